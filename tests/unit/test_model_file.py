"""zros.sim.model_file: a robot's drive and lidar from its SDF or URDF, without processes."""
from __future__ import annotations

import pytest

from zros.sim import BURGER, LDS_01, WAFFLE
from zros.sim.model_file import robot_from_xml
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
    assert plain.warning == "model 'statue' has no libgazebo_ros_diff_drive.so plugin: simulating a TurtleBot3 burger"


def test_bad_numbers_are_one_line_errors() -> None:
    with pytest.raises(SdfError, match=r"^<robot XML>:1: <wheel_separation> needs 1 finite numbers, got 'wide'$"):
        robot_from_xml('<robot name="r"><gazebo><plugin filename="libgazebo_ros_diff_drive.so">'
                       '<wheel_separation>wide</wheel_separation></plugin></gazebo></robot>', fallback='burger')
