"""nav2_common.launch: substitutions that rewrite a parameter file while the launch resolves.

- `RewrittenYaml(source_file, param_rewrites, root_key=None, key_rewrites=None,
  convert_types=False)`: a copy of a YAML parameter file with values replaced (by leaf name or
  by dotted path), added (dotted paths through `ros__parameters`), keys renamed, and the whole
  put under `root_key` (a namespace) when it is not empty.
- `ReplaceString(source_file, replacements, condition=None)`: a copy of any text file with
  strings replaced, when the condition holds.
- `HasNodeParams(source_file, node_name)`: 'True' when the file holds parameters for that node.
- `ParseMultiRobotPose('robots').value()`: the robots and poses of `robots:="r1={x: 1.0}; ..."`.

Each performs to the path of the new file, kept in the launch's log directory.
"""
from zros.nav2_common.launch.has_node_params import HasNodeParams
from zros.nav2_common.launch.parse_multirobot_pose import ParseMultiRobotPose
from zros.nav2_common.launch.replace_string import ReplaceString
from zros.nav2_common.launch.rewritten_yaml import RewrittenYaml

__all__ = ['RewrittenYaml', 'ReplaceString', 'HasNodeParams', 'ParseMultiRobotPose']
