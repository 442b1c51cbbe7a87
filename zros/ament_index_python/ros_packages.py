"""ROS 2 packages as colcon and ament lay them out, found without a build.

A student's workspace holds packages made by `ros2 pkg create`: a folder with a `package.xml`
and, for `ament_python`, a `setup.py` whose `data_files` say what goes into the package's share
directory and whose `console_scripts` name its executables. colcon would build and install
them; zros reads the same files instead:

- **Source packages** (a folder with `package.xml`), found under the directories of
  `ZROS_NODE_PATH` the way colcon discovers them (a workspace, its `src/`, or the package
  folder itself), and those installed with `pip install -e` (their folder is the editable
  install's source). `setup.py` is read by running it with a stand-in `setup()` that records
  its arguments, as colcon's Python support does. The share directory is a tree of symbolic
  links that mirrors `data_files` (`colcon build --symlink-install`), so an edited launch file
  is used at once; it is brought up to date whenever the package index is read.
- **Install prefixes**: the ament resource index (`<prefix>/share/ament_index/resource_index/
  packages/<pkg>`) of each `AMENT_PREFIX_PATH` directory and of this Python environment (where a
  non-editable `pip install` puts `data_files`). Executables are the files in
  `<prefix>/lib/<pkg>/` (colcon's layout) and the `console_scripts` of an installed
  distribution of the package's name.

An ament_cmake package found in source is its own share directory (its `msg/`, `launch/`,
`urdf/` ... in place); it has no executables zros can run.
"""
from __future__ import annotations

import functools
import hashlib
import os
import sys
import threading
import types
import xml.etree.ElementTree as ElementTree
from dataclasses import dataclass, field
from pathlib import Path

from zros.errors import ZrosError

__all__ = ['RosPackage', 'SetupPyError', 'find_source_packages', 'read_setup_py', 'source_package',
           'prefix_packages', 'editable_source_dirs', 'share_tree_root', 'install_prefixes', 'RESOURCE_INDEX']

#: Folders colcon never looks into for packages.
_SKIPPED = frozenset({'build', 'install', 'log', '__pycache__', 'node_modules'})
#: Files that make colcon skip a folder and everything below it.
_IGNORE_MARKERS = ('COLCON_IGNORE', 'AMENT_IGNORE', 'CATKIN_IGNORE')
_MAX_DEPTH = 5
#: An install prefix's ament resource index; its `packages/` folder lists the installed packages.
RESOURCE_INDEX = Path('share') / 'ament_index' / 'resource_index'


class SetupPyError(ZrosError):
    """A package's setup.py could not be read."""


@dataclass
class RosPackage:
    """One ROS package: its name, where its share directory is, and its executables.

    Attributes:
        name: the package name (package.xml's `<name>`, or the index marker's).
        share: the share directory (`get_package_share_directory`).
        prefix: the install prefix (`get_package_prefix`): the directory holding `share/<name>`.
        executables: {executable: target}; a target is `module:function` (a console script)
            or the path of a script file (`lib/<pkg>/<exe>`).
        python_root: the folder to put on sys.path so the console scripts' modules import
            (a source package's own folder), or None.
        source: the source folder of a package found in source, else None.
    """

    name: str
    share: Path
    prefix: Path
    executables: dict[str, str] = field(default_factory=dict)
    python_root: Path | None = None
    source: Path | None = None

    @property
    def compiled(self) -> bool:
        """Whether its nodes are compiled ones zros cannot run (an ament_cmake package found in
        source, or an index entry with no scripts)."""
        return not self.executables and self.python_root is None


# -- package.xml ---------------------------------------------------------------------------------
def _manifest(folder: Path) -> tuple[str, str]:
    """(name, build type) from `folder/package.xml` (build type 'ament_cmake' when unsaid)."""
    path = folder / 'package.xml'
    try:
        root = ElementTree.parse(path).getroot()
    except (OSError, ElementTree.ParseError) as exc:
        raise SetupPyError(f'{path}: cannot read package.xml: {exc}') from None
    name = (root.findtext('name') or '').strip()
    if not name:
        raise SetupPyError(f'{path}: package.xml has no <name>')
    build_type = (root.findtext('export/build_type') or '').strip()
    if not build_type:
        build_type = 'ament_python' if (folder / 'setup.py').is_file() else 'ament_cmake'
    return name, build_type


# -- discovery, colcon's way -------------------------------------------------------------------
def find_source_packages(root: Path) -> list[Path]:
    """The package folders (holding `package.xml`) at or below `root`, as colcon finds them:
    not below a package, not in hidden, build/install/log or COLCON_IGNOREd folders."""
    found: list[Path] = []

    def walk(folder: Path, depth: int) -> None:
        if any((folder / marker).exists() for marker in _IGNORE_MARKERS):
            return
        if (folder / 'package.xml').is_file():
            found.append(folder)
            return
        if depth >= _MAX_DEPTH:
            return
        try:
            children = sorted(p for p in folder.iterdir() if p.is_dir())
        except OSError:
            return
        for child in children:
            if not child.name.startswith('.') and child.name not in _SKIPPED:
                walk(child, depth + 1)

    if root.is_dir():
        walk(root, 0)
    return found


# -- setup.py, read as colcon reads it -------------------------------------------------------------
_setup_lock = threading.Lock()


def _find_packages(where: str = '.', exclude: tuple = (), include: tuple = ('*',)) -> list[str]:
    """setuptools.find_packages for a setup.py read here (regular packages only)."""
    import fnmatch
    base = Path(where)
    found = []
    for init in sorted(base.rglob('__init__.py')):
        parts = init.parent.relative_to(base).parts
        if not parts or any(not p.isidentifier() for p in parts):
            continue
        name = '.'.join(parts)
        if any(fnmatch.fnmatchcase(name, pattern) for pattern in include) and \
                not any(fnmatch.fnmatchcase(name, pattern) for pattern in exclude):
            found.append(name)
    return found


def read_setup_py(folder: Path) -> dict:
    """The keyword arguments `folder/setup.py` passes to `setup()`.

    The file runs in its own folder (its `glob('launch/*')` reads the package's files) with
    `setuptools` and `distutils.core` standing in, so nothing is built or installed.

    Raises:
        SetupPyError: the file is missing, raises, or never calls setup().
    """
    path = folder / 'setup.py'
    try:
        text = path.read_text(encoding='utf-8')
    except OSError as exc:
        raise SetupPyError(f'{path}: cannot read: {exc.strerror}') from None
    captured: list[dict] = []
    stand_in = types.ModuleType('setuptools')
    stand_in.setup = lambda **kwargs: captured.append(kwargs)
    stand_in.find_packages = stand_in.find_namespace_packages = _find_packages
    core = types.ModuleType('distutils.core')
    core.setup = stand_in.setup
    names = ('setuptools', 'distutils.core')
    with _setup_lock:
        saved = {name: sys.modules.get(name) for name in names}
        saved_argv, saved_cwd = sys.argv, os.getcwd()
        sys.modules['setuptools'], sys.modules['distutils.core'] = stand_in, core
        sys.argv = [str(path)]
        try:
            os.chdir(folder)
            exec(compile(text, str(path), 'exec'), {'__name__': '__main__', '__file__': str(path)})  # noqa: S102
        except SystemExit:
            pass
        except Exception as exc:  # noqa: BLE001 - the user's file: any error is one line
            raise SetupPyError(f'{path}: {type(exc).__name__}: {exc}') from None
        finally:
            os.chdir(saved_cwd)
            sys.argv = saved_argv
            for name, module in saved.items():
                if module is None:
                    sys.modules.pop(name, None)
                else:
                    sys.modules[name] = module
    if not captured:
        raise SetupPyError(f'{path}: never calls setup()')
    return captured[-1]


def _console_scripts(entry_points: object) -> dict[str, str]:
    """{name: 'module:function'} from setup()'s `entry_points` (a dict of lists or of a string)."""
    if not isinstance(entry_points, dict):
        return {}
    scripts = entry_points.get('console_scripts', [])
    if isinstance(scripts, str):
        scripts = scripts.splitlines()
    found = {}
    for line in scripts:
        name, _, target = str(line).partition('=')
        if name.strip() and target.strip():
            found[name.strip()] = target.strip().split()[0]
    return found


# -- the share tree -------------------------------------------------------------------------------
def share_tree_root() -> Path:
    """Where the share trees of source packages are kept (`ZROS_CACHE_DIR`, else
    `$XDG_CACHE_HOME/zros`, else `~/.cache/zros`)."""
    base = os.environ.get('ZROS_CACHE_DIR')
    if base:
        return Path(base) / 'install'
    cache = os.environ.get('XDG_CACHE_HOME') or os.path.join(os.path.expanduser('~'), '.cache')
    return Path(cache) / 'zros' / 'install'


def _data_files(folder: Path, data_files: object) -> dict[Path, Path]:
    """{path under the prefix: source file} for setup()'s `data_files` (directories are
    walked, as setuptools installs them)."""
    wanted: dict[Path, Path] = {}
    for entry in data_files or ():
        if isinstance(entry, str):
            destination, sources = '', [entry]
        else:
            destination, sources = entry
        for source in sources:
            source_path = (folder / source).resolve()
            if source_path.is_file():
                wanted[Path(destination) / source_path.name] = source_path
            elif source_path.is_dir():
                for file in source_path.rglob('*'):
                    if file.is_file():
                        wanted[Path(destination) / source_path.name / file.relative_to(source_path)] = file
    return wanted


def _link(target: Path, link: Path) -> None:
    """`link` -> `target`, made atomically (several nodes may bring one tree up to date at once)."""
    try:
        if link.is_symlink() and os.readlink(link) == str(target):
            return
    except OSError:
        pass
    link.parent.mkdir(parents=True, exist_ok=True)
    temporary = link.with_name(f'.{link.name}.{os.getpid()}.{threading.get_ident()}')
    os.symlink(target, temporary)
    os.replace(temporary, link)


def _sync_tree(prefix: Path, wanted: dict[Path, Path]) -> None:
    """Make `prefix` hold exactly the links `wanted` asks for."""
    for relative, source in wanted.items():
        _link(source, prefix / relative)
    if not prefix.is_dir():
        return
    for path in sorted(prefix.rglob('*'), reverse=True):   # children before their folders
        relative = path.relative_to(prefix)
        try:
            if path.is_symlink() and relative not in wanted:
                path.unlink()
            elif path.is_dir() and not path.is_symlink() and not any(path.iterdir()):
                path.rmdir()
        except OSError:
            pass


def source_package(folder: Path) -> RosPackage:
    """The package in source folder `folder` (holding package.xml), its share tree up to date.

    Raises:
        SetupPyError: package.xml or setup.py cannot be read.
    """
    folder = folder.resolve()
    name, build_type = _manifest(folder)
    if build_type != 'ament_python' or not (folder / 'setup.py').is_file():
        return RosPackage(name, share=folder, prefix=folder.parent, source=folder)
    arguments = read_setup_py(folder)
    key = hashlib.sha1(str(folder).encode()).hexdigest()[:12]
    prefix = share_tree_root() / f'{name}-{key}'
    wanted = _data_files(folder, arguments.get('data_files'))
    wanted.setdefault(Path('share') / name / 'package.xml', folder / 'package.xml')
    _sync_tree(prefix, wanted)
    package_dir = arguments.get('package_dir') or {}
    python_root = folder / package_dir.get('', '.') if isinstance(package_dir, dict) else folder
    return RosPackage(name, share=prefix / 'share' / name, prefix=prefix,
                      executables=_console_scripts(arguments.get('entry_points')),
                      python_root=python_root.resolve(), source=folder)


# -- installed packages -------------------------------------------------------------------------
def editable_source_dirs() -> list[Path]:
    """The source folders of ROS packages installed with `pip install -e` in this environment."""
    import json
    from importlib import metadata
    found = []
    for dist in metadata.distributions():
        text = dist.read_text('direct_url.json')
        if not text:
            continue
        try:
            info = json.loads(text)
        except ValueError:
            continue
        url = info.get('url', '')
        if info.get('dir_info', {}).get('editable') and url.startswith('file://'):
            from urllib.parse import unquote, urlparse
            folder = Path(unquote(urlparse(url).path))
            if (folder / 'package.xml').is_file() and folder not in found:
                found.append(folder)
    return found


def install_prefixes() -> list[Path]:
    """AMENT_PREFIX_PATH's directories, then this Python environment's prefix."""
    prefixes = [Path(p) for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    prefixes.append(Path(sys.prefix))
    return prefixes


@functools.lru_cache(maxsize=8)
def _distribution_scripts(name: str) -> dict[str, str]:
    from importlib import metadata
    try:
        dist = metadata.distribution(name)
    except metadata.PackageNotFoundError:
        return {}
    return {ep.name: ep.value for ep in dist.entry_points if ep.group == 'console_scripts'}


def prefix_packages() -> list[RosPackage]:
    """The packages the ament resource index of each prefix lists (first prefix wins)."""
    found: dict[str, RosPackage] = {}
    for prefix in install_prefixes():
        markers = prefix / RESOURCE_INDEX / 'packages'
        if not markers.is_dir():
            continue
        for marker in sorted(markers.iterdir()):
            name = marker.name
            if name in found or name.startswith('.'):
                continue
            executables = dict(_distribution_scripts(name)) if prefix == Path(sys.prefix) else {}
            scripts = prefix / 'lib' / name
            if scripts.is_dir():
                executables.update({p.name: str(p) for p in sorted(scripts.iterdir())
                                    if p.is_file() and os.access(p, os.X_OK)})
            found[name] = RosPackage(name, share=prefix / 'share' / name, prefix=prefix, executables=executables)
    return list(found.values())
