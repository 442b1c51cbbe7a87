"""The scene view's Python half, without a browser: message -> scene conversion, the tools'
messages, .rviz and view files, the graph drawing (layout, rqt_graph's hides) and the console filter."""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from zros.view.scene import config as view_config
from zros.view.scene import convert, tools
from zros.view.scene.console import LogBuffer, to_html
from zros.view.scene.geometry import Transform, quat_from_yaw, yaw_of
from zros.view.scene.graph_hides import Hides, apply_hides
from zros.view.scene.graph_layout import layered_layout
from zros.view.scene.graph_svg import layout, to_svg

#: `zros graph --json --include-hidden --include-debug` of turtlebot3_world + navigation2.launch.py,
#: plus the Nav2 nodes zros does not start (velocity_smoother, smoother_server, collision_monitor)
#: and rviz2 with its usual topics: a Nav2-sized graph (17 nodes, 61 topics, 165 edges).
NAV2_GRAPH = Path(__file__).parents[1] / 'data' / 'nav2_graph.json'


# -- geometry ---------------------------------------------------------------------------------
def test_transform_composition_and_inverse():
    a = Transform(np.array([1.0, 2.0, 0.0]), quat_from_yaw(math.pi / 2))
    b = Transform(np.array([0.5, 0.0, 0.1]), quat_from_yaw(0.3))
    p = np.array([[1.0, 0.0, 0.0], [0.0, 2.0, 1.0]])
    assert np.allclose((a @ b).apply(p), a.apply(b.apply(p)))
    assert np.allclose(a.inverse().apply(a.apply(p)), p)
    assert a.apply(np.array([[1.0, 0.0, 0.0]]))[0] == pytest.approx([1.0, 3.0, 0.0])
    assert yaw_of((a @ b).rotation) == pytest.approx(math.pi / 2 + 0.3)


# -- maps ---------------------------------------------------------------------------------------
def test_map_and_costmap_colour_schemes():
    data = np.array([0, 100, -1, 50, 99, 1], dtype=np.int8)
    rgba = convert.occupancy_rgba(data, 3, 2, 'map')
    assert rgba.shape == (2, 3, 4)
    assert tuple(rgba[0, 0]) == (255, 255, 255, 255)           # free: white
    assert tuple(rgba[0, 1]) == (0, 0, 0, 255)                 # occupied: black
    assert tuple(rgba[0, 2, :3]) == convert.UNKNOWN_RGB        # unknown: grey-green
    assert rgba[1, 0, 0] == 128                                # 50 %: mid grey (row 1 = the grid's row 1)
    cost = convert.occupancy_rgba(data, 3, 2, 'costmap', alpha=0.5)
    assert cost[0, 0, 3] == 0                                  # free space is see-through
    assert tuple(cost[0, 1, :3]) == (255, 0, 255)              # lethal: magenta
    assert tuple(cost[1, 1, :3]) == (0, 255, 255)              # inscribed: cyan
    assert cost[1, 2, 2] > cost[1, 2, 0]                       # low cost: blue
    assert cost[0, 1, 3] == 127                                # alpha scales opacity
    with pytest.raises(ValueError, match='expected 3 x 3'):
        convert.occupancy_rgba(data, 3, 3)
    with pytest.raises(ValueError, match="unknown colour scheme 'jet'"):
        convert.occupancy_rgba(data, 3, 2, 'jet')


def test_the_map_display_pastes_costmap_updates_into_its_last_grid():
    """RViz's Map display: `<topic>_updates` patches the last whole grid; an update before any
    grid, or one that does not fit it, is dropped."""
    import threading
    from types import SimpleNamespace

    from zros.view.scene.displays.maps import MapDisplay

    from interfaces.map_msgs.msg import OccupancyGridUpdate
    from interfaces.nav_msgs.msg import OccupancyGrid
    scene = SimpleNamespace(add_frame=lambda name, **_: SimpleNamespace(name=name))
    display = MapDisplay(SimpleNamespace(scene=scene, wake=threading.Event()), 'Costmap', '/global_costmap/costmap')
    update = OccupancyGridUpdate(x=1, y=2, width=2, height=1, data=np.array([100, 99], np.int8))
    display.on_update(update)
    assert display._latest is None                             # nothing to paste into yet
    grid = OccupancyGrid()
    grid.info.width, grid.info.height = 4, 3
    grid.data = np.zeros(12, np.int8)
    display.on_message(grid)
    display.on_update(update)
    shown = np.asarray(display._latest.data).reshape(3, 4)
    assert shown[2].tolist() == [0, 100, 99, 0] and not shown[:2].any()
    assert not np.asarray(grid.data).any()                     # the message drawn before is not changed under it
    display.on_update(OccupancyGridUpdate(x=0, y=0, width=1, height=1, data=np.array([5], np.int8)))
    assert np.asarray(display._latest.data).reshape(3, 4)[[0, 2], [0, 1]].tolist() == [5, 100]   # on top of the last
    before = display._latest
    display.on_update(OccupancyGridUpdate(x=3, y=0, width=2, height=1, data=np.array([1, 1], np.int8)))
    assert display._latest is before                           # outside the grid: dropped


def test_known_window_and_cropped_placement():
    from interfaces.nav_msgs.msg import MapMetaData
    cells = np.full((10, 12), -1, dtype=np.int8)
    cells[3:5, 6:9] = 0
    assert convert.known_window(cells, 2) == (1, 7, 4, 11)
    assert convert.known_window(cells, 20) == (0, 10, 0, 12)
    assert convert.known_window(np.full((3, 3), -1), 1) is None
    info = MapMetaData(width=12, height=10, resolution=0.5)
    centre, width, height = convert.grid_placement(info, (1, 7, 4, 11))
    assert (width, height) == (3.5, 3.0)
    assert centre.translation == pytest.approx([7.5 * 0.5, 4.0 * 0.5, 0.0])


def test_grid_placement_centres_the_image_on_the_rotated_origin():
    from interfaces.nav_msgs.msg import MapMetaData
    info = MapMetaData(width=40, height=20, resolution=0.05)
    info.origin.position.x, info.origin.position.y = -1.0, 2.0
    info.origin.orientation.z, info.origin.orientation.w = math.sin(math.pi / 4), math.cos(math.pi / 4)
    centre, width, height = convert.grid_placement(info)
    assert (width, height) == pytest.approx((2.0, 1.0))
    # half the extent (1.0, 0.5) along the origin's axes, which are turned by 90 degrees
    assert centre.translation == pytest.approx([-1.0 - 0.5, 2.0 + 1.0, 0.0])
    assert yaw_of(centre.rotation) == pytest.approx(math.pi / 2)


# -- sensors ------------------------------------------------------------------------------------
def test_scan_points_keep_only_valid_beams():
    ranges = np.array([1.0, np.inf, 0.05, 2.0, np.nan, 5.0], dtype=np.float32)
    points = convert.scan_points(ranges, 0.0, math.pi / 2, 0.1, 3.5)
    assert points.shape == (2, 3) and points.dtype == np.float32
    assert points[0] == pytest.approx([1.0, 0.0, 0.0])
    assert points[1] == pytest.approx([0.0, -2.0, 0.0], abs=1e-5)     # beam 3, at 270 degrees


def test_scan_points_angles():
    points = convert.scan_points([1.0, 1.0, 1.0, 1.0], -math.pi / 2, math.pi / 2, 0.1, 3.5)
    assert points[:, :2] == pytest.approx(np.array([[0, -1], [1, 0], [0, 1], [-1, 0]]), abs=1e-6)


def test_pointcloud2_xyz_and_rgb():
    from interfaces.sensor_msgs.msg import PointCloud2, PointField
    records = np.zeros(3, dtype=[('x', '<f4'), ('y', '<f4'), ('z', '<f4'), ('pad', '<f4'), ('rgb', '<u4')])
    records['x'], records['y'], records['z'] = [1, 2, np.nan], [0, 1, 0], [0.5, 0.5, 0.5]
    records['rgb'] = [0xFF0000, 0x00FF00, 0x0000FF]
    fields = [PointField(name=n, offset=o, datatype=7, count=1) for n, o in (('x', 0), ('y', 4), ('z', 8))]
    fields.append(PointField(name='rgb', offset=16, datatype=6, count=1))
    cloud = PointCloud2(height=1, width=3, fields=fields, point_step=20, row_step=60,
                        data=np.frombuffer(records.tobytes(), dtype=np.uint8))
    xyz, colors = convert.pointcloud2_points(cloud)
    assert xyz.tolist() == [[1.0, 0.0, 0.5], [2.0, 1.0, 0.5]]           # the NaN point is dropped
    assert colors.tolist() == [[255, 0, 0], [0, 255, 0]]
    with pytest.raises(ValueError, match='no x, y, z fields'):
        convert.pointcloud2_points(PointCloud2(fields=fields[1:], width=1, height=1, point_step=20))


# -- poses ------------------------------------------------------------------------------------------
def test_pose_arrows_and_flat_arrow_mesh():
    positions = np.array([[0.0, 0.0, 0.0], [1.0, 1.0, 0.0]])
    rotations = np.stack([quat_from_yaw(0.0), quat_from_yaw(math.pi / 2)])
    arrows = convert.pose_arrows(positions, rotations, 0.5)
    assert arrows.shape == (2, 2, 3)
    assert arrows[1, 1] == pytest.approx([1.0, 1.5, 0.0])
    vertices, faces = convert.flat_arrow_mesh(0.5)
    assert vertices[:, 0].max() == pytest.approx(0.5) and vertices[:, 0].min() == 0.0
    assert faces.max() < len(vertices) and (vertices[:, 2] == 0).all()


def test_poses_array_from_pose_array_message():
    from interfaces.geometry_msgs.msg import Pose
    poses = [Pose() for _ in range(3)]
    for i, pose in enumerate(poses):
        pose.position.x = float(i)
        pose.orientation.w = 1.0
    positions, rotations = convert.poses_array(poses)
    assert positions[:, 0].tolist() == [0.0, 1.0, 2.0] and rotations[:, 3].tolist() == [1.0, 1.0, 1.0]


def test_covariance_ellipse_axes():
    covariance = np.zeros(36)
    covariance[0], covariance[7] = 0.25, 0.04          # sigma x 0.5 m, sigma y 0.2 m
    outline = convert.covariance_ellipse(covariance, segments=64)
    assert np.abs(outline[:, 0]).max() == pytest.approx(0.5, rel=1e-3)
    assert np.abs(outline[:, 1]).max() == pytest.approx(0.2, rel=1e-3)


def test_polyline_segments():
    points = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0]], dtype=float)
    assert convert.polyline_segments(points).shape == (2, 2, 3)
    assert convert.polyline_segments(points, closed=True)[-1].tolist() == [[1, 1, 0], [0, 0, 0]]
    assert convert.polyline_segments(points[:1]).shape == (0, 2, 3)


def test_marker_shapes():
    from interfaces.geometry_msgs.msg import Point
    from interfaces.visualization_msgs.msg import Marker
    marker = Marker(type=Marker.LINE_STRIP, points=[Point(x=0.0), Point(x=1.0), Point(x=1.0, y=1.0)])
    marker.color.r, marker.color.a = 1.0, 0.5
    marker.scale.x = 0.05
    shape = convert.marker_shape(marker)
    assert shape.kind == 'line_strip' and shape.rgb == (255, 0, 0) and shape.alpha == 0.5
    assert shape.points.shape == (3, 3) and shape.colors is None
    arrow = Marker(type=Marker.ARROW)
    arrow.scale.x = 2.0
    arrow.pose.orientation.z, arrow.pose.orientation.w = math.sin(math.pi / 4), math.cos(math.pi / 4)
    points = convert.arrow_marker_points(convert.marker_shape(arrow))
    assert points[0, 1] == pytest.approx([0.0, 2.0, 0.0], abs=1e-6)
    with pytest.raises(ValueError, match='unknown marker type 42'):
        convert.marker_shape(Marker(type=42))


# -- tools ------------------------------------------------------------------------------------------
def test_ground_point_and_drag_pose():
    assert tools.ground_point((1.0, 2.0, 10.0), (0.0, 0.0, -1.0)) == pytest.approx([1.0, 2.0, 0.0])
    assert tools.ground_point((0.0, 0.0, 1.0), (1.0, 0.0, -1.0)) == pytest.approx([1.0, 0.0, 0.0])
    assert tools.ground_point((0.0, 0.0, 1.0), (1.0, 0.0, 0.0)) is None      # parallel
    assert tools.ground_point((0.0, 0.0, 1.0), (0.0, 0.0, 1.0)) is None      # looking up
    pose = tools.drag_pose((1.0, 1.0), (1.0, 3.0))
    assert pose == pytest.approx((1.0, 1.0, math.pi / 2))
    assert tools.drag_pose((1.0, 1.0), (1.0, 1.0)).yaw == 0.0


def test_initial_pose_has_rviz_default_covariance():
    pose = tools.PlanarPose(1.5, -0.5, math.pi)
    msg = tools.initial_pose(pose, 'map')
    assert msg.header.frame_id == 'map'
    assert (msg.pose.pose.position.x, msg.pose.pose.position.y) == (1.5, -0.5)
    assert yaw_of(np.array([msg.pose.pose.orientation.x, msg.pose.pose.orientation.y, msg.pose.pose.orientation.z,
                            msg.pose.pose.orientation.w])) == pytest.approx(math.pi)
    covariance = np.asarray(msg.pose.covariance).reshape(6, 6)
    assert covariance[0, 0] == 0.25 and covariance[1, 1] == 0.25
    assert covariance[5, 5] == pytest.approx(0.06853891945200942)
    assert np.count_nonzero(covariance) == 3
    goal = tools.goal_pose(pose, 'odom')
    assert goal.header.frame_id == 'odom' and goal.pose.orientation.z == pytest.approx(1.0)
    point = tools.clicked_point(np.array([1.0, 2.0, 0.0]), 'map')
    assert (point.point.x, point.point.y) == (1.0, 2.0)


def test_teleop_twist():
    twist = tools.teleop_twist('forward-left', 0.2, 1.0)
    assert (twist.linear.x, twist.angular.z) == (0.2, 1.0)
    assert tools.teleop_twist('stop', 0.2, 1.0).linear.x == 0.0
    with pytest.raises(ValueError, match="unknown teleop direction 'up'"):
        tools.teleop_twist('up', 0.2, 1.0)


# -- .rviz and view files ----------------------------------------------------------------------
RVIZ = """\
Panels:
  - Class: rviz_common/Displays
Visualization Manager:
  Class: ""
  Displays:
    - Class: rviz_default_plugins/Grid
      Cell Size: 0.5
      Color: 100; 110; 120
      Enabled: true
      Plane Cell Count: 20
    - Class: rviz_default_plugins/RobotModel
      Description Topic:
        Value: /robot_description
      Enabled: true
      Name: RobotModel
    - Class: rviz_default_plugins/TF
      Show Names: false
    - Class: rviz_common/Group
      Displays:
        - Class: rviz_default_plugins/Map
          Name: Global Costmap
          Topic:
            Value: /global_costmap/costmap
          Color Scheme: costmap
          Alpha: 0.3
        - Class: nav2_rviz_plugins/ParticleCloud
          Topic:
            Value: /particle_cloud
          Color: 0; 180; 0
    - Class: rviz_default_plugins/LaserScan
      Topic:
        Value: /scan
      Size (m): 0.05
    - Class: rviz_default_plugins/Polygon
      Name: Footprint
    - Class: rviz_default_plugins/Polygon
      Name: Footprint 2
    - Class: rviz_default_plugins/MarkerArray
      Topic:
        Value: /explore/frontiers
    - Class: rviz_default_plugins/Image
      Topic:
        Value: /camera/image
      Enabled: false
  Global Options:
    Fixed Frame: odom
  Views:
    Current:
      Class: rviz_default_plugins/Orbit
      Distance: 2.0
      Focal Point: {X: -0.1, Y: 0.25, Z: 0.3}
      Pitch: 0.5
      Yaw: -0.623
"""


def test_rviz_file(tmp_path):
    path = tmp_path / 'config.rviz'
    path.write_text(RVIZ)
    config = view_config.load_config(path)
    assert config.fixed_frame == 'odom'
    assert (config.grid.enabled, config.grid.cell_size, config.grid.cells, config.grid.color) == \
        (True, 0.5, 20, (100, 110, 120))
    kinds = [(d.kind, d.topic, d.msg_type) for d in config.displays]
    assert kinds == [('RobotModel', '/robot_description', 'std_msgs/msg/String'), ('TF', '', ''),
                     ('Map', '/global_costmap/costmap', 'nav_msgs/msg/OccupancyGrid'),
                     ('PoseArray', '/particle_cloud', 'nav2_msgs/msg/ParticleCloud'),
                     ('LaserScan', '/scan', 'sensor_msgs/msg/LaserScan'),
                     ('Marker', '/explore/frontiers', 'visualization_msgs/msg/MarkerArray'),
                     ('Image', '/camera/image', 'sensor_msgs/msg/Image')]
    by_topic = {d.topic: d for d in config.displays}
    assert by_topic['/global_costmap/costmap'].options == {'color_scheme': 'costmap', 'alpha': 0.3}
    assert by_topic['/particle_cloud'].options == {'color': (0, 180, 0)}
    assert by_topic['/scan'].options == {'size': 0.05}
    assert by_topic['/camera/image'].enabled is False
    assert config.displays[1].options == {'show_names': False}
    assert config.unknown == ['rviz_default_plugins/Polygon']                 # listed once
    assert config.camera['distance'] == 2.0 and config.camera['focal_y'] == 0.25


def test_view_file_round_trip(tmp_path):
    path = tmp_path / 'config.rviz'
    path.write_text(RVIZ)
    config = view_config.load_config(path)
    saved = tmp_path / 'saved.view.yaml'
    saved.write_text(view_config.dump_view(config))
    again = view_config.load_config(saved)
    assert again.fixed_frame == config.fixed_frame and again.grid == config.grid
    assert [(d.kind, d.name, d.topic, d.msg_type, d.enabled, d.options) for d in again.displays] == \
        [(d.kind, d.name, d.topic, d.msg_type, d.enabled, d.options) for d in config.displays]


@pytest.mark.parametrize('text, message', [
    ('a: [', 'is not valid YAML'),
    ('just text', 'neither an RViz config nor a zros view file'),
    ('other: 1', 'neither an RViz config'),
    ('zros_view: 1\ndisplays:\n- {topic: /x}\n', 'display 1 has no class'),
])
def test_bad_config_files(tmp_path, text, message):
    path = tmp_path / 'bad.rviz'
    path.write_text(text)
    with pytest.raises(view_config.ConfigError, match=message):
        view_config.load_config(path)
    with pytest.raises(view_config.ConfigError, match='cannot read'):
        view_config.load_config(tmp_path / 'missing.rviz')


# -- graph and console ---------------------------------------------------------------------------
def _nav2_graph() -> dict:
    content = json.loads(NAV2_GRAPH.read_text())
    content['edges'] = [tuple(edge) for edge in content['edges']]
    return content


def _assert_readable(placed, edges) -> int:
    """No two boxes overlap; every edge's route runs from its src box to its dst box, left to
    right (or, reversed to break a cycle, right to left all the way). Returns the reversed count."""
    boxes = np.array([(b.x, b.y, b.x + b.width, b.y + b.height) for b in placed.boxes.values()])
    apart = ((boxes[:, None, 2] <= boxes[None, :, 0]) | (boxes[None, :, 2] <= boxes[:, None, 0])
             | (boxes[:, None, 3] <= boxes[None, :, 1]) | (boxes[None, :, 3] <= boxes[:, None, 1]))
    np.fill_diagonal(apart, True)
    assert apart.all(), 'boxes overlap'
    assert boxes[:, 2].max() <= placed.width and boxes[:, 3].max() <= placed.height and boxes.min() >= 0
    reversed_count = 0
    for src, dst in edges:
        points = np.array(placed.routes[(src, dst)])
        a, b = placed.boxes[src], placed.boxes[dst]
        steps = np.diff(points[:, 0])
        if a.layer < b.layer:
            assert (steps >= 0).all() and points[0, 0] == a.x + a.width and points[-1, 0] == b.x, (src, dst)
        else:
            reversed_count += 1
            assert a.layer > b.layer and (steps <= 0).all() and points[-1, 0] == b.x + b.width, (src, dst)
        assert a.y <= points[0, 1] <= a.y + a.height and b.y <= points[-1, 1] <= b.y + b.height
    return reversed_count


def test_graph_layout_runs_left_to_right_and_survives_cycles():
    content = {'nodes': ['/talker', '/listener', '/relay'],
               'topics': {'/chatter': ['std_msgs/msg/String'], '/echo': ['std_msgs/msg/String']},
               'edges': [('n:/talker', 't:/chatter'), ('t:/chatter', 'n:/listener'), ('t:/chatter', 'n:/relay'),
                         ('n:/relay', 't:/echo'), ('t:/echo', 'n:/talker')]}
    placed = layout(content)
    assert set(placed.boxes) == {'n:/talker', 'n:/listener', 'n:/relay', 't:/chatter', 't:/echo'}
    layers = {v: b.layer for v, b in placed.boxes.items()}
    assert layers['n:/talker'] < layers['t:/chatter'] < layers['n:/listener']
    assert _assert_readable(placed, content['edges']) == 1           # one edge closes the cycle
    svg = to_svg(content)
    assert svg.startswith('<svg') and svg.count('<ellipse') == 3 and svg.count('<rect') == 2
    assert svg.count('marker-end') == 5 and '/chatter' in svg
    assert 'no nodes' in to_svg({'nodes': [], 'topics': {}, 'edges': []})


def test_layered_layout_of_a_dag_points_every_edge_right_and_spans_long_edges():
    # a -> b -> c -> d and a -> d: the long edge crosses two layers through dummy points.
    edges = [('a', 'b'), ('b', 'c'), ('c', 'd'), ('a', 'd'), ('e', 'd')]
    placed = layered_layout('abcde', edges, {v: 50.0 for v in 'abcde'})
    assert [placed.boxes[v].layer for v in 'abcd'] == [0, 1, 2, 3]
    assert placed.boxes['e'].layer == 2                  # a source sits next to its successor, not in layer 0
    assert _assert_readable(placed, edges) == 0
    assert len(placed.routes[('a', 'd')]) == 2 + 2 * 2   # two ends, in and out of each crossed column


def test_layered_layout_removes_avoidable_crossings():
    # Name order would cross a->y with b->x; the barycentre sweeps untangle it.
    edges = [('a', 'y'), ('b', 'x'), ('y', 'p'), ('x', 'q')]
    placed = layered_layout(['a', 'b', 'x', 'y', 'p', 'q'], edges, {})
    y = {v: placed.boxes[v].y for v in placed.boxes}
    assert (y['a'] < y['b']) == (y['y'] < y['x']) == (y['p'] < y['q'])


def test_nav2_graph_is_laid_out_in_layers_without_overlaps():
    content = _nav2_graph()
    for hides in (Hides(), Hides(False, False, False, False, False)):
        shown = apply_hides(content, hides)
        placed = layout(shown)
        assert set(placed.boxes) == {'n:' + n for n in shown['nodes']} | {'t:' + t for t in shown['topics']}
        reversed_count = _assert_readable(placed, shown['edges'])
        assert reversed_count <= len(shown['edges']) // 10         # cycles cost a few edges, not the picture
    everything = layout(content)
    assert max(b.layer for b in everything.boxes.values()) >= 4     # layered, not one strip
    assert '<path data-edge=' in to_svg(content)


def test_rqt_graph_hides():
    content = _nav2_graph()
    default = apply_hides(content)
    topics, nodes = set(default['topics']), set(default['nodes'])
    assert {'/scan', '/odom', '/map', '/cmd_vel', '/cmd_vel_nav', '/local_costmap/costmap_raw'} <= topics
    for gone in ('/tf', '/tf_static', '/rosout', '/parameter_events', '/clock',    # tf, debug, params
                 '/amcl/transition_event', '/plan', '/amcl_pose',                   # dead sinks (rviz2 is debug)
                 '/navigate_to_pose/_action/status', '/initialpose'):               # hidden; leaf (only rviz2 publishes)
        assert gone not in topics, gone
    assert '/rviz2' not in nodes and '/amcl' in nodes and '/waypoint_follower' in nodes   # nodes stay without edges
    shown = {'t:' + t for t in topics} | {'n:' + n for n in nodes}
    assert all(s in shown and d in shown for s, d in default['edges'])
    # Each checkbox off brings its own back.
    assert {'/tf', '/tf_static'} <= set(apply_hides(content, Hides(tf=False))['topics'])
    assert '/parameter_events' in apply_hides(content, Hides(params=False))['topics']
    debug = apply_hides(content, Hides(debug=False))
    assert '/rviz2' in debug['nodes'] and {'/plan', '/initialpose'} <= set(debug['topics'])
    assert '/rosout' in apply_hides(content, Hides(debug=False, dead_sinks=False))['topics']
    sinks = apply_hides(content, Hides(dead_sinks=False, leaf_topics=False))
    assert {'/amcl_pose', '/amcl/transition_event'} <= set(sinks['topics'])
    assert '/amcl_pose' not in apply_hides(content, Hides(dead_sinks=False))['topics']   # a leaf topic too
    nothing = apply_hides(content, Hides(False, False, False, False, False))
    assert nothing['topics'] == content['topics'] and sorted(nothing['edges']) == sorted(content['edges'])


def test_console_filters():
    from interfaces.rcl_interfaces.msg import Log
    buffer = LogBuffer(capacity=10)
    for level, name, text in ((20, 'talker', 'Publishing: hello 1'), (30, 'amcl', 'Please set the initial pose'),
                              (40, 'talker', 'Something failed'), (10, 'listener', 'I heard: hello')):
        buffer.add(Log(level=level, name=name, msg=text))
    assert [r.text for r in buffer.select(min_level=30)] == ['Please set the initial pose', 'Something failed']
    assert [r.node for r in buffer.select(node='talker')] == ['talker', 'talker']
    assert [r.level for r in buffer.select(text='HELLO')] == [20, 10]
    assert buffer.nodes == {'talker', 'amcl', 'listener'} and buffer.seq == 4
    html = to_html(buffer.select(), total=buffer.seq)
    assert html.count('<tr') == 4 and 'WARN' in html and 'Please set the initial pose' in html
    assert 'no log lines match' in to_html([], total=4)
