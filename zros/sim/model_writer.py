"""A TurtleBot3 written as Gazebo's model.sdf and as a URDF, from zros's numbers for it.

    text = model_sdf(turtlebot3_model('burger'))       # models/turtlebot3_burger/model.sdf
    text = model_urdf(BURGER)                         # urdf/turtlebot3_burger.urdf

Students' launch files open turtlebot3_gazebo's `models/turtlebot3_<model>/model.sdf` (to spawn
the robot) and `urdf/turtlebot3_<model>.urdf` (for robot_state_publisher); zros ships both,
written from one source (zros.sim.robot's RobotSpec and zros.sim.model_file's plugin options,
ROBOTIS's numbers) by tools/write_turtlebot3_gazebo.py, so the file a student reads, the robot
zros simulates and the frames robot_state_publisher publishes cannot disagree. The SDF has
ROBOTIS's links, joints, sensors and plugins (diff drive, ray sensor, IMU, joint state
publisher) with their elements; shapes are primitives (the body is the disc zros collides with),
no meshes. zros.sim.model_file reads the SDF back to the same RobotModel.
"""
from __future__ import annotations

from xml.sax.saxutils import escape

from zros.sim.model_file import RobotModel
from zros.sim.robot import RobotSpec

__all__ = ['model_sdf', 'model_urdf', 'model_config', 'BODY_HEIGHT']

BODY_HEIGHT = 0.14          # [m] of the body cylinder, from base_link up
_WHEEL_WIDTH = 0.018
_WHEEL_ROLL = -1.57         # ROBOTIS's wheel and caster joint roll: the axle along base_link's y
_OPTICAL = (-1.57, 0.0, -1.57)   # camera frame (x forward) -> optical frame (z forward), as ROBOTIS writes it
#: The camera's fixed frames in ROBOTIS's turtlebot3_gazebo URDFs, (joint, parent, child, xyz, rpy):
#: the waffle's RealSense R200 and the waffle_pi's Raspberry Pi camera. The simulator has no
#: camera; the frames are here so that a user's TF tree (and RViz's camera frames) match upstream's.
_CAMERA_FRAMES: dict[str, tuple[tuple[str, str, str, tuple[float, float, float], tuple[float, float, float]], ...]] = {
    'waffle': (
        ('camera_joint', 'base_link', 'camera_link', (0.064, -0.065, 0.094), (0, 0, 0)),
        ('camera_rgb_joint', 'camera_link', 'camera_rgb_frame', (0.005, 0.018, 0.013), (0, 0, 0)),
        ('camera_rgb_optical_joint', 'camera_rgb_frame', 'camera_rgb_optical_frame', (0, 0, 0), _OPTICAL),
        ('camera_depth_joint', 'camera_link', 'camera_depth_frame', (0.005, 0.028, 0.013), (0, 0, 0)),
        ('camera_depth_optical_joint', 'camera_depth_frame', 'camera_depth_optical_frame', (0, 0, 0), _OPTICAL)),
    'waffle_pi': (
        ('camera_joint', 'base_link', 'camera_link', (0.073, -0.011, 0.084), (0, 0, 0)),
        ('camera_rgb_joint', 'camera_link', 'camera_rgb_frame', (0.003, 0.011, 0.009), (0, 0, 0)),
        ('camera_rgb_optical_joint', 'camera_rgb_frame', 'camera_rgb_optical_frame', (0, 0, 0), _OPTICAL)),
}


def _n(*values: float) -> str:
    return ' '.join(f'{float(v):g}' for v in values)


def _casters(spec: RobotSpec) -> list[tuple[str, tuple[float, float, float]]]:
    if len(spec.caster_mounts) == 1:
        return [('caster_back_link', spec.caster_mounts[0])]
    return [(f'caster_back_{side}_link', mount) for side, mount in zip(('right', 'left'), spec.caster_mounts)]


def model_config(model: str, description: str) -> str:
    """Gazebo's model.config for `models/turtlebot3_<model>/`."""
    return ('<?xml version="1.0"?>\n<model>\n'
            f'  <name>turtlebot3_{escape(model)}</name>\n  <version>1.0</version>\n'
            '  <sdf version="1.6">model.sdf</sdf>\n'
            f'  <description>{escape(description)}</description>\n</model>\n')


def model_sdf(model: RobotModel, *, note: str = '') -> str:
    """SDF 1.6 text of a TurtleBot3 model whose plugins and sensors say what `model` says."""
    spec, lidar, drive = model.spec, model.lidar, model.drive
    base_z = spec.base_height
    lx, ly, lz = spec.lidar_mount
    ix, iy, iz = spec.imu_mount
    links = ['<link name="base_footprint"/>',
             f'<link name="base_link"><pose>{_n(0, 0, base_z, 0, 0, 0)}</pose>'
             f'<inertial><mass>{_n(spec.mass)}</mass></inertial>'
             f'<collision name="body"><pose>{_n(0, 0, BODY_HEIGHT / 2, 0, 0, 0)}</pose><geometry><cylinder>'
             f'<radius>{_n(spec.body_radius)}</radius><length>{_n(BODY_HEIGHT)}</length></cylinder></geometry>'
             '</collision></link>']
    imu_sensor = ''
    if model.imu is not None and model.imu_output is not None:
        gyro = ''.join(f'<{a}><noise type="gaussian"><mean>0.0</mean><stddev>{_n(model.imu.gyro_noise_stddev)}'
                       f'</stddev></noise></{a}>' for a in 'xyz')
        accel = ''.join(f'<{a}><noise type="gaussian"><mean>0.0</mean><stddev>{_n(model.imu.accel_noise_stddev)}'
                        f'</stddev></noise></{a}>' for a in 'xyz')
        imu_sensor = (f'<sensor name="tb3_imu" type="imu"><always_on>true</always_on>'
                      f'<update_rate>{_n(model.imu.rate)}</update_rate><imu><angular_velocity>{gyro}'
                      f'</angular_velocity><linear_acceleration>{accel}</linear_acceleration></imu>'
                      f'<plugin name="turtlebot3_imu" filename="libgazebo_ros_imu_sensor.so"><ros>'
                      f'<remapping>~/out:={escape(model.imu_output.topic)}</remapping></ros>'
                      f'<frame_name>{escape(model.imu_output.frame)}</frame_name></plugin></sensor>')
    links.append(f'<link name="imu_link"><pose>{_n(ix, iy, base_z + iz, 0, 0, 0)}</pose>{imu_sensor}</link>')
    ray = ''
    if model.scan is not None:
        ray = (f'<sensor name="hls_lfcd_lds" type="ray"><always_on>true</always_on><visualize>true</visualize>'
               f'<update_rate>{_n(lidar.rate)}</update_rate><ray><scan><horizontal>'
               f'<samples>{lidar.samples}</samples><resolution>1.0</resolution>'
               f'<min_angle>{_n(lidar.angle_min)}</min_angle><max_angle>{_n(lidar.angle_max)}</max_angle>'
               f'</horizontal></scan><range><min>{_n(lidar.range_min)}</min><max>{_n(lidar.range_max)}</max>'
               f'<resolution>0.015</resolution></range><noise><type>gaussian</type><mean>0.0</mean>'
               f'<stddev>{_n(lidar.noise_stddev)}</stddev></noise></ray>'
               f'<plugin name="turtlebot3_laserscan" filename="libgazebo_ros_ray_sensor.so"><ros>'
               f'<remapping>~/out:={escape(model.scan.topic)}</remapping></ros>'
               f'<output_type>sensor_msgs/LaserScan</output_type><frame_name>{escape(model.scan.frame)}</frame_name>'
               '</plugin></sensor>')
    links.append(f'<link name="base_scan"><pose>{_n(lx, ly, base_z + lz, 0, 0, 0)}</pose>'
                 f'<collision name="lidar"><geometry><cylinder><radius>{_n(spec.lidar_housing_radius)}</radius>'
                 f'<length>0.0315</length></cylinder></geometry></collision>{ray}</link>')
    joints = ['<joint name="base_joint" type="fixed"><parent>base_footprint</parent><child>base_link</child></joint>',
              '<joint name="imu_joint" type="fixed"><parent>base_link</parent><child>imu_link</child></joint>',
              '<joint name="lidar_joint" type="fixed"><parent>base_link</parent><child>base_scan</child></joint>']
    for side, (x, y, z) in zip(('left', 'right'), spec.wheel_mounts):
        links.append(f'<link name="wheel_{side}_link"><pose>{_n(x, y, base_z + z, _WHEEL_ROLL, 0, 0)}</pose>'
                     f'<collision name="wheel_{side}"><geometry><cylinder><radius>{_n(spec.wheel_radius)}</radius>'
                     f'<length>{_n(_WHEEL_WIDTH)}</length></cylinder></geometry></collision></link>')
        joints.append(f'<joint name="wheel_{side}_joint" type="revolute"><parent>base_link</parent>'
                      f'<child>wheel_{side}_link</child><axis><xyz>0 0 1</xyz></axis></joint>')
    for name, (x, y, z) in _casters(spec):
        links.append(f'<link name="{name}"><pose>{_n(x, y, base_z + z, _WHEEL_ROLL, 0, 0)}</pose></link>')
        joints.append(f'<joint name="{name.removesuffix("_link")}_joint" type="ball"><parent>base_link</parent>'
                      f'<child>{name}</child></joint>')
    flag = lambda value: 'true' if value else 'false'  # noqa: E731
    plugins = [
        '<plugin name="turtlebot3_diff_drive" filename="libgazebo_ros_diff_drive.so">'
        f'<ros><remapping>cmd_vel:={escape(drive.cmd_vel_topic)}</remapping>'
        f'<remapping>odom:={escape(drive.odom_topic)}</remapping></ros>'
        f'<update_rate>{_n(drive.update_rate)}</update_rate>'
        '<left_joint>wheel_left_joint</left_joint><right_joint>wheel_right_joint</right_joint>'
        f'<wheel_separation>{_n(spec.wheel_separation)}</wheel_separation>'
        f'<wheel_diameter>{_n(2 * spec.wheel_radius)}</wheel_diameter>'
        f'<max_wheel_torque>20</max_wheel_torque><max_wheel_acceleration>{_n(spec.max_wheel_acceleration)}'
        '</max_wheel_acceleration>'
        f'<odometry_source>{1 if drive.odometry_source == "world" else 0}</odometry_source>'
        f'<publish_odom>{flag(drive.publish_odom)}</publish_odom>'
        f'<publish_odom_tf>{flag(drive.publish_odom_tf)}</publish_odom_tf>'
        f'<publish_wheel_tf>{flag(drive.publish_wheel_tf)}</publish_wheel_tf>'
        f'<odometry_frame>{escape(drive.odometry_frame)}</odometry_frame>'
        f'<robot_base_frame>{escape(drive.robot_base_frame)}</robot_base_frame></plugin>']
    if model.joint_states is not None:
        names = ''.join(f'<joint_name>{escape(j)}</joint_name>' for j in model.joint_states.joints)
        plugins.append('<plugin name="turtlebot3_joint_state" filename="libgazebo_ros_joint_state_publisher.so">'
                       f'<ros><remapping>~/out:={escape(model.joint_states.topic)}</remapping></ros>'
                       f'<update_rate>{_n(model.joint_states.rate)}</update_rate>{names}</plugin>')
    comment = f'<!-- {escape(note)} -->\n' if note else ''
    body = '\n'.join(links + joints + plugins)
    return (f'<?xml version="1.0"?>\n{comment}<sdf version="1.6">\n<model name="turtlebot3_{spec.model}">\n'
            f'<pose>0 0 0 0 0 0</pose>\n{body}\n</model>\n</sdf>\n')


def model_urdf(spec: RobotSpec, *, note: str = '') -> str:
    """A URDF of the TurtleBot3's links and joints (what robot_state_publisher needs), with
    primitive shapes; its fixed frames are the ones zros's simulator uses."""
    def joint(name: str, kind: str, parent: str, child: str, xyz: tuple[float, ...], rpy: tuple[float, ...],
              extra: str = '') -> str:
        return (f'  <joint name="{name}" type="{kind}">\n    <parent link="{parent}"/>\n    <child link="{child}"/>\n'
                f'    <origin xyz="{_n(*xyz)}" rpy="{_n(*rpy)}"/>{extra}\n  </joint>\n')

    def cylinder_link(name: str, radius: float, length: float, z: float = 0.0) -> str:
        geometry = f'<geometry><cylinder radius="{_n(radius)}" length="{_n(length)}"/></geometry>'
        origin = f'<origin xyz="{_n(0, 0, z)}" rpy="0 0 0"/>'
        return (f'  <link name="{name}">\n    <visual>{origin}{geometry}</visual>\n'
                f'    <collision>{origin}{geometry}</collision>\n  </link>\n')
    parts = ['<link name="base_footprint"/>\n',
             joint('base_joint', 'fixed', 'base_footprint', 'base_link', (0, 0, spec.base_height), (0, 0, 0)),
             cylinder_link('base_link', spec.body_radius, BODY_HEIGHT, BODY_HEIGHT / 2)]
    for side, mount in zip(('left', 'right'), spec.wheel_mounts):
        parts += [joint(f'wheel_{side}_joint', 'continuous', 'base_link', f'wheel_{side}_link', mount,
                        (_WHEEL_ROLL, 0, 0), '\n    <axis xyz="0 0 1"/>'),
                  cylinder_link(f'wheel_{side}_link', spec.wheel_radius, _WHEEL_WIDTH)]
    for name, mount in _casters(spec):
        parts += [joint(name.removesuffix('_link') + '_joint', 'fixed', 'base_link', name, mount, (_WHEEL_ROLL, 0, 0)),
                  f'  <link name="{name}"/>\n']
    parts += [joint('imu_joint', 'fixed', 'base_link', 'imu_link', spec.imu_mount, (0, 0, 0)),
              '  <link name="imu_link"/>\n',
              joint('scan_joint', 'fixed', 'base_link', 'base_scan', spec.lidar_mount, (0, 0, 0)),
              cylinder_link('base_scan', spec.lidar_housing_radius, 0.0315)]
    for name, parent, child, xyz, rpy in _CAMERA_FRAMES.get(spec.model, ()):
        parts += [joint(name, 'fixed', parent, child, xyz, rpy), f'  <link name="{child}"/>\n']
    comment = f'<!-- {escape(note)} -->\n' if note else ''
    return f'<?xml version="1.0"?>\n{comment}<robot name="turtlebot3_{spec.model}">\n  ' + '  '.join(
        p if not p.startswith('  ') else p[2:] for p in parts) + '</robot>\n'
