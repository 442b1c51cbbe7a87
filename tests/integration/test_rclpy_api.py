"""rclpy's smaller API surface that real programs import: zros.Parameter at top level, the
logging severity path and logger services, AsyncParameterClient, sensor_msgs_py.point_cloud2 and
cv_bridge (numpy only)."""
from __future__ import annotations

import textwrap
import time

import numpy as np
import pytest

import zros
from zros.cv_bridge import CvBridge, CvBridgeError
from zros.executors import SingleThreadedExecutor
from zros.node import Node
from zros.parameter_client import AsyncParameterClient
from zros.sensor_msgs_py import point_cloud2 as pc2


def test_parameter_at_top_level_infers_types():
    from zros.impl.logging_severity import LoggingSeverity
    assert zros.Parameter.Type.DOUBLE == 3
    assert zros.Parameter('speed', value=2.0).type_ == zros.Parameter.Type.DOUBLE
    assert zros.Parameter('names', value=['a', 'b']).type_ == zros.Parameter.Type.STRING_ARRAY
    assert zros.Parameter('n', zros.Parameter.Type.DOUBLE, 3).value == 3.0
    assert LoggingSeverity.DEBUG == 10 and LoggingSeverity is zros.logging.LoggingSeverity


def test_parameter_dict_from_yaml_file(tmp_path):
    from zros.parameter import ParameterFileError, parameter_dict_from_yaml_file
    path = tmp_path / 'params.yaml'
    path.write_text('/**:\n  ros__parameters:\n    rate: 1.0\n    shared: x\n'
                    'arm:\n  ros__parameters:\n    rate: 5.0\n    joint: {limit: 2}\n'
                    'base:\n  ros__parameters:\n    wheels: 4\n')
    every = parameter_dict_from_yaml_file(str(path))
    assert list(every) == ['rate', 'joint.limit', 'wheels'] and every['joint.limit'].value.integer_value == 2
    wild = parameter_dict_from_yaml_file(str(path), use_wildcard=True, target_nodes=['/arm'], namespace='ns.')
    assert list(wild) == ['ns.rate', 'ns.shared', 'ns.joint.limit']
    assert wild['ns.rate'].value.double_value == 5.0, "the node's own entry overrides /**"
    with pytest.raises(ParameterFileError, match='no parameters for node'):
        parameter_dict_from_yaml_file(str(path), target_nodes=['gripper'])


def test_set_parameters_with_top_level_parameter(context):
    node = Node('param_api', context=context)
    node.declare_parameter('speed', 1.0)
    node.add_on_set_parameters_callback(
        lambda params: _result(all(p.value <= 5.0 for p in params if p.name == 'speed')))
    assert node.set_parameters([zros.Parameter('speed', value=2.0)])[0].successful
    assert node.get_parameter('speed').value == 2.0
    assert not node.set_parameters([zros.Parameter('speed', value=10.0)])[0].successful


def _result(ok):
    from interfaces.rcl_interfaces.msg import SetParametersResult
    return SetParametersResult(successful=ok)


LOGGER_NODE = textwrap.dedent('''
    import zros
    from zros.node import Node

    zros.init()
    node = Node('chatty', enable_logger_service=True)
    node.create_timer(0.05, lambda: node.get_logger().debug('debug line'))
    node.get_logger().info('ready')
    try:
        zros.spin(node)
    except (KeyboardInterrupt, zros.executors.ExternalShutdownException):
        pass
''')


def test_logger_service_changes_a_running_nodes_level(spawn, zros_cli):
    child = spawn.script(LOGGER_NODE, name='chatty')
    child.wait_for_output('ready', timeout=15)
    assert 'debug line' not in child.output()
    got = zros_cli('service', 'call', '/chatty/get_logger_levels', 'rcl_interfaces/srv/GetLoggerLevels',
                   '{names: [chatty]}')
    assert got.returncode == 0 and 'level=0)' in got.stdout, got
    bad = zros_cli('service', 'call', '/chatty/set_logger_levels', 'rcl_interfaces/srv/SetLoggerLevels',
                   '{levels: [{name: chatty, level: 7}]}')
    assert 'successful=False' in bad.stdout and 'Invalid logger level' in bad.stdout, bad
    ok = zros_cli('service', 'call', '/chatty/set_logger_levels', 'rcl_interfaces/srv/SetLoggerLevels',
                  '{levels: [{name: chatty, level: 10}]}')
    assert 'successful=True' in ok.stdout, ok
    child.wait_for_output('[DEBUG]', timeout=10)
    got = zros_cli('service', 'call', '/chatty/get_logger_levels', 'rcl_interfaces/srv/GetLoggerLevels',
                   '{names: [chatty]}')
    assert 'level=10)' in got.stdout, got


def test_async_parameter_client_against_a_node_process(spawn, context, tmp_path):
    spawn.node('demo_nodes', 'param_talker')
    node = Node('param_client', context=context)
    executor = SingleThreadedExecutor(context=context)
    executor.add_node(node)
    client = AsyncParameterClient(node, 'param_talker')
    assert client.wait_for_services(timeout_sec=15) and client.services_are_ready()

    def done(future):
        executor.spin_until_future_complete(future, timeout_sec=10)
        assert future.done(), 'no answer from the parameter service'
        return future.result()

    names = done(client.list_parameters()).result.names
    assert {'published_text', 'timer_period', 'use_sim_time'} <= set(names)
    seen = []
    set_future = client.set_parameters([zros.Parameter('published_text', value='BME')], callback=seen.append)
    assert done(set_future).results[0].successful
    deadline = time.monotonic() + 10   # the done-callback runs on the executor, maybe after other work
    while not seen and time.monotonic() < deadline:
        executor.spin_once(timeout_sec=0.1)
    assert seen == [set_future]
    assert done(client.get_parameters(['published_text'])).values[0].string_value == 'BME'
    assert list(done(client.get_parameter_types(['timer_period'])).types) == [zros.Parameter.Type.DOUBLE]
    assert 'Seconds' in done(client.describe_parameters(['timer_period'])).descriptors[0].description
    refused = done(client.set_parameters_atomically([zros.Parameter('timer_period', value=99.0)]))
    assert not refused.result.successful
    assert done(client.set_parameters([zros.Parameter('extra', value=7)])).results[0].successful
    assert done(client.delete_parameters(['extra'])).results[0].successful
    params = tmp_path / 'params.yaml'
    params.write_text('param_talker:\n  ros__parameters:\n    published_text: from file\n'
                      '/**:\n  ros__parameters:\n    timer_period: 2.0\n')
    assert len(done(client.load_parameter_file(str(params))).results) == 1
    assert len(done(client.load_parameter_file(str(params), use_wildcard=True)).results) == 2
    values = done(client.get_parameters(['published_text', 'timer_period'])).values
    assert values[0].string_value == 'from file' and values[1].double_value == 2.0
    executor.shutdown()


# -- point_cloud2 -------------------------------------------------------------------------------
def _wire(msg):
    from zros.message import deserialize, serialize
    return deserialize(serialize(msg), type(msg))


def test_point_cloud_round_trip_and_reads():
    from interfaces.sensor_msgs.msg import PointField
    from interfaces.std_msgs.msg import Header
    xyz = np.array([[1, 2, 3], [np.nan, 0, 0], [4, 5, 6]], dtype=np.float32)
    cloud = _wire(pc2.create_cloud_xyz32(Header(frame_id='lidar'), xyz))
    assert (cloud.width, cloud.height, cloud.point_step, cloud.row_step) == (3, 1, 12, 36)
    assert [tuple(p) for p in pc2.read_points(cloud, field_names=('x', 'y', 'z'), skip_nans=True)] == \
        [(1.0, 2.0, 3.0), (4.0, 5.0, 6.0)]
    assert pc2.read_points_numpy(cloud, skip_nans=True).tolist() == [[1, 2, 3], [4, 5, 6]]
    assert pc2.read_points_list(cloud, field_names=['z'])[2].z == 6.0
    assert pc2.read_points(cloud, uvs=[2, 0])['x'].tolist() == [4.0, 1.0]
    mixed = [PointField(name='x', offset=0, datatype=PointField.FLOAT32, count=1),
             PointField(name='ring', offset=4, datatype=PointField.UINT16, count=1),
             PointField(name='rgb', offset=8, datatype=PointField.UINT8, count=3)]
    cloud = _wire(pc2.create_cloud(Header(), mixed, [(1.5, 7, 1, 2, 3), (2.5, 9, 4, 5, 6)], point_step=12))
    points = pc2.read_points(cloud)
    assert points.dtype.names == ('x', 'ring', 'rgb_0', 'rgb_1', 'rgb_2') and points.dtype.itemsize == 12
    assert points['ring'].tolist() == [7, 9] and points['rgb_2'].tolist() == [3, 6]
    with pytest.raises(ValueError, match='one datatype'):
        pc2.read_points_numpy(cloud)
    with pytest.raises(ValueError, match="no field 'q'"):
        pc2.read_points(cloud, field_names=['q'])
    structured = pc2.read_points(cloud)
    assert pc2.read_points(pc2.create_cloud(Header(), mixed, structured, point_step=12))['x'].tolist() == [1.5, 2.5]


def test_big_endian_cloud_reads_right():
    from interfaces.sensor_msgs.msg import PointCloud2, PointField
    values = np.array([1.25, -2.0], dtype='>f4')
    cloud = PointCloud2(height=1, width=2, point_step=4, row_step=8, is_bigendian=True, is_dense=True,
                        fields=[PointField(name='x', offset=0, datatype=PointField.FLOAT32, count=1)],
                        data=values.tobytes())
    assert pc2.read_points_numpy(cloud)[:, 0].tolist() == [1.25, -2.0]


# -- cv_bridge ----------------------------------------------------------------------------------
def test_cv_bridge_images_and_conversions():
    bridge = CvBridge()
    rng = np.random.default_rng(3)
    bgr = rng.integers(0, 256, (4, 5, 3), dtype=np.uint8)
    msg = _wire(bridge.cv2_to_imgmsg(bgr, 'bgr8'))
    assert (msg.encoding, msg.height, msg.width, msg.step) == ('bgr8', 4, 5, 15)
    assert (bridge.imgmsg_to_cv2(msg) == bgr).all()
    assert (bridge.imgmsg_to_cv2(msg, 'rgb8') == bgr[..., ::-1]).all()
    grey = bridge.imgmsg_to_cv2(msg, 'mono8')
    expected = np.rint(0.114 * bgr[..., 0] + 0.587 * bgr[..., 1] + 0.299 * bgr[..., 2])
    assert grey.shape == (4, 5) and np.abs(grey - expected).max() <= 1
    rgba = bridge.imgmsg_to_cv2(msg, 'rgba8')
    assert (rgba[..., 3] == 255).all() and (rgba[..., :3] == bgr[..., ::-1]).all()
    assert bridge.imgmsg_to_cv2(bridge.cv2_to_imgmsg(grey, 'mono8'), 'mono16').max() == int(grey.max()) * 257
    depth = rng.random((3, 4)).astype(np.float32)
    depth_msg = bridge.cv2_to_imgmsg(depth)
    assert depth_msg.encoding == '32FC1' and (bridge.imgmsg_to_cv2(_wire(depth_msg)) == depth).all()
    with pytest.raises(CvBridgeError, match='incompatible type 32FC1'):
        bridge.cv2_to_imgmsg(depth, 'mono8')
    with pytest.raises(CvBridgeError, match='not a supported conversion'):
        bridge.imgmsg_to_cv2(depth_msg, 'bgr8')
    with pytest.raises(TypeError):
        bridge.cv2_to_imgmsg([[1, 2]])


def test_cv_bridge_padded_and_big_endian_rows():
    from interfaces.sensor_msgs.msg import Image
    rows = np.array([[1, 2, 0, 0], [3, 4, 0, 0]], dtype='>u2')  # width 2, step 8 bytes
    msg = Image(height=2, width=2, encoding='mono16', is_bigendian=1, step=8, data=rows.tobytes())
    assert CvBridge().imgmsg_to_cv2(msg).tolist() == [[1, 2], [3, 4]]


def test_cv_bridge_compressed_png_without_opencv():
    bridge = CvBridge()
    bgra = np.random.default_rng(5).integers(0, 256, (6, 7, 4), dtype=np.uint8)
    compressed = _wire(bridge.cv2_to_compressed_imgmsg(bgra, dst_format='png'))
    assert compressed.format == 'png' and bytes(compressed.data[:4]) == b'\x89PNG'
    assert (bridge.compressed_imgmsg_to_cv2(compressed) == bgra).all()
    assert (bridge.compressed_imgmsg_to_cv2(compressed, 'rgb8') == bgra[..., 2::-1]).all()
    try:
        import cv2  # noqa: F401
    except ImportError:
        with pytest.raises(CvBridgeError, match='need OpenCV'):
            bridge.cv2_to_compressed_imgmsg(bgra)
