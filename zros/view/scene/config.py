"""What the view shows, read from an RViz `.rviz` file or a zros view file, and saved as the latter.

A `.rviz` file (YAML) gives the fixed frame, the grid, the camera and the displays, each with its
topic and the options the view understands (colour scheme, alpha, size, colour, arrow length).
Display classes the view does not draw are collected in `ViewConfig.unknown` (listed once in the
page), never fatal. A zros view file is plain YAML with the same content:

    zros_view: 1
    fixed_frame: map
    grid: {enabled: true, cell_size: 1.0, cells: 10, color: [160, 160, 164]}
    displays:
    - {class: Map, name: Map, topic: /map, enabled: true, color_scheme: map, alpha: 0.7}
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = ['ViewConfig', 'GridConfig', 'DisplayConfig', 'ConfigError', 'load_config', 'parse_rviz', 'parse_view',
           'dump_view', 'RVIZ_CLASSES']


class ConfigError(ValueError):
    """The file cannot be read as an RViz config or a zros view file."""


@dataclass
class GridConfig:
    enabled: bool = True
    cell_size: float = 1.0       # [m]
    cells: int = 10              # per side
    color: tuple[int, int, int] = (160, 160, 164)
    frame: str = ''              # '' = the fixed frame


@dataclass
class DisplayConfig:
    kind: str                    # a zros display kind: Map, LaserScan, ...
    name: str
    topic: str = ''
    msg_type: str = ''           # '' = the kind's first type
    enabled: bool = True
    options: dict[str, Any] = field(default_factory=dict)


@dataclass
class ViewConfig:
    fixed_frame: str = ''        # '' = choose from TF (map, else odom, else a root frame)
    grid: GridConfig = field(default_factory=GridConfig)
    displays: list[DisplayConfig] = field(default_factory=list)
    unknown: list[str] = field(default_factory=list)
    camera: dict[str, Any] = field(default_factory=dict)
    source: str = ''             # the file it came from


# RViz class -> (zros kind, message type or '', {RViz property: (option, converter)})
def _color(text: Any) -> tuple[int, int, int]:
    parts = [int(float(p)) for p in str(text).replace(',', ';').split(';') if p.strip()]
    if len(parts) < 3:
        raise ValueError(f'not a colour: {text!r}')
    return (parts[0], parts[1], parts[2])


_COLOR = ('color', _color)
_ALPHA = ('alpha', float)
RVIZ_CLASSES: dict[str, tuple[str, str, dict[str, tuple[str, Any]]]] = {
    'Map': ('Map', 'nav_msgs/msg/OccupancyGrid', {'Color Scheme': ('color_scheme', str), 'Alpha': _ALPHA}),
    'LaserScan': ('LaserScan', 'sensor_msgs/msg/LaserScan', {'Size (m)': ('size', float), 'Color': _COLOR}),
    'PointCloud2': ('PointCloud2', 'sensor_msgs/msg/PointCloud2', {'Size (m)': ('size', float)}),
    'Path': ('Path', 'nav_msgs/msg/Path', {'Color': _COLOR}),
    'PoseArray': ('PoseArray', 'geometry_msgs/msg/PoseArray', {'Color': _COLOR, 'Arrow Length': ('length', float)}),
    'ParticleCloud': ('PoseArray', 'nav2_msgs/msg/ParticleCloud', {'Color': _COLOR,
                                                                     'Arrow Length': ('length', float)}),
    'Pose': ('Pose', 'geometry_msgs/msg/PoseStamped', {'Color': _COLOR, 'Shaft Length': ('length', float)}),
    'PoseWithCovariance': ('PoseWithCovariance', 'geometry_msgs/msg/PoseWithCovarianceStamped',
                           {'Color': _COLOR, 'Shaft Length': ('length', float)}),
    'Odometry': ('Odometry', 'nav_msgs/msg/Odometry', {'Keep': ('keep', int)}),
    'Marker': ('Marker', 'visualization_msgs/msg/Marker', {}),
    'MarkerArray': ('Marker', 'visualization_msgs/msg/MarkerArray', {}),
    'Image': ('Image', 'sensor_msgs/msg/Image', {}),
    'TF': ('TF', '', {'Show Names': ('show_names', bool), 'Show Axes': ('show_axes', bool),
                      'Show Arrows': ('show_arrows', bool), 'Marker Scale': ('marker_scale', float)}),
    'RobotModel': ('RobotModel', 'std_msgs/msg/String', {'Alpha': _ALPHA}),
}


def load_config(path: str | Path) -> ViewConfig:
    """Read a `.rviz` file or a zros view file (told apart by their content).

    Raises:
        ConfigError: unreadable, not YAML, or neither kind of file.
    """
    import yaml
    path = Path(path)
    try:
        text = path.read_text(encoding='utf-8')
    except OSError as exc:
        raise ConfigError(f'cannot read {path}: {exc.strerror or exc}') from None
    try:
        data = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, 'problem_mark', None)
        where = f' (line {mark.line + 1})' if mark is not None else ''
        raise ConfigError(f'{path} is not valid YAML{where}') from None
    if not isinstance(data, dict):
        raise ConfigError(f'{path} is neither an RViz config nor a zros view file')
    config = parse_view(data) if 'zros_view' in data else parse_rviz(data) if 'Visualization Manager' in data \
        else None
    if config is None:
        raise ConfigError(f"{path} is neither an RViz config (no 'Visualization Manager') nor a zros view file")
    config.source = str(path)
    return config


def parse_rviz(data: dict[str, Any]) -> ViewConfig:
    """The ViewConfig of a parsed `.rviz` document."""
    manager = data.get('Visualization Manager') or {}
    config = ViewConfig()
    options = manager.get('Global Options') or {}
    config.fixed_frame = str(options.get('Fixed Frame') or '')
    config.grid.enabled = False                 # only a Grid display turns it on
    for display in _flatten(manager.get('Displays') or []):
        _rviz_display(display, config)
    current = (manager.get('Views') or {}).get('Current') or {}
    if isinstance(current, dict):
        focal = current.get('Focal Point') or {}
        config.camera = {key: float(value) for key, value in (
            ('distance', current.get('Distance')), ('pitch', current.get('Pitch')), ('yaw', current.get('Yaw')),
            ('focal_x', focal.get('X')), ('focal_y', focal.get('Y')), ('focal_z', focal.get('Z')))
            if isinstance(value, (int, float))}
        if 'TopDownOrtho' in str(current.get('Class', '')):
            config.camera['mode'] = 'top-down'
    return config


def _flatten(displays: list[Any]) -> list[dict[str, Any]]:
    """The displays of a list, groups (rviz_common/Group) opened."""
    out: list[dict[str, Any]] = []
    for display in displays:
        if not isinstance(display, dict):
            continue
        if str(display.get('Class', '')).endswith('/Group'):
            out.extend(_flatten(display.get('Displays') or []))
        else:
            out.append(display)
    return out


def _topic_of(display: dict[str, Any], *keys: str) -> str:
    for key in keys:
        value = display.get(key)
        if isinstance(value, dict):
            value = value.get('Value')
        if value:
            return str(value)
    return ''


def _rviz_display(display: dict[str, Any], config: ViewConfig) -> None:
    rviz_class = str(display.get('Class', ''))
    short = rviz_class.rsplit('/', 1)[-1]
    name = str(display.get('Name') or short)
    enabled = bool(display.get('Enabled', True))
    if short == 'Grid':
        grid = config.grid
        grid.enabled = enabled
        grid.cell_size = float(display.get('Cell Size', grid.cell_size))
        grid.cells = int(display.get('Plane Cell Count', grid.cells))
        grid.frame = str(display.get('Reference Frame') or '').replace('<Fixed Frame>', '')
        if 'Color' in display:
            try:
                grid.color = _color(display['Color'])
            except ValueError:
                pass
        return
    known = RVIZ_CLASSES.get(short)
    if known is None:
        if rviz_class not in config.unknown:
            config.unknown.append(rviz_class)
        return
    kind, msg_type, properties = known
    options: dict[str, Any] = {}
    for key, (option, convert) in properties.items():
        if key in display:
            try:
                options[option] = convert(display[key])
            except (TypeError, ValueError):
                continue
    if short == 'MarkerArray' or short == 'Marker':
        topic = _topic_of(display, 'Topic', 'Marker Topic')
    elif short == 'RobotModel':
        topic = _topic_of(display, 'Description Topic') or '/robot_description'
    else:
        topic = _topic_of(display, 'Topic')
    config.displays.append(DisplayConfig(kind, name, topic, msg_type, enabled, options))


def parse_view(data: dict[str, Any]) -> ViewConfig:
    """The ViewConfig of a parsed zros view file.

    Raises:
        ConfigError: a display entry has no class.
    """
    config = ViewConfig(fixed_frame=str(data.get('fixed_frame') or ''))
    grid = data.get('grid') or {}
    config.grid = GridConfig(enabled=bool(grid.get('enabled', True)), cell_size=float(grid.get('cell_size', 1.0)),
                             cells=int(grid.get('cells', 10)), color=tuple(grid.get('color', (160, 160, 164))),
                             frame=str(grid.get('frame') or ''))
    for index, entry in enumerate(data.get('displays') or []):
        if not isinstance(entry, dict) or 'class' not in entry:
            raise ConfigError(f'display {index + 1} has no class')
        entry = dict(entry)
        kind = str(entry.pop('class'))
        msg_type = str(entry.pop('type', '') or '')
        if kind == 'MarkerArray':
            kind, msg_type = 'Marker', msg_type or 'visualization_msgs/msg/MarkerArray'
        config.displays.append(DisplayConfig(kind, str(entry.pop('name', kind)), str(entry.pop('topic', '') or ''),
                                             msg_type, bool(entry.pop('enabled', True)),
                                             {k: tuple(v) if isinstance(v, list) else v for k, v in entry.items()}))
    config.camera = dict(data.get('camera') or {})
    return config


def dump_view(config: ViewConfig) -> str:
    """A zros view file's text for `config`."""
    import yaml
    grid = config.grid
    data = {'zros_view': 1, 'fixed_frame': config.fixed_frame,
            'grid': {'enabled': grid.enabled, 'cell_size': grid.cell_size, 'cells': grid.cells,
                     'color': list(grid.color), 'frame': grid.frame},
            'camera': dict(config.camera),
            'displays': [{'class': d.kind, 'name': d.name, 'topic': d.topic, 'type': d.msg_type,
                          'enabled': d.enabled, **{k: list(v) if isinstance(v, tuple) else v
                                                   for k, v in d.options.items()}}
                         for d in config.displays]}
    return yaml.safe_dump(data, sort_keys=False, default_flow_style=None)
