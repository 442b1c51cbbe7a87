"""opennav_docking's docking_server as a process, on a simulated TurtleBot3 in turtlebot3_world:
BasicNavigator's Jazzy calls dock the robot by pose and by dock id (the robot starts at the
staging pose), undock it, and fail with Nav2's error codes; far from the staging pose it asks
navigate_to_pose (here a stand-in that refuses) to go there first."""
from __future__ import annotations

from conftest import activate

START = (-2.0, -0.5)                # turtlebot3_world's spawn pose, where odom has the robot at the start

# Nav2 Jazzy's docking_server section (nav2_bringup/params/nav2_params.yaml), with one dock of
# this test's: 0.7 m ahead of where the robot starts, in odom (the simulator gives no map frame;
# its odom is Gazebo's, the world frame, and the robot starts at (-2.0, -0.5) facing +x).
PARAMS = """\
docking_server:
  ros__parameters:
    controller_frequency: 50.0
    initial_perception_timeout: 5.0
    wait_charge_timeout: 5.0
    dock_approach_timeout: 30.0
    undock_linear_tolerance: 0.05
    undock_angular_tolerance: 0.1
    max_retries: 3
    base_frame: "base_link"
    fixed_frame: "odom"
    dock_backwards: false
    dock_prestaging_tolerance: 0.5
    dock_plugins: ['simple_charging_dock']
    simple_charging_dock:
      plugin: 'opennav_docking::SimpleChargingDock'
      docking_threshold: 0.05
      staging_x_offset: -0.7
      use_external_detection_pose: true
      use_battery_status: false
      use_stall_detection: false
      external_detection_timeout: 1.0
      external_detection_translation_x: -0.18
      external_detection_translation_y: 0.0
      external_detection_rotation_roll: -1.57
      external_detection_rotation_pitch: -1.57
      external_detection_rotation_yaw: 0.0
      filter_coef: 0.1
    docks: ['home_dock']
    home_dock:
      type: 'simple_charging_dock'
      frame: odom
      pose: [-1.3, -0.5, 0.0]
    controller:
      k_phi: 3.0
      k_delta: 2.0
      v_linear_min: 0.15
      v_linear_max: 0.15
      use_collision_detection: true
      costmap_topic: "local_costmap/costmap_raw"
      footprint_topic: "local_costmap/published_footprint"
      transform_tolerance: 0.1
      projection_time: 5.0
      simulation_step: 0.1
      dock_collision_threshold: 0.3
"""

NAVIGATOR = '''
import math
import zros
from zros.nav2_simple_commander.robot_navigator import BasicNavigator, TaskResult
from interfaces.geometry_msgs.msg import PoseStamped
from interfaces.nav_msgs.msg import Odometry

zros.init()
nav = BasicNavigator()
odom = {}
nav.create_subscription(Odometry, 'odom', lambda m: odom.update(x=m.pose.pose.position.x, y=m.pose.pose.position.y), 10)
states = []


def finish(what):
    while not nav.isTaskComplete():
        fb = nav.getFeedback()
        if fb is not None and hasattr(fb, 'state') and (not states or states[-1] != fb.state):
            states.append(fb.state)
    for _ in range(5):
        zros.spin_once(nav, timeout_sec=0.1)
    result = nav.result_future.result().result
    print(f'{what}: {nav.getResult().name} {result.error_code} x={odom["x"]:.3f} y={odom["y"]:.3f}', flush=True)


dock = PoseStamped()
dock.header.frame_id = 'odom'
dock.pose.position.x, dock.pose.position.y, dock.pose.orientation.w = -1.3, -0.5, 1.0
nav.dockRobotByPose(dock, '', nav_to_dock=True)
finish('by pose')
print('states:', states, flush=True)
nav.dockRobotByPose(dock)
finish('again')
nav.undockRobot()
finish('undock')
nav.undockRobot()
finish('undock twice')
nav.dockRobotByID('home_dock', nav_to_dock=False)
finish('by id')
nav.dockRobotByID('nowhere')
finish('unknown id')
nav.dockRobotByPose(dock, 'no_such_type')
finish('unknown type')
nav.undockRobot('simple_charging_dock')
finish('undock by type')
far = PoseStamped()
far.header.frame_id = 'odom'
far.pose.position.x, far.pose.position.y, far.pose.orientation.w = -0.5, -0.5, 1.0
nav.dockRobotByPose(far)
finish('navigate first')
'''


def test_dock_and_undock_a_simulated_turtlebot3(spawn, probe, tmp_path):
    from interfaces.nav2_msgs.action import DockRobot, UndockRobot
    params = tmp_path / 'nav2_params.yaml'
    params.write_text(PARAMS)
    spawn.node('turtlebot3_gazebo', 'gzserver', '--ros-args', '-p', 'world:=turtlebot3_world')
    server = spawn.node('opennav_docking', 'opennav_docking', '--ros-args', '-r', '__node:=docking_server',
                        '--params-file', str(params))
    activate(probe, 'docking_server', server)
    # bt_navigator's part: a navigate_to_pose server that records the staging goal and fails it.
    from zros.action import ActionServer
    from interfaces.nav2_msgs.action import NavigateToPose
    staging_goals: list = []

    def refuse(handle):
        staging_goals.append(handle.request.pose)
        handle.abort()
        return NavigateToPose.Result()
    ActionServer(probe, NavigateToPose, 'navigate_to_pose', refuse)
    script = spawn.script(NAVIGATOR, name='navigator')
    assert script.wait(150) == 0, script.output() + server.output()
    lines = {line.split(':', 1)[0]: line.split(':', 1)[1].split() for line in script.output().splitlines()
             if ':' in line and not line.startswith('[')}

    def x_of(key: str) -> float:        # from where the robot started (odom is the world frame)
        return float(lines[key][2].split('=')[1]) - START[0]

    def y_of(key: str) -> float:
        return float(lines[key][3].split('=')[1]) - START[1]

    assert lines['by pose'][:2] == ['SUCCEEDED', '0'], script.output() + server.output()
    assert abs(x_of('by pose') - 0.7) < 0.06 and abs(y_of('by pose')) < 0.06
    # The feedback the navigator sampled while the controller drove the robot on.
    assert str(DockRobot.Feedback.CONTROLLING) in ''.join(lines['states']).strip('[]').split(',')
    assert 'Robot already within pre-staging pose tolerance' in server.output()
    assert lines['again'][:2] == ['SUCCEEDED', '0']                    # already docked
    assert 'already docked' in server.output()
    assert lines['undock'][:2] == ['SUCCEEDED', '0']
    assert abs(x_of('undock')) < 0.08 and abs(y_of('undock')) < 0.08   # back on the staging pose
    assert lines['undock twice'][0] == 'FAILED'                        # not in the dock any more
    assert lines['by id'][:2] == ['SUCCEEDED', '0'] and abs(x_of('by id') - 0.7) < 0.06
    assert lines['unknown id'][:2] == ['FAILED', str(DockRobot.Result.DOCK_NOT_IN_DB)]
    assert lines['unknown type'][:2] == ['FAILED', str(DockRobot.Result.DOCK_NOT_VALID)]
    assert lines['undock by type'][:2] == ['SUCCEEDED', str(UndockRobot.Result.NONE)]
    # Far from the staging pose: the navigator is asked to go there; its failure is FAILED_TO_STAGE.
    assert lines['navigate first'][:2] == ['FAILED', str(DockRobot.Result.FAILED_TO_STAGE)]
    assert len(staging_goals) == 1 and staging_goals[0].header.frame_id == 'odom'
    assert abs(staging_goals[0].pose.position.x - (START[0] + 0.8)) < 1e-6
