"""Upstream launch files, run unchanged: how many of the launch files ROS packages ship resolve
under `zros launch --print`, and the first line of each failure.

    python benchmarks/upstream_launch.py TREE [TREE ...] [--json out.json] [--only NAME]

Each TREE is a folder holding ROS packages as fetched (a repository checkout or `git archive` of
one branch: nav2_bringup and nav2_common of navigation2, turtlebot3_simulations,
turtlebot3, slam_toolbox, m-explore-ros2, geometry_tutorials ...). Nothing is fetched here and
nothing is copied into zros: the trees go on ZROS_NODE_PATH, where zros finds their packages as
colcon would (they shadow zros's own packages of the same names), and every launch file in a
package's `launch/` folder is planned with `python -m zros launch FILE --print` in a fresh
process. The packages' own files come from the tree; the nodes they start, and the packages
they include but the trees lack, come from zros. A launch file that requires an argument
without a default is given the value below (the map of turtlebot3_world, as a user would), and
TURTLEBOT3_MODEL is `burger` and LDS_MODEL `LDS-01`, as the courses export them.

A file passes when the plan resolves (exit 0). The table printed (and `--json`) lists each file
with `ok` or the first line of the error: what zros lacks, by name.
"""
from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO))

from zros.ament_index_python.ros_packages import find_source_packages  # noqa: E402

#: Values for arguments that launch files declare without a default (as a user passes them).
REQUIRED_ARGUMENTS = {
    'map': str(REPO / 'nodes' / 'turtlebot3_navigation2' / 'map' / 'map.yaml'),
    'namespace': '',
}
_REQUIRED = re.compile(r"[Rr]equired launch argument '(\w+)' was not given|launch configuration '(\w+)' is not set")
_LAUNCH_FILE = re.compile(r'.*(launch\.(py|xml|ya?ml)|_launch\.py)$')


def launch_files(package: Path) -> list[Path]:
    folder = package / 'launch'
    return sorted(p for p in folder.rglob('*') if p.is_file() and _LAUNCH_FILE.match(p.name)) if folder.is_dir() else []


def plan(path: Path, env: dict[str, str], log_dir: str) -> tuple[bool, str]:
    """(resolved, first error line) for one launch file, retrying with required arguments."""
    arguments: list[str] = []
    for _ in range(4):
        command = [sys.executable, '-m', 'zros', 'launch', str(path), *arguments, '--print', '--log-dir', log_dir]
        try:
            result = subprocess.run(command, env=env, capture_output=True, text=True, timeout=120,
                                    stdin=subprocess.DEVNULL)
        except subprocess.TimeoutExpired:
            return False, 'timed out after 120 s'
        if result.returncode == 0:
            return True, ''
        error = (result.stderr.strip().splitlines() or ['(no error line)'])[-1]
        missing = _REQUIRED.search(error)
        name = missing and (missing.group(1) or missing.group(2))
        if not name or name not in REQUIRED_ARGUMENTS:
            return False, error.replace(str(path.parent) + '/', '')
        arguments.append(f'{name}:={REQUIRED_ARGUMENTS[name]}')
    return False, error


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('trees', nargs='+', type=Path, help='folders holding fetched ROS packages')
    parser.add_argument('--json', help='write the results here')
    parser.add_argument('--only', help='only packages whose name contains this')
    args = parser.parse_args()
    packages = [folder for tree in args.trees for folder in find_source_packages(tree.resolve())]
    env = dict(os.environ, ZROS_NODE_PATH=os.pathsep.join(str(t.resolve()) for t in args.trees),
               TURTLEBOT3_MODEL=os.environ.get('TURTLEBOT3_MODEL', 'burger'),
               LDS_MODEL=os.environ.get('LDS_MODEL', 'LDS-01'))
    results = []
    with tempfile.TemporaryDirectory(prefix='upstream_launch_') as log_dir:
        env['ZROS_CACHE_DIR'] = str(Path(log_dir) / 'cache')
        for package in packages:
            if args.only and args.only not in package.name:
                continue
            for path in launch_files(package):
                ok, error = plan(path, env, log_dir)
                results.append({'package': package.name, 'file': str(path.relative_to(package)), 'ok': ok,
                                'error': error})
                print(f"{'ok  ' if ok else 'FAIL'} {package.name}/{path.relative_to(package)}"
                      + ('' if ok else f'\n     {error}'), flush=True)
    passed = sum(r['ok'] for r in results)
    print(f'\n{passed} of {len(results)} launch files resolve')
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=2))
    return 0


if __name__ == '__main__':
    sys.exit(main())
