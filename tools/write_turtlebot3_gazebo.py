"""Write turtlebot3_gazebo's upstream-shaped files from zros's own sources (one geometry, two spellings).

    python tools/write_turtlebot3_gazebo.py      # rewrites nodes/turtlebot3_gazebo/{worlds,models,urdf}

- `worlds/NAME.world`: Gazebo world files of zros's YAML worlds (zros/sim/worlds/NAME.yaml);
- `models/turtlebot3_MODEL/model.sdf`, `model.config`: the TurtleBot3 with ROBOTIS's plugin and
  sensor elements (zros.sim.model_file's numbers);
- `urdf/turtlebot3_MODEL.urdf`: its links and joints for robot_state_publisher.
Run it after changing any of those sources; tests/unit/test_turtlebot3_gazebo_files.py checks
that the shipped files are what this writes and that they read back to the same worlds and robots.
"""
from __future__ import annotations

import sys
from pathlib import Path

from zros.sim import load_world, robot_spec
from zros.sim.model_file import turtlebot3_model
from zros.sim.model_writer import model_config, model_sdf, model_urdf
from zros.sim.sdf_writer import world_to_sdf

WORLDS = ('empty_world', 'turtlebot3_world', 'turtlebot3_house', 'turtlebot3_bighouse')
MODELS = ('burger', 'waffle', 'waffle_pi')
PACKAGE = Path(__file__).resolve().parent.parent / 'nodes' / 'turtlebot3_gazebo'


def files() -> dict[Path, str]:
    """Every file this tool writes (relative to the package) and its text."""
    out = {Path('worlds') / f'{name}.world': world_to_sdf(load_world(name), note=(
        f'written by zros (tools/write_turtlebot3_gazebo.py) from zros/sim/worlds/{name}.yaml; '
        'edit that file and rerun')) for name in WORLDS}
    note = 'written by zros (tools/write_turtlebot3_gazebo.py) from ROBOTIS\'s numbers in zros.sim; do not edit'
    for model in MODELS:
        folder = Path('models') / f'turtlebot3_{model}'
        out[folder / 'model.sdf'] = model_sdf(turtlebot3_model(model), note=note)
        out[folder / 'model.config'] = model_config(model, f'TurtleBot3 {model}, as zros simulates it')
        out[Path('urdf') / f'turtlebot3_{model}.urdf'] = model_urdf(robot_spec(model), note=note)
    return out


def main(args: list[str]) -> int:
    for relative, text in files().items():
        path = PACKAGE / relative
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding='utf-8')
        print(path)
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
