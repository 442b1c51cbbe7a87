"""The scene view: RViz's role in the browser, on viser, with rqt's tools as tabs beside it.

`SceneView(node, config=...)` serves one page: a 3D scene in the fixed frame (orbit, pan, zoom,
a top-down button, a grid), the Displays list (one per topic, RViz's display types), the tools
(2D Pose Estimate, Nav2 Goal, Publish Point, a teleop pad) and a side panel of pages, rqt's
tools (Topics, Plot, Services, Parameters, Images, Graph, Console; more with `add_page`). The caller spins `node`.

Threads: the node's executor stores messages; a render thread (`zros-view-render`) draws them
when a display's rate allows; a slow thread (`zros-view-slow`, 2 Hz) reads the graph, refreshes
the pages, picks up new topics and updates status lines; viser's own threads run the GUI
callbacks (tools, teleop, options).
"""
from __future__ import annotations

import contextlib
import io
import math
import socket
import threading
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Sequence

import numpy as np

from zros.view.scene import tools
from zros.view.scene.config import DisplayConfig, GridConfig, ViewConfig, dump_view
from zros.view.scene.displays import DISPLAY_KINDS, display_for_topic
from zros.view.scene.displays.base import DISABLED, ERROR, OK, WARN, Display, DisplayContext
from zros.view.scene.pages import ConsolePage, GraphPage, ImagesPage, Page, TopicsPage, TopicStats
from zros.view.scene.rqt_pages import ParametersPage, PlotPage, ServicesPage

if TYPE_CHECKING:
    import viser

    from zros.node import Node

__all__ = ['SceneView', 'DEFAULT_PORT', 'ViewError', 'PANEL_WIDTHS']

DEFAULT_PORT = 8080
PANEL_WIDTHS = (340, 400)       # [px] the control panel (docked left) and the pages (docked right)
RQT_PANEL_WIDTH = 760           # [px] the pages, when an rqt command opened the view on one
RQT_GRAPH_PANEL_WIDTH = 1200    # [px] ... on the Graph page (rqt_graph): a navigation stack's graph is wide
RENDER_RATE = 30.0              # [Hz] the most any display is redrawn
SLOW_PERIOD = 0.5               # [s] graph reads, pages, status
SERVER_STOP_WAIT = 1.0          # [s] close() waits this long for viser's server thread (see close)
TELEOP_PERIOD = 0.1             # [s] /cmd_vel while a pad direction is held
_STATUS_COLORS = {OK: '#16a34a', WARN: '#d97706', ERROR: '#dc2626', DISABLED: '#9ca3af'}
_TOOL_HINTS = {
    'pose': '2D Pose Estimate: press where the robot is and drag towards its heading.',
    'goal': 'Nav2 Goal: press on the goal and drag towards the heading wanted there.',
    'point': 'Publish Point: click a point on the ground.',
}
_AUTO_DISPLAYS = [DisplayConfig('TF', 'TF')]
_AUTO_SKIP = ('/rosout', '/parameter_events', '/tf', '/tf_static', '/initialpose', '/goal_pose', '/clicked_point')


class ViewError(RuntimeError):
    """The view cannot start (port taken, viser missing)."""


class SceneView:
    """Serves the scene view for `node`'s graph on http://host:port/.

    Args:
        node: subscribes to the displayed topics, publishes the tools' messages, reads the graph.
        config: what to show; None shows every known topic as it appears ("auto"), in the
            fixed frame `map` (else `odom`, else a root of the TF tree).
        host: address to bind (loopback by default: nothing is exposed to the network).
        port: TCP port; 0 picks a free one; if taken and `port_tries` > 1 the next ones are tried.
        image_page_url: where the full-size image page is served, linked from the Images tab.
        tf: False to run without TF (every frame but the fixed one is then "not transformable").
        first_page: the title of the page to open on ('Plot', 'Graph', ...: what `zros run
            rqt_plot rqt_plot` and the other rqt commands show); the pages then get the wider panel.
        plot: field paths the Plot page starts with ('/turtle1/pose/x').
    Raises:
        ViewError: no port could be bound.
    """

    def __init__(self, node: 'Node', *, config: ViewConfig | None = None, host: str = '127.0.0.1',
                 port: int = DEFAULT_PORT, port_tries: int = 1, image_page_url: str | None = None,
                 tf: bool = True, title: str = 'zros view', first_page: str = '',
                 plot: Sequence[str] = ()) -> None:
        self.node = node
        self.auto = config is None
        self.config = config or ViewConfig()
        self.stats = TopicStats()
        self.displays: list[Display] = []
        self.pages: list[Page] = []
        self.tool: str | None = None
        self.teleop_twist: Any = None
        self.host = host
        self._closed = threading.Event()
        self._lock = threading.RLock()
        self._entities: list[Any] = []
        self._topic_types: list[tuple[str, list[str]]] = []
        self._published_types: dict[str, set[str]] = {}
        self._status_dirty = threading.Event()
        self._fixed_auto = not self.config.fixed_frame
        self.frames = self._start_tf() if tf else None
        self.server = self._start_server(host, port, port_tries)
        self.port = self.server.get_port()
        self.ctx = DisplayContext(self.server.scene, self.server.gui, node, self.frames,
                                  self.config.fixed_frame or 'map', threading.Event(),
                                  publishers=self._publisher_count)
        self._publishers_on: dict[str, int] = {}
        self._pubs = {
            'pose': node.create_publisher(_msg('geometry_msgs/msg/PoseWithCovarianceStamped'), '/initialpose', 10),
            'goal': node.create_publisher(_msg('geometry_msgs/msg/PoseStamped'), '/goal_pose', 10),
            'point': node.create_publisher(_msg('geometry_msgs/msg/PointStamped'), '/clicked_point', 10),
        }
        self._cmd_vel: Any = None
        self._build_scene()
        self._build_gui(title, image_page_url, first_page, plot)
        for entry in self.config.displays or (_AUTO_DISPLAYS if self.auto else []):
            self.add_display(entry)
        self._threads = [threading.Thread(target=self._render_loop, name='zros-view-render', daemon=True),
                         threading.Thread(target=self._slow_loop, name='zros-view-slow', daemon=True)]
        for thread in self._threads:
            thread.start()

    # -- start-up --------------------------------------------------------------------------
    def _start_tf(self) -> Any:
        try:
            from zros.view.scene.frames import Frames
            return Frames(self.node)
        except ImportError:
            return None

    def _start_server(self, host: str, port: int, port_tries: int) -> 'viser.ViserServer':
        import viser
        if port != 0:
            for candidate in range(port, port + max(1, port_tries)):
                if _port_free(host, candidate):
                    port = candidate
                    break
            else:
                last = f'..{port + port_tries - 1}' if port_tries > 1 else ''
                raise ViewError(f'cannot serve on {host}:{port}{last}: address already in use')
        else:
            port = _free_port(host)
        with contextlib.redirect_stdout(io.StringIO()):          # viser prints a banner: we print the URL
            return viser.ViserServer(host=host, port=port, label=None, verbose=False)

    @property
    def gui(self) -> 'viser.GuiApi':
        """viser's GUI API: pages add their widgets with it."""
        return self.server.gui

    @property
    def url(self) -> str:
        host = {'0.0.0.0': '127.0.0.1', '': '127.0.0.1', '::': '[::1]'}.get(self.host, self.host)
        return f'http://{host}:{self.port}/'

    # -- the scene ---------------------------------------------------------------------------
    def _build_scene(self) -> None:
        scene = self.server.scene
        scene.set_up_direction('+z')
        scene.world_axes.visible = False
        scene.configure_environment_map(None)     # viser's default HDRI washes out unlit planes (the map)
        scene.configure_default_lights(True, cast_shadow=False)   # a shadow pass per frame buys nothing here
        self.grid: Any = None
        self._apply_grid(self.config.grid)
        camera = self.config.camera
        distance = float(camera.get('distance', 8.0))
        pitch, yaw = float(camera.get('pitch', 0.785)), float(camera.get('yaw', 0.785))
        focal = np.array([camera.get('focal_x', 0.0), camera.get('focal_y', 0.0), camera.get('focal_z', 0.0)])
        initial = self.server.initial_camera
        if camera.get('mode') == 'top-down':
            initial.position, initial.look_at = _top_down(focal, distance)
        else:
            initial.position = focal + distance * np.array([math.cos(pitch) * math.cos(yaw),
                                                            math.cos(pitch) * math.sin(yaw), math.sin(pitch)])
            initial.look_at = focal
        initial.up = (0.0, 0.0, 1.0)
        self._focal = focal
        self._distance = distance

    def _apply_grid(self, grid: GridConfig) -> None:
        """The grid as thin lines (one draw call; viser's shader grid costs a fill of the whole plane)."""
        if self.grid is not None:
            self.grid.remove()
        half = grid.cell_size * grid.cells / 2.0
        ticks = np.linspace(-half, half, grid.cells + 1)
        along_x = np.stack([np.stack([np.full_like(ticks, -half), ticks], 1), np.stack([np.full_like(ticks, half),
                                                                                        ticks], 1)], axis=1)
        lines = np.concatenate([along_x, along_x[:, :, ::-1]])
        segments = np.concatenate([lines, np.full((*lines.shape[:2], 1), -0.001)], axis=2).astype(np.float32)
        self.grid = self.server.scene.add_line_segments('/grid', segments, tuple(int(c) for c in grid.color),
                                                        thickness=1.0, thickness_units='screen', visible=grid.enabled)
        self.config.grid = grid

    def set_camera(self, mode: str, *, focal: Any = None, distance: float | None = None) -> None:
        """Point every open page's camera: 'top-down' (2D navigation work) or 'orbit' (3D)."""
        focal = np.asarray(self._focal if focal is None else focal, dtype=np.float64)
        distance = float(distance or self._distance)
        for client in self.server.get_clients().values():
            with client.atomic():
                if mode == 'top-down':
                    client.camera.up_direction = (0.0, 0.0, 1.0)
                    client.camera.position, client.camera.look_at = _top_down(focal, distance)
                else:
                    client.camera.look_at = focal
                    client.camera.position = focal + distance * np.array([0.56, 0.56, 0.61])
        self.config.camera.update({'mode': mode, 'distance': distance, 'focal_x': float(focal[0]),
                                   'focal_y': float(focal[1]), 'focal_z': float(focal[2])})

    # -- the control panel ---------------------------------------------------------------------
    def _build_gui(self, title: str, image_page_url: str | None, first_page: str, plot: Sequence[str]) -> None:
        import viser
        gui = self.server.gui
        gui.configure_theme(control_width='large', show_logo=False, show_share_button=False,
                            brand_color=(37, 99, 235))
        gui.set_panel_label(title)
        main = gui.main_panel
        main.dock_left()
        main.set_width(PANEL_WIDTHS[0])
        if first_page:                  # an rqt command: its pages first, the scene's controls folded away
            main.minimize()
        self.global_status = gui.add_html('')
        with gui.add_folder('Global Options'):
            frames = [self.ctx.fixed_frame]
            self.fixed_frame_input = gui.add_dropdown('Fixed Frame', frames, initial_value=self.ctx.fixed_frame)
            # viser runs on_update for the view's own assignments too (client None): only a
            # person's choice pins the frame; the automatic odom -> map switch must stay possible.
            self.fixed_frame_input.on_update(lambda event: self.set_fixed_frame(
                self.fixed_frame_input.value, user=event.client is not None))
            self.grid_input = gui.add_checkbox('Grid', self.config.grid.enabled)
            self.grid_input.on_update(lambda _: setattr(self.grid, 'visible', self.grid_input.value))
            camera = gui.add_button_group('Camera', ['Top-down', '3D orbit'])
            camera.on_click(lambda event: self.set_camera('top-down' if event.target.value == 'Top-down' else 'orbit'))
        with gui.add_folder('Tools'):
            self.tool_buttons = {
                'pose': gui.add_button('2D Pose Estimate', icon=viser.Icon.CURRENT_LOCATION, color='green'),
                'goal': gui.add_button('Nav2 Goal', icon=viser.Icon.FLAG, color='pink'),
                'point': gui.add_button('Publish Point', icon=viser.Icon.MAP_PIN, color='cyan'),
            }
            for name, button in self.tool_buttons.items():
                button.on_click(lambda _, name=name: self.start_tool(name))
            self.tool_hint = gui.add_html(_hint('Pick a tool, then use it in the scene.'))
        with gui.add_folder('Teleop (/cmd_vel)', expand_by_default=False):
            row1 = gui.add_button_group(' ', ['↺ Left', '▲ Forward', '↻ Right'])
            row2 = gui.add_button_group('  ', ['■ Stop', '▼ Back'])
            self.linear_speed = gui.add_slider('Linear [m/s]', 0.0, 1.0, 0.01, 0.2)
            self.angular_speed = gui.add_slider('Angular [rad/s]', 0.0, 3.0, 0.05, 1.0)
            directions = {'↺ Left': 'left', '▲ Forward': 'forward', '↻ Right': 'right', '■ Stop': 'stop',
                          '▼ Back': 'back'}
            for row in (row1, row2):
                row.on_click(lambda event: self.drive(directions[event.target.value]))
        self.displays_folder = gui.add_folder('Displays')
        with self.displays_folder:
            self.unknown_note = gui.add_html('')
            self._show_unknown()
        with gui.add_folder('Add display', expand_by_default=False):
            self.add_choice = gui.add_dropdown('Topic', ['(none yet)'])
            add_button = gui.add_button('Add', icon=viser.Icon.PLUS)
            add_button.on_click(lambda _: self._add_from_gui())
        with gui.add_folder('Save view', expand_by_default=False):
            default = Path(self.config.source).with_suffix('.view.yaml').name if self.config.source else 'view.yaml'
            self.save_path = gui.add_text('File', default)
            save = gui.add_button('Save', icon=viser.Icon.DEVICE_FLOPPY)
            self.save_note = gui.add_html('')
            save.on_click(lambda _: self._save_from_gui())
        self.side = gui.add_panel()
        self.side.dock_right()
        self.side.set_width(RQT_GRAPH_PANEL_WIDTH if first_page == 'Graph' else RQT_PANEL_WIDTH if first_page
                            else PANEL_WIDTHS[1])
        self.images_page = ImagesPage(image_page_url)
        pages = [TopicsPage(), PlotPage(plot), ServicesPage(), ParametersPage(), self.images_page, GraphPage(),
                 ConsolePage()]
        titles = [page.title for page in pages]
        if first_page and first_page not in titles:
            raise ValueError(f'no page {first_page!r} (pages: {", ".join(titles)})')
        pages.sort(key=lambda page: page.title != first_page)
        for page in pages:
            self.add_page(page)
        self.images_tab = self.images_page.tab
        self.server.scene.on_click()(self._on_scene_click)

    def add_page(self, page: Page) -> None:
        """Add a tab to the side panel (see zros.view.scene.pages.Page)."""
        tab = page.tab = self.side.add_tab(page.title, icon=page.icon)
        with tab:
            page.build(self)
        with self._lock:
            self.pages.append(page)

    def _show_unknown(self) -> None:
        unknown = self.config.unknown
        self.unknown_note.content = '' if not unknown else _status_html(
            WARN, 'Not shown (display classes zros does not draw): ' + ', '.join(unknown))

    # -- displays --------------------------------------------------------------------------
    def add_display(self, entry: DisplayConfig) -> Display | None:
        """Add one display (and its entry in the Displays list); None if the kind is unknown."""
        cls = DISPLAY_KINDS.get(entry.kind)
        if cls is None:
            if entry.kind not in self.config.unknown:
                self.config.unknown.append(entry.kind)
                self._show_unknown()
            return None
        name = self._unique_name(entry.name or entry.kind)
        display = cls(self.ctx, name, entry.topic, entry.options, msg_type=entry.msg_type or None)
        display.on_status = lambda _: self._status_dirty.set()
        if entry.kind == 'Image':
            display.container = self.images_tab
        self._display_gui(display)
        if not entry.enabled:
            display.set_enabled(False)
        else:
            try:
                display.subscribe()
            except Exception as exc:  # noqa: BLE001 - a bad topic or type reads as the display's status
                display._set_status(ERROR, f'cannot subscribe: {exc}')
        with self._lock:
            self.displays.append(display)
        self.ctx.wake.set()
        return display

    def _unique_name(self, name: str) -> str:
        taken = {d.name for d in self.displays}
        if name not in taken:
            return name
        index = 2
        while f'{name} ({index})' in taken:
            index += 1
        return f'{name} ({index})'

    def _display_gui(self, display: Display) -> None:
        gui = self.server.gui
        with self.displays_folder:
            folder = gui.add_folder(display.name + (f'  ·  {display.topic}' if display.topic else ''))
        with folder:
            status = gui.add_html(_status_html(display.status.level, display.status.text))
            enabled = gui.add_checkbox('Enabled', display.enabled)
            enabled.on_update(lambda _: display.set_enabled(enabled.value))
            for option, value in display.options.items():
                self._option_widget(display, option, value)
            remove = gui.add_button('Remove', color='gray')
            remove.on_click(lambda _: self.remove_display(display))
        display.gui = {'folder': folder, 'status': status, 'enabled': enabled}

    def _option_widget(self, display: Display, option: str, value: Any) -> None:
        from zros.view.scene.convert import MAP_SCHEMES
        gui = self.server.gui
        label = option.replace('_', ' ').capitalize()
        if option == 'color_scheme':
            widget = gui.add_dropdown(label, list(MAP_SCHEMES), initial_value=str(value))
        elif isinstance(value, bool):
            widget = gui.add_checkbox(label, value)
        elif option == 'alpha':
            widget = gui.add_slider(label, 0.0, 1.0, 0.05, float(value))
        elif isinstance(value, (int, float)):
            widget = gui.add_number(label, value, step=0.01 if isinstance(value, float) else 1)
        elif isinstance(value, tuple) and len(value) == 3:
            widget = gui.add_rgb(label, tuple(int(c) for c in value))
        else:
            return
        widget.on_update(lambda _: display.set_option(option, widget.value))

    def remove_display(self, display: Display) -> None:
        with self._lock:
            if display not in self.displays:
                return
            self.displays.remove(display)
        display.destroy()
        folder = getattr(display, 'gui', {}).get('folder')
        if folder is not None:
            folder.remove()

    def displays_on(self, topic: str) -> list[Display]:
        with self._lock:
            return [d for d in self.displays if d.topic == topic]

    def _add_from_gui(self) -> None:
        choice = self.add_choice.value
        if ' · ' not in choice:
            return
        topic, msg_type = choice.split(' · ', 1)
        cls = display_for_topic(topic, msg_type)
        if cls is not None:
            self.add_display(DisplayConfig(cls.kind, _display_name(cls.kind, topic), topic, msg_type,
                                           options=_auto_options(cls.kind, topic)))

    def set_fixed_frame(self, frame: str, *, user: bool = False) -> None:
        """Show everything in `frame`; every display redraws its last message there."""
        frame = frame.strip().lstrip('/')
        if not frame:
            return
        if user:
            self._fixed_auto = False
        if frame == self.ctx.fixed_frame:
            return
        self.ctx.fixed_frame = frame
        self.config.fixed_frame = frame
        if self.fixed_frame_input.value != frame:
            if frame not in self.fixed_frame_input.options:
                self.fixed_frame_input.options = [frame, *self.fixed_frame_input.options]
            self.fixed_frame_input.value = frame
        with self._lock:
            displays = list(self.displays)
        for display in displays:
            display.redraw()
        self._status_dirty.set()

    # -- tools -----------------------------------------------------------------------------
    def start_tool(self, name: str) -> None:
        """Arm a tool: the next drag (or click, for Publish Point) on the ground uses it."""
        self._stop_tool()
        self.tool = name
        self.tool_hint.content = _hint(_TOOL_HINTS[name], active=True)
        if name == 'point':
            return
        size = max(200.0, self._distance * 20)
        vertices = np.array([[-size, -size, 0.0], [size, -size, 0.0], [size, size, 0.0], [-size, size, 0.0]],
                            dtype=np.float32)
        faces = np.array([[0, 1, 2], [0, 2, 3]], dtype=np.uint32)
        self._surface = self.server.scene.add_mesh_simple('/tool/surface', vertices, faces, color=(255, 255, 255),
                                                          opacity=0.0, side='double', cast_shadow=False,
                                                          receive_shadow=False)
        self._surface.on_drag('left')(self._on_drag)

    def _stop_tool(self) -> None:
        surface = getattr(self, '_surface', None)
        if surface is not None:
            surface.remove()
            self._surface = None
        preview = getattr(self, '_preview', None)
        if preview is not None:
            preview.remove()
            self._preview = None
        self.tool = None

    def _on_drag(self, event: Any) -> None:
        start = np.asarray(event.start_position, dtype=np.float64)
        camera = np.asarray(event.client.camera.position, dtype=np.float64)
        end = tools.ground_point(camera, np.asarray(event.end_position) - camera)
        end = start if end is None else end
        pose = tools.drag_pose(start, end)
        color = (0, 200, 80) if self.tool == 'pose' else (220, 40, 160)
        points = np.array([[[pose.x, pose.y, 0.02], [pose.x + 0.6 * math.cos(pose.yaw),
                                                      pose.y + 0.6 * math.sin(pose.yaw), 0.02]]], dtype=np.float32)
        if getattr(self, '_preview', None) is None:
            self._preview = self.server.scene.add_arrows('/tool/preview', points, color, shaft_radius=0.03,
                                                         head_radius=0.08, head_length=0.15)
        else:
            self._preview.points = points
        if event.phase == 'end':
            self.use_tool(self.tool or '', pose)

    def use_tool(self, name: str, pose: tools.PlanarPose) -> None:
        """Publish what tool `name` publishes for `pose` (in the fixed frame), and disarm it."""
        stamp = self.node.get_clock().now().to_msg()
        frame = self.ctx.fixed_frame
        if name == 'pose':
            self._pubs['pose'].publish(tools.initial_pose(pose, frame, stamp))
            text = f'Published /initialpose: x {pose.x:.2f}, y {pose.y:.2f}, yaw {math.degrees(pose.yaw):.0f}° in [{frame}]'
        elif name == 'goal':
            self._pubs['goal'].publish(tools.goal_pose(pose, frame, stamp))
            text = f'Published /goal_pose: x {pose.x:.2f}, y {pose.y:.2f}, yaw {math.degrees(pose.yaw):.0f}° in [{frame}]'
        else:
            return
        self._stop_tool()
        self.tool_hint.content = _hint(text)

    def _on_scene_click(self, event: Any) -> None:
        if self.tool != 'point':
            return
        point = tools.ground_point(event.ray_origin, event.ray_direction)
        if point is None:
            return
        frame = self.ctx.fixed_frame
        self._pubs['point'].publish(tools.clicked_point(point, frame, self.node.get_clock().now().to_msg()))
        self._stop_tool()
        self.tool_hint.content = _hint(f'Published /clicked_point: ({point[0]:.2f}, {point[1]:.2f}, '
                                       f'{point[2]:.2f}) in [{frame}]')

    def drive(self, direction: str) -> None:
        """The teleop pad: keep publishing this direction's Twist on /cmd_vel until Stop."""
        if self._cmd_vel is None:
            self._cmd_vel = self.node.create_publisher(_msg('geometry_msgs/msg/Twist'), '/cmd_vel', 10)
        twist = tools.teleop_twist(direction, float(self.linear_speed.value), float(self.angular_speed.value))
        self._cmd_vel.publish(twist)
        self.teleop_twist = None if direction == 'stop' else twist

    # -- graph reads -------------------------------------------------------------------------
    def graph_entities(self) -> list[Any]:
        return list(self._entities)

    def topic_types(self) -> list[tuple[str, list[str]]]:
        """Topics of the graph (hidden ones left out) with their types, as last read."""
        return list(self._topic_types)

    def endpoint_counts(self, topic: str) -> tuple[int, int]:
        from zros.graph import EntityKind
        pubs = sum(1 for e in self._entities if e.kind == EntityKind.PUBLISHER and e.name == topic)
        subs = sum(1 for e in self._entities if e.kind == EntityKind.SUBSCRIPTION and e.name == topic)
        return pubs, subs

    def _publisher_count(self, topic: str) -> int:
        """Publishers on `topic` other than this view's own node (its tools publish too)."""
        return self._publishers_on.get(topic, 0)

    def _read_graph(self) -> None:
        from zros.graph_content import is_hidden
        from zros.graph import EntityKind
        entities = self.node._graph_entities()
        self._entities = entities
        topics: dict[str, set[str]] = {}
        publishers: dict[str, int] = {}
        published: dict[str, set[str]] = {}
        me = self.node.get_fully_qualified_name()
        for e in entities:
            if e.kind in (EntityKind.PUBLISHER, EntityKind.SUBSCRIPTION) and not is_hidden(e.name):
                topics.setdefault(e.name, set()).add(e.type)
                if e.kind == EntityKind.PUBLISHER and e.node_fqn != me:
                    publishers[e.name] = publishers.get(e.name, 0) + 1
                    published.setdefault(e.name, set()).add(e.type)
        self._topic_types = sorted((name, sorted(types)) for name, types in topics.items())
        self._publishers_on = publishers
        self._published_types = published

    # -- loops -------------------------------------------------------------------------------
    def _render_loop(self) -> None:
        wake = self.ctx.wake
        while not self._closed.is_set():
            wake.wait(1.0 / RENDER_RATE)
            wake.clear()
            if self._closed.is_set():
                break
            now = time.monotonic()
            with self._lock:
                displays = list(self.displays)
            with self.server.atomic():                  # one batch per pass: one wake-up of viser's loop
                for display in displays:
                    try:
                        display.tick(now)
                    except Exception as exc:  # noqa: BLE001 - one broken display must not stop the others
                        display._set_status(ERROR, f'internal error: {exc!r}')
            if self._status_dirty.is_set():
                self._status_dirty.clear()
                self._update_statuses()

    def _slow_loop(self) -> None:
        last_teleop = 0.0
        next_slow = 0.0
        while not self._closed.wait(TELEOP_PERIOD):
            now = time.monotonic()
            if self.teleop_twist is not None and self._cmd_vel is not None and now - last_teleop >= TELEOP_PERIOD:
                self._cmd_vel.publish(self.teleop_twist)
                last_teleop = now
            if now < next_slow:
                continue
            next_slow = now + SLOW_PERIOD
            try:
                self._slow_step(now)
            except Exception as exc:  # noqa: BLE001 - keep the page alive; say what broke
                self.node.get_logger().warn(f'view: {exc!r}', throttle_duration_sec=10.0)

    def _slow_step(self, now: float) -> None:
        self._read_graph()
        tree = self.frames.tree() if self.frames is not None else {}
        if self._fixed_auto:
            best = _best_fixed_frame(tree)
            if best:
                self.set_fixed_frame(best)
        frames = sorted(set(tree) | set(tree.values()) | {self.ctx.fixed_frame})
        if tuple(frames) != tuple(self.fixed_frame_input.options):
            self.fixed_frame_input.options = frames
        choices = [f'{name} · {types[0]}' for name, types in self._topic_types
                   if types and display_for_topic(name, types[0]) is not None]
        if tuple(choices or ['(none yet)']) != tuple(self.add_choice.options):
            self.add_choice.options = choices or ['(none yet)']
        if self.auto:
            self._auto_add()
        self._follow_published_types()
        with self._lock:
            pages = list(self.pages)
        for page in pages:
            page.refresh(now)
        self._update_statuses()

    def _auto_add(self) -> None:
        shown = {d.topic for d in self.displays}
        for name, types in self._topic_types:
            if (name in shown or name in _AUTO_SKIP or name.startswith('/sim/') or not types
                    or not self._publishers_on.get(name)):
                continue
            cls = display_for_topic(name, types[0])
            if cls is None:
                continue
            self.add_display(DisplayConfig(cls.kind, _display_name(cls.kind, name), name, types[0],
                                           options=_auto_options(cls.kind, name)))

    def _follow_published_types(self) -> None:
        """A display that draws several types (PoseArray: geometry_msgs/PoseArray and nav2's
        ParticleCloud) subscribes with the type the topic's publishers send, whatever a .rviz file
        or a guess said."""
        with self._lock:
            displays = list(self.displays)
        for display in displays:
            sent = self._published_types.get(display.topic, set())
            if not display.enabled or display.msg_type in sent or len(display.msg_types) < 2:
                continue
            drawable = sorted(sent & set(display.msg_types))
            if drawable:
                display.msg_type = drawable[0]
                display.subscribe()

    def _update_statuses(self) -> None:
        with self._lock:
            displays = list(self.displays)
        for display in displays:
            widgets = getattr(display, 'gui', None)
            if widgets:
                content = _status_html(display.status.level, display.status.text)
                if widgets['status'].content != content:
                    widgets['status'].content = content
        frame = self.ctx.fixed_frame
        if self.frames is None:
            text = _status_html(ERROR, 'TF is not available: only data in the fixed frame can be shown')
        else:
            tree = self.frames.tree()
            known = set(tree) | set(tree.values())
            if frame in known or not known and any(d.status.level == OK for d in displays):
                text = _status_html(OK, f'Fixed frame [{frame}]')
            elif not known:
                text = _status_html(WARN, f'Fixed frame [{frame}]: no transforms received yet')
            else:
                text = _status_html(ERROR, f'Fixed frame [{frame}] does not exist (TF knows: '
                                    + ', '.join(sorted(known)[:8]) + ')')
        if self.global_status.content != text:
            self.global_status.content = text

    # -- saving ----------------------------------------------------------------------------
    def current_config(self) -> ViewConfig:
        """What the page shows now, as a ViewConfig (for `dump_view`)."""
        with self._lock:
            displays = list(self.displays)
        entries = []
        for display in displays:
            saved = display.config()
            entries.append(DisplayConfig(saved.pop('class'), saved.pop('name'), saved.pop('topic'), saved.pop('type'),
                                         saved.pop('enabled'), saved))
        grid = self.config.grid
        grid.enabled = bool(self.grid_input.value)
        return ViewConfig(fixed_frame=self.ctx.fixed_frame, grid=grid, displays=entries,
                          camera=dict(self.config.camera))

    def save(self, path: str | Path) -> Path:
        """Write the page's layout as a zros view file.

        Raises:
            OSError: the file cannot be written.
        """
        path = Path(path).expanduser()
        path.write_text(dump_view(self.current_config()), encoding='utf-8')
        return path

    def _save_from_gui(self) -> None:
        try:
            path = self.save(self.save_path.value)
        except OSError as exc:
            self.save_note.content = _status_html(ERROR, f'cannot write {self.save_path.value}: {exc.strerror or exc}')
            return
        self.save_note.content = _status_html(OK, f'Saved to {path.resolve()}; open it with zros view -d {path}')

    # -- shutdown ----------------------------------------------------------------------------
    def close(self) -> None:
        """Stop the threads, drop the subscriptions and stop serving (idempotent)."""
        if self._closed.is_set():
            return
        self._closed.set()
        self.ctx.wake.set()
        for thread in self._threads:
            thread.join(timeout=3.0)
        if self.teleop_twist is not None and self._cmd_vel is not None:
            self._cmd_vel.publish(tools.teleop_twist('stop', 0.0, 0.0))
        for page in self.pages:
            page.close()
        for display in list(self.displays):
            display.unsubscribe()
        # viser's stop() closes the listening socket and the websockets at once, then waits (up to
        # 5 s) for every TCP connection to end, including a second, idle one Chromium keeps open,
        # which websockets drops only at its opening timeout: Ctrl-C on a view with a page open
        # took 5 s, past `zros launch`'s SIGINT grace. Nothing is served by then, so the rest of
        # the wait happens on a daemon thread.
        stopper = threading.Thread(target=self.server.stop, name='zros-view-stop', daemon=True)
        with contextlib.redirect_stdout(io.StringIO()):          # viser says "Server stopped"
            stopper.start()
            stopper.join(SERVER_STOP_WAIT)

    def __enter__(self) -> 'SceneView':
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def _msg(name: str) -> type:
    from zros.typesupport import get_message
    return get_message(name)


def _top_down(focal: np.ndarray, distance: float) -> tuple[np.ndarray, np.ndarray]:
    """Camera position and target looking straight down at `focal`, +x right and +y up on screen."""
    look_at = np.array([focal[0], focal[1], 0.0])
    return look_at + np.array([0.0, -1e-3 * distance, distance]), look_at


def _best_fixed_frame(tree: dict[str, str]) -> str:
    frames = set(tree) | set(tree.values())
    for candidate in ('map', 'odom', 'world'):
        if candidate in frames:
            return candidate
    roots = sorted(set(tree.values()) - set(tree))
    return roots[0] if roots else ''


def _display_name(kind: str, topic: str) -> str:
    return kind


def _auto_options(kind: str, topic: str) -> dict[str, Any]:
    if kind == 'Map' and 'costmap' in topic:
        return {'color_scheme': 'costmap', 'alpha': 0.5}
    if kind == 'PoseArray' and 'particle' in topic:
        return {'color': (0, 180, 0), 'length': 0.15}
    return {}


def _status_html(level: str, text: str) -> str:
    import html
    color = _STATUS_COLORS.get(level, '#6b7280')
    return (f'<div style="font-size:12px;line-height:1.35;display:flex;gap:6px"><span style="color:{color}">●</span>'
            f'<span data-status="{level}">{html.escape(text)}</span></div>')


def _hint(text: str, *, active: bool = False) -> str:
    import html
    style = 'color:#1d4ed8;font-weight:600' if active else 'color:#555'
    return f'<div style="font-size:12px;{style}" data-tool-hint="1">{html.escape(text)}</div>'


def _port_free(host: str, port: int) -> bool:
    with socket.socket(socket.AF_INET6 if ':' in host else socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        try:
            probe.bind((host, port))
        except OSError:
            return False
    return True


def _free_port(host: str) -> int:
    with socket.socket(socket.AF_INET6 if ':' in host else socket.AF_INET, socket.SOCK_STREAM) as probe:
        probe.bind((host, 0))
        return probe.getsockname()[1]

