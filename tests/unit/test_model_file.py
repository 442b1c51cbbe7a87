"""zros.sim.model_file: a robot's drive, odometry options, sensors and outputs from its SDF or URDF."""
from __future__ import annotations

import pytest

from zros.sim import BURGER, LDS_01, WAFFLE
from zros.sim.model_file import (TURTLEBOT3_DRIVE, TURTLEBOT3_IMU_OUTPUT, TURTLEBOT3_JOINT_STATES, TURTLEBOT3_SCAN,
                                 DiffDrivePlugin, JointStateOutput, SensorOutput, robot_from_xml, turtlebot3_model)
from zros.sim.sdf import SdfError

SDF = '''<sdf version="1.6"><model name="my_bot"><link name="base_scan">
<sensor name="lidar" type="ray"><update_rate>10</update_rate><ray><scan><horizontal><samples>180</samples>
<min_angle>-1.57</min_angle><max_angle>1.57</max_angle></horizontal></scan><range><min>0.2</min><max>8.0</max></range>
<noise><type>gaussian</type><stddev>0.02</stddev></noise></ray></sensor></link>
<plugin name="dd" filename="libgazebo_ros_diff_drive.so"><wheel_separation>0.30</wheel_separation>
<wheel_diameter>0.10</wheel_diameter><max_wheel_acceleration>2.0</max_wheel_acceleration></plugin></model></sdf>'''

URDF = '''<robot name="my_urdf_bot"><link name="base_link"/>
<gazebo><plugin name="dd" filename="libgazebo_ros_diff_drive.so"><wheel_separation>0.4</wheel_separation>
<wheel_diameter>0.2</wheel_diameter></plugin></gazebo></robot>'''


def test_an_sdf_models_diff_drive_and_ray_sensor_become_its_spec_and_lidar() -> None:
    robot = robot_from_xml(SDF, fallback='waffle')
    assert robot.warning == ''
    assert (robot.spec.wheel_separation, robot.spec.wheel_radius, robot.spec.max_wheel_acceleration) == (0.30, 0.05, 2.0)
    assert robot.spec.body_radius == WAFFLE.body_radius            # the rest is the fallback TurtleBot3's
    lidar = robot.lidar
    assert (lidar.samples, lidar.angle_min, lidar.angle_max, lidar.range_min, lidar.range_max) == (180, -1.57, 1.57, 0.2, 8.0)
    assert (lidar.noise_stddev, lidar.rate) == (0.02, 10.0)


def test_a_urdf_with_gazebo_tags_and_the_fallbacks() -> None:
    robot = robot_from_xml(URDF, fallback='burger')
    assert (robot.spec.wheel_separation, robot.spec.wheel_radius) == (0.4, 0.1) and robot.lidar == LDS_01
    plain = robot_from_xml('<robot name="statue"><link name="base_link"/></robot>', fallback='burger')
    assert plain.spec == BURGER
    assert plain.warning == ("model 'statue' has no diff-drive plugin (libgazebo_ros_diff_drive.so or "
                             'gz-sim-diff-drive-system): simulating a TurtleBot3 burger')


def test_bad_numbers_are_one_line_errors() -> None:
    with pytest.raises(SdfError, match=r"^<robot XML>:1: <wheel_separation> needs 1 finite numbers, got 'wide'$"):
        robot_from_xml('<robot name="r"><gazebo><plugin filename="libgazebo_ros_diff_drive.so">'
                       '<wheel_separation>wide</wheel_separation></plugin></gazebo></robot>', fallback='burger')


TB3_LIKE = '''<sdf version="1.6"><model name="tb">
<link name="imu_link"><sensor name="imu" type="imu"><update_rate>50</update_rate><imu>
<angular_velocity><z><noise type="gaussian"><stddev>0.001</stddev></noise></z></angular_velocity>
<linear_acceleration><x><noise type="gaussian"><stddev>0.05</stddev></noise></x></linear_acceleration></imu>
<plugin name="my_imu" filename="libgazebo_ros_imu_sensor.so"><ros><remapping>~/out:=imu/data</remapping></ros></plugin>
</sensor></link>
<link name="laser"><sensor name="lds" type="ray"><update_rate>7</update_rate>
<plugin name="my_laser" filename="libgazebo_ros_ray_sensor.so"><frame_name>laser_frame</frame_name></plugin></sensor></link>
<plugin name="dd" filename="libgazebo_ros_diff_drive.so"><ros><remapping>cmd_vel:=base/cmd</remapping>
<remapping>odom:=wheel_odom</remapping></ros><update_rate>20</update_rate><odometry_source>0</odometry_source>
<publish_odom>true</publish_odom><publish_wheel_tf>1</publish_wheel_tf><odometry_frame>odom_w</odometry_frame>
<robot_base_frame>base_link</robot_base_frame></plugin>
<plugin name="js" filename="libgazebo_ros_joint_state_publisher.so"><update_rate>10</update_rate>
<joint_name>wheel_right_joint</joint_name></plugin></model></sdf>'''


def test_the_diff_drive_plugins_odometry_options_and_gazebos_defaults() -> None:
    drive = robot_from_xml(TB3_LIKE, fallback='burger').drive
    assert drive == DiffDrivePlugin(odometry_source='encoder', publish_odom=True, publish_odom_tf=False,
                                    publish_wheel_tf=True, odometry_frame='odom_w', robot_base_frame='base_link',
                                    update_rate=20.0, cmd_vel_topic='base/cmd', odom_topic='wheel_odom')
    # Absent elements take the plugin's defaults: WORLD odometry, nothing published, 100 Hz.
    assert robot_from_xml(SDF, fallback='burger').drive == DiffDrivePlugin()
    assert DiffDrivePlugin().odometry_source == 'world' and not DiffDrivePlugin().publish_odom


def test_sensors_and_the_joint_state_publisher_say_topic_frame_and_rate() -> None:
    robot = robot_from_xml(TB3_LIKE, fallback='burger')
    assert robot.scan == SensorOutput('my_laser/out', 'laser_frame', 7.0)       # no remapping: ~/out
    assert robot.lidar.rate == 7.0
    assert robot.imu_output == SensorOutput('imu/data', 'imu_link', 50.0)       # frame: the sensor's link
    assert (robot.imu.rate, robot.imu.gyro_noise_stddev, robot.imu.accel_noise_stddev) == (50.0, 0.001, 0.05)
    assert robot.joint_states == JointStateOutput('joint_states', 10.0, ('wheel_right_joint',))
    bare = robot_from_xml(SDF, fallback='burger')            # a ray sensor without a plugin, no IMU
    assert bare.imu is None and bare.imu_output is None and bare.joint_states is None
    assert bare.scan is not None and bare.scan.frame == 'base_scan'


def test_a_model_without_a_diff_drive_is_robotis_turtlebot3() -> None:
    plain = robot_from_xml('<robot name="statue"/>', fallback='waffle')
    assert plain.drive == TURTLEBOT3_DRIVE and plain.drive.odometry_source == 'world'
    assert (plain.scan, plain.imu_output, plain.joint_states) == (TURTLEBOT3_SCAN, TURTLEBOT3_IMU_OUTPUT,
                                                                 TURTLEBOT3_JOINT_STATES)
    assert turtlebot3_model('burger')._replace(warning=plain.warning) == plain._replace(spec=BURGER)


def test_bad_plugin_options_are_one_line_errors() -> None:
    plugin = '<robot name="r"><gazebo><plugin filename="libgazebo_ros_diff_drive.so">{}</plugin></gazebo></robot>'
    with pytest.raises(SdfError, match=r"^<robot XML>:1: odometry_source must be 'world' \(1\) or 'encoder' \(0\)"):
        robot_from_xml(plugin.format('<odometry_source>2</odometry_source>'), fallback='burger')
    with pytest.raises(SdfError, match=r"^<robot XML>:1: <publish_odom> must be true or false, got 'yes'$"):
        robot_from_xml(plugin.format('<publish_odom>yes</publish_odom>'), fallback='burger')
    with pytest.raises(SdfError, match=r'^<robot XML>:1: update_rate must be >= 0, got -1$'):
        robot_from_xml(plugin.format('<update_rate>-1</update_rate>'), fallback='burger')


# A Gazebo Sim (Harmonic) model in the shape of nav2_minimal_tb3_sim's gz_waffle.sdf: its systems
# and sensors name their topics and frames.
GZ_SDF = '''<sdf version="1.6"><model name="gz_bot"><link name="base_footprint"/><link name="base_scan">
<sensor name="front_lidar" type="gpu_lidar"><update_rate>10</update_rate><topic>/ns/scan</topic>
<gz_frame_id>laser</gz_frame_id><lidar><scan><horizontal><samples>720</samples><resolution>1</resolution>
<min_angle>0</min_angle><max_angle>6.28</max_angle></horizontal></scan><range><min>0.05</min><max>20.0</max>
</range><noise><type>gaussian</type><mean>0</mean><stddev>0.03</stddev></noise></lidar></sensor></link>
<link name="imu_link"><sensor name="my_imu" type="imu"><topic>ns/imu</topic><gz_frame_id>imu_link</gz_frame_id>
</sensor></link>
<plugin filename="gz-sim-diff-drive-system" name="gz::sim::systems::DiffDrive">
<wheel_separation>0.287</wheel_separation><wheel_radius>0.033</wheel_radius>
<max_linear_acceleration>1.5</max_linear_acceleration><max_linear_velocity>0.46</max_linear_velocity>
<max_angular_velocity>1.9</max_angular_velocity><topic>ns/cmd_vel</topic><odom_topic>ns/odom</odom_topic>
<tf_topic>ns/tf</tf_topic><frame_id>odom</frame_id><child_frame_id>base_footprint</child_frame_id>
<odom_publish_frequency>30</odom_publish_frequency></plugin>
<plugin filename="gz-sim-joint-state-publisher-system" name="gz::sim::systems::JointStatePublisher">
<topic>ns/joint_states</topic></plugin></model></sdf>'''


def test_gz_sim_diff_drive_and_gpu_lidar_set_the_numbers_topics_and_frames() -> None:
    robot = robot_from_xml(GZ_SDF, fallback='waffle')
    assert robot.warning == ''
    spec = robot.spec
    assert (spec.wheel_separation, spec.wheel_radius, spec.max_wheel_acceleration) == (0.287, 0.033, 1.5)
    assert (spec.max_linear, spec.max_angular) == (0.46, 1.9)
    lidar = robot.lidar
    assert (lidar.samples, lidar.range_min, lidar.range_max, lidar.noise_stddev, lidar.rate) == (720, 0.05, 20.0, 0.03,
                                                                                                10.0)
    topics = robot.topics
    assert (topics.cmd_vel, topics.odom, topics.tf, topics.joint_states, topics.scan, topics.imu) == (
        '/ns/cmd_vel', '/ns/odom', '/ns/tf', '/ns/joint_states', '/ns/scan', '/ns/imu')   # relative -> absolute
    assert (topics.odom_frame, topics.base_frame, topics.scan_frame, topics.imu_frame) == (
        'odom', 'base_footprint', 'laser', 'imu_link')
    assert topics.namespace == 'ns'
    # Its outputs: the same names and frames, at its systems' and sensors' rates; Gazebo Sim's
    # DiffDrive always publishes odometry and TF, integrated from the wheels (encoder).
    assert robot.drive == DiffDrivePlugin(odometry_source='encoder', publish_odom=True, publish_odom_tf=True,
                                          odometry_frame='odom', robot_base_frame='base_footprint', update_rate=30.0,
                                          cmd_vel_topic='/ns/cmd_vel', odom_topic='/ns/odom')
    assert robot.scan == SensorOutput('/ns/scan', 'laser', 10.0)
    assert robot.imu_output is not None and robot.imu_output.topic == '/ns/imu'
    assert robot.joint_states == JointStateOutput('/ns/joint_states', 200.0, ('wheel_left_joint', 'wheel_right_joint'))


def test_gz_sim_defaults_are_gazebos_scoped_names() -> None:
    xml = ('<sdf version="1.9"><model name="bot"><link name="chassis"><sensor name="l" type="lidar"/></link>'
           '<plugin filename="libgz-sim8-diff-drive-system.so" name="gz::sim::systems::DiffDrive"/></model></sdf>')
    topics = robot_from_xml(xml, fallback='burger', world='shapes').topics
    assert (topics.cmd_vel, topics.odom, topics.tf) == ('/model/bot/cmd_vel', '/model/bot/odometry', '/model/bot/tf')
    assert topics.scan == '/world/shapes/model/bot/link/chassis/sensor/l/scan'
    assert topics.joint_states == '/world/shapes/model/bot/joint_state'
    assert (topics.odom_frame, topics.base_frame, topics.scan_frame) == ('bot/odom', 'bot/chassis', 'bot::chassis::l')


def test_a_classic_model_has_no_gz_topics_and_bad_gz_numbers_are_one_line() -> None:
    assert robot_from_xml(SDF, fallback='burger').topics is None
    with pytest.raises(SdfError, match=r'^<robot XML>:1: wheel_separation, wheel_radius, .* must be > 0$'):
        robot_from_xml('<sdf version="1.9"><model name="m"><plugin filename="gz-sim-diff-drive-system" name="d">'
                       '<wheel_radius>0</wheel_radius></plugin></model></sdf>', fallback='burger')
