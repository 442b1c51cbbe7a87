"""nav2_waypoint_follower's follow_gps_waypoints (Nav2 Jazzy) as a process: BasicNavigator's
followGpsWaypoints sends GPS poses, the follower turns each into a map pose with
robot_localization's /fromLL and drives to them with navigate_to_pose; here the test process
plays navsat_transform_node (/fromLL, a flat-earth conversion around a datum) and bt_navigator
(a navigate_to_pose that records each goal and refuses the ones far away)."""
from __future__ import annotations

import math

from conftest import activate

DATUM = (45.0, 9.0)                 # latitude, longitude of the map origin [deg]
M_PER_DEG_LAT = 111_132.0

NAVIGATOR = f'''
import zros
from zros.nav2_simple_commander.robot_navigator import BasicNavigator
from interfaces.geographic_msgs.msg import GeoPose

zros.init()
nav = BasicNavigator()


def geopose(lat, lon):
    pose = GeoPose()
    pose.position.latitude, pose.position.longitude = lat, lon
    pose.orientation.w = 1.0
    return pose


# 1 m north, 2 m east, then 10 km north (refused by navigate_to_pose), then back to the datum.
nav.followGpsWaypoints([geopose({DATUM[0]} + 1 / {M_PER_DEG_LAT}, {DATUM[1]}),
                        geopose({DATUM[0]}, {DATUM[1]} + 2 / ({M_PER_DEG_LAT} * 0.70711)),
                        geopose({DATUM[0]} + 0.09, {DATUM[1]}),
                        geopose({DATUM[0]}, {DATUM[1]})])
while not nav.isTaskComplete():
    pass
result = nav.result_future.result().result
print('result:', nav.getResult().name, [(m.index, m.error_code) for m in result.missed_waypoints], flush=True)
'''


def test_gps_waypoints_go_through_from_ll_then_navigate_to_pose(spawn, probe, tmp_path):
    from zros.action import ActionServer
    from interfaces.nav2_msgs.action import NavigateToPose
    from interfaces.robot_localization.srv import FromLL
    params = tmp_path / 'params.yaml'
    params.write_text('waypoint_follower:\n  ros__parameters:\n    stop_on_failure: false\n'
                      '    global_frame_id: map\n')

    def from_ll(request, response):
        lat, lon = request.ll_point.latitude, request.ll_point.longitude
        response.map_point.x = (lon - DATUM[1]) * M_PER_DEG_LAT * math.cos(math.radians(DATUM[0]))
        response.map_point.y = (lat - DATUM[0]) * M_PER_DEG_LAT
        return response
    probe.create_service(FromLL, '/fromLL', from_ll)
    goals: list = []

    def navigate(handle):
        goals.append(handle.request.pose)
        if handle.request.pose.pose.position.y > 100.0:
            handle.abort()
        else:
            handle.succeed()
        return NavigateToPose.Result()
    ActionServer(probe, NavigateToPose, 'navigate_to_pose', navigate)
    follower = spawn.node('nav2_waypoint_follower', 'waypoint_follower', '--ros-args', '--params-file', str(params))
    activate(probe, 'waypoint_follower', follower)
    script = spawn.script(NAVIGATOR, name='navigator')
    assert script.wait(60) == 0, script.output() + follower.output()
    assert 'result: SUCCEEDED [(2, 601)]' in script.output(), script.output() + follower.output()
    assert [g.header.frame_id for g in goals] == ['map'] * 4
    points = [(round(g.pose.position.x, 2), round(g.pose.position.y, 2)) for g in goals]
    assert points[0] == (0.0, 1.0) and points[1] == (2.0, 0.0) and points[3] == (0.0, 0.0), points
    assert 'Converted all 4 GPS waypoint to map frame' in follower.output()


def test_without_from_ll_a_gps_goal_fails_before_the_robot_moves(spawn, probe, tmp_path):
    from zros.action import ActionServer
    from interfaces.nav2_msgs.action import NavigateToPose
    goals: list = []
    ActionServer(probe, NavigateToPose, 'navigate_to_pose', lambda handle: goals.append(handle) or handle.succeed()
                 or NavigateToPose.Result())
    follower = spawn.node('nav2_waypoint_follower', 'waypoint_follower')       # stop_on_failure: true
    activate(probe, 'waypoint_follower', follower)
    script = spawn.script(NAVIGATOR, name='navigator')
    assert script.wait(60) == 0, script.output() + follower.output()
    assert 'result: FAILED' in script.output(), script.output()
    assert 'is navsat_transform_node running?' in follower.output()
    assert goals == []
