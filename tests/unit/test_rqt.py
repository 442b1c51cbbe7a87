"""rqt's tools without a browser: plot paths and their errors, the plot's decimation and CSV,
request forms and their type checks and the rqt commands' arguments. `zros run rqt_plot rqt_plot`
serving the page: tests/integration/test_rqt_commands.py; the pages in a real browser:
tests/integration/test_rqt_browser.py."""
from __future__ import annotations

import numpy as np
import pytest

from zros.view.scene.fields import FieldError, check_field, field_value, fill_request, form_fields, \
    message_tree_html, numeric_fields, parse_field, split_plot_path
from zros.view.scene.plot import PlotBuffer


def test_plot_paths_name_a_topic_and_a_field():
    topics = ['/turtle1/pose', '/turtle1/cmd_vel', '/odom', '/scan']
    assert split_plot_path('/turtle1/pose/x', topics) == ('/turtle1/pose', ['x'])
    assert split_plot_path('turtle1/pose/theta', topics) == ('/turtle1/pose', ['theta'])
    assert split_plot_path('/odom/twist/twist/linear/x', topics) == ('/odom', ['twist', 'twist', 'linear', 'x'])
    assert split_plot_path('/scan/ranges[3]', topics) == ('/scan', ['ranges', 3])
    assert parse_field('poses/2/position.x') == ['poses', 2, 'position', 'x']
    with pytest.raises(FieldError, match='no topic of the graph'):
        split_plot_path('/turtle2/pose/x', topics)


def test_fields_are_checked_against_the_message_definition():
    from interfaces.geometry_msgs.msg import PoseArray
    from interfaces.nav_msgs.msg import Odometry
    from interfaces.sensor_msgs.msg import LaserScan
    from interfaces.turtlesim.msg import Pose
    assert check_field(Pose, ['x']) == 'float32'
    assert check_field(Odometry, parse_field('twist/twist/linear/x')) == 'float64'
    assert check_field(LaserScan, ['ranges', 0]) == 'float32'
    assert check_field(PoseArray, parse_field('poses[1]/orientation/w')) == 'float64'
    for msg_type, path, message in [
            (Pose, 'q', "has no field 'q' (its fields: x, y, theta"),
            (Pose, '', 'name a field of turtlesim/msg/Pose to plot, e.g. x'),
            (LaserScan, 'ranges', 'ranges is an array: add an index, e.g. ranges[0]'),
            (LaserScan, 'header/frame_id', 'only numbers can be plotted'),
            (Odometry, 'pose', 'only numbers can be plotted'),
            (Pose, 'x[1]', 'applies to an array only')]:
        with pytest.raises(FieldError, match=message.replace('[', r'\[').replace('(', r'\(')):
            check_field(msg_type, parse_field(path))


def test_field_values_and_the_picker():
    from interfaces.nav_msgs.msg import Odometry
    from interfaces.sensor_msgs.msg import LaserScan
    scan = LaserScan(ranges=[1.5, 2.5])
    assert field_value(scan, ['ranges', 1]) == 2.5
    with pytest.raises(FieldError, match='beyond the 2 elements'):
        field_value(scan, ['ranges', 5])
    paths = numeric_fields(Odometry)
    assert 'pose/pose/position/x' in paths and 'twist/twist/angular/z' in paths and 'pose/covariance[0]' in paths
    assert all(check_field(Odometry, parse_field(p)) for p in paths)


def test_plot_buffer_decimates_to_a_shared_axis_and_exports_every_sample():
    buffer = PlotBuffer()
    for i in range(2000):                               # 50 Hz for 40 s
        buffer.add('/a/x', i * 0.02, np.sin(i * 0.02))
    for i in range(5):                                   # another topic, 1 Hz, from t = 30 s
        buffer.add('/b/y', 30.0 + i, float(i))
    x, a, b = buffer.window(['/a/x', '/b/y'], 10.0, 40.0, points=300)
    assert x.size == a.size == b.size == 300
    assert np.all(np.diff(x) > 0) and x[0] >= 10.0 and x[-1] <= 40.0
    assert np.abs(a - np.sin(x)).max() < 0.05            # bin means follow the curve
    assert np.isfinite(b).all() and b[-1] == 4.0 and b[0] == 0.0
    x, a = buffer.window(['/a/x'], 39.0, 40.0, points=300)   # few samples: exactly those
    assert x.size == 50 and np.allclose(a, np.sin(x))
    rows = [line.split(',') for line in buffer.to_csv(['/a/x', '/b/y']).splitlines()]
    assert rows[0] == ['time', '/a/x', '/b/y']
    assert sum(1 for row in rows[1:] if row[1]) == 2000 and sum(1 for row in rows[1:] if row[2]) == 5
    assert float(rows[-1][0]) == pytest.approx(39.98) and float(rows[-1][1]) == pytest.approx(np.sin(39.98))


def test_request_forms_show_defaults_and_check_types_before_sending():
    from interfaces.rcl_interfaces.srv import SetParameters
    from interfaces.std_msgs.msg import Header, Int8
    from interfaces.turtlesim.srv import Spawn
    fields = form_fields(Spawn.Request)
    assert [(f.path, f.kind, f.default, f.type_text) for f in fields] == [
        ('x', 'float', 0.0, 'float32'), ('y', 'float', 0.0, 'float32'), ('theta', 'float', 0.0, 'float32'),
        ('name', 'text', '', 'string')]
    request = fill_request(Spawn.Request, {'x': 2, 'y': 3.5, 'name': 'bob'})
    assert (request.x, request.y, request.name) == (2.0, 3.5, 'bob')
    assert [f.path for f in form_fields(Header)] == ['stamp/sec', 'stamp/nanosec', 'frame_id']
    assert fill_request(Header, {'stamp/sec': 7, 'frame_id': 'map'}).stamp.sec == 7
    assert [f.kind for f in form_fields(SetParameters.Request)] == ['yaml']
    with pytest.raises(FieldError, match=r'data: 300 is outside int8 \(-128\.\.127\)'):
        fill_request(Int8, {'data': 300})
    with pytest.raises(FieldError, match='data: int8 needs a whole number, got 1.5'):
        fill_request(Int8, {'data': 1.5})
    with pytest.raises(FieldError, match='parameters: not a YAML list'):
        fill_request(SetParameters.Request, {'parameters': '[{name: a'})
    with pytest.raises(FieldError, match='needs a list'):
        fill_request(SetParameters.Request, {'parameters': 'five'})


def test_message_tree_html():
    from zros.convert import message_to_ordereddict
    from interfaces.sensor_msgs.msg import LaserScan
    from interfaces.std_msgs.msg import Header
    text = message_tree_html(message_to_ordereddict(LaserScan(ranges=list(range(20)), header=Header(frame_id='<b>'))))
    assert '<details open><summary>' in text and 'frame_id' in text and '&#x27;&lt;b&gt;&#x27;' in text
    assert '(20)' in text and '…' in text                 # long arrays are cut, with their length


def test_rqt_commands_arguments():
    from zros.view.scene.node import RQT_PAGES, expand_plot_fields, parse_rqt_args
    assert expand_plot_fields(['/turtle1/pose/x:y', '/odom/twist/twist/linear/x']) == [
        '/turtle1/pose/x', '/turtle1/pose/y', '/odom/twist/twist/linear/x']
    assert parse_rqt_args('rqt_plot', ['/turtle1/pose/x', '--port', '0']).fields == ['/turtle1/pose/x']
    assert RQT_PAGES['rqt_graph'] == 'Graph' and RQT_PAGES['rqt_reconfigure'] == 'Parameters'
