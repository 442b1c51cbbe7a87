"""Substitutions (launch.substitutions): values computed while the launch resolves.

Each class is the Python spelling of a YAML substitution and builds the same template:
`LaunchConfiguration('x', default='y')` is `$(var x y)`, `FindPackageShare('p')` is
`$(find-pkg-share p)`, `Command(['xacro ', path])` is `$(command 'xacro PATH')`. Arguments are
what launch calls SomeSubstitutionsType: a string (literal), a Substitution, or a list of
them concatenated.
"""
from __future__ import annotations

from typing import Any, ClassVar, Iterable

from zros.launch.errors import LaunchError, SubstitutionError
from zros.launch.files import module_getattr
from zros.launch.template import Call, Substitution, Template, is_static, to_template

__all__ = [
    'Substitution', 'SubstitutionFailure', 'TextSubstitution', 'LaunchConfiguration', 'EnvironmentVariable',
    'PathJoinSubstitution', 'PythonExpression', 'Command', 'FindExecutable', 'ThisLaunchFile',
    'ThisLaunchFileDir', 'AnonName', 'NotSubstitution', 'AndSubstitution', 'OrSubstitution', 'AllSubstitution',
    'AnySubstitution', 'EqualsSubstitution', 'NotEqualsSubstitution', 'IfElseSubstitution', 'LaunchLogDir',
    'FileContent', 'substitution_of_call', 'substitutions_of',
]

__getattr__ = module_getattr(__name__)

#: launch's name for a failed substitution.
SubstitutionFailure = SubstitutionError


class _CallSubstitution(Substitution):
    """A substitution that is one call of a registered template function."""

    _name = ''
    _aliases: ClassVar[tuple[str, ...]] = ()   # other `$(...)` names of the same substitution
    _by_name: ClassVar[dict[str, type['_CallSubstitution']]] = {}   # `$(name)` -> its class

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        for name in filter(None, (cls._name, *cls._aliases)):
            _CallSubstitution._by_name.setdefault(name, cls)

    def __init__(self, *args: Any) -> None:
        self._args: tuple[Template, ...] = tuple(to_template(arg) for arg in args)

    def template(self) -> Template:
        return (Call(self._name, self._args),)


def substitutions_of(template: Template) -> list[Substitution]:
    """launch's form of a template: one substitution per part, literal text as TextSubstitution."""
    return [TextSubstitution(text=part) if isinstance(part, str)
            else part if isinstance(part, Substitution)
            else substitution_of_call(part) for part in template]


def substitution_of_call(call: Call) -> Substitution:
    """The Python substitution a parsed `$(name args...)` is: an instance of its class when
    zros has one (`$(env X)` is an EnvironmentVariable), built from the parsed arguments
    without going through the class's keyword arguments."""
    cls = _CallSubstitution._by_name.get(call.name, _CallSubstitution)
    substitution = cls.__new__(cls)
    substitution._name = call.name
    substitution._args = call.args
    return substitution


class TextSubstitution(Substitution):
    """`TextSubstitution(text='...')`: literal text."""

    def __init__(self, *, text: str) -> None:
        self.text = text

    def template(self) -> Template:
        return to_template(self.text)


class LaunchConfiguration(_CallSubstitution):
    """`LaunchConfiguration('name', default=...)`: a launch argument or configuration (`$(var)`)."""

    _name = 'var'

    def __init__(self, variable_name: Any, *, default: Any = None) -> None:
        super().__init__(variable_name, *(() if default is None else (default,)))
        self.variable_name = variable_name


class EnvironmentVariable(_CallSubstitution):
    """`EnvironmentVariable('NAME', default_value=...)` (`$(env)`): an error when unset without
    a default."""

    _name = 'env'

    def __init__(self, name: Any, *, default_value: Any = None) -> None:
        super().__init__(name, *(() if default_value is None else (default_value,)))

    @property
    def name(self) -> list[Substitution]:
        """The variable's name, as launch keeps it: a list of substitutions."""
        return substitutions_of(self._args[0])

    @property
    def default_value(self) -> list[Substitution] | None:
        return substitutions_of(self._args[1]) if len(self._args) > 1 else None


class PathJoinSubstitution(_CallSubstitution):
    """`PathJoinSubstitution([a, 'b', c])`: the parts joined with the path separator."""

    _name = 'path-join'

    def __init__(self, substitutions: Iterable[Any]) -> None:
        if isinstance(substitutions, (str, Substitution)):
            substitutions = [substitutions]
        super().__init__(*substitutions)

    def __truediv__(self, other: Any) -> 'PathJoinSubstitution':
        joined = PathJoinSubstitution([self])
        joined._args = (*self._args, to_template(other))
        return joined


class PythonExpression(_CallSubstitution):
    """`PythonExpression(['1 + ', LaunchConfiguration('n')], python_modules=['math'])` (`$(eval)`):
    a Python expression with the listed modules in scope (math's names also bare), evaluated in
    zros's restricted scope (see docs/launch.md)."""

    _name = 'eval'

    def __init__(self, expression: Any, python_modules: Any = ('math',)) -> None:
        modules = [python_modules] if isinstance(python_modules, (str, Substitution)) else list(python_modules)
        if modules == ['math']:   # the default: `$(eval EXPR)`
            super().__init__(expression)
            return
        separated = [part for index, module in enumerate(modules) for part in ([','] if index else []) + [module]]
        super().__init__(expression, separated)

    @property
    def expression(self) -> list[Substitution]:
        return substitutions_of(self._args[0])

    @property
    def python_modules(self) -> list[Substitution]:
        """One substitution per module, as launch keeps them (`$(eval EXPR 'a, b')` has two)."""
        if len(self._args) < 2:
            return [TextSubstitution(text='math')]
        if is_static(self._args[1]):
            names = ''.join(self._args[1]).replace(',', ' ').split()
            return [TextSubstitution(text=name) for name in names]
        return substitutions_of(self._args[1])

    def describe(self) -> str:
        """launch's spelling, `PythonExpr('ceil(x)', ['math'])` (templates print `$(eval ...)`)."""
        expression = ' + '.join(_quoted_describe(part) for part in self.expression)
        modules = ', '.join(_quoted_describe(module) for module in self.python_modules)
        return f'PythonExpr({expression}, [{modules}])'


def _quoted_describe(substitution: Substitution) -> str:
    """How launch describes a part: literal text in quotes, a substitution by its describe()."""
    return f"'{substitution.text}'" if isinstance(substitution, TextSubstitution) else substitution.describe()


class Command(_CallSubstitution):
    """`Command(['xacro ', path], on_stderr='fail')` (`$(command)`): the command's stdout; the
    command line is split like a shell would, and is killed after 60 s."""

    _name = 'command'

    def __init__(self, command: Any, *, on_stderr: Any = 'fail') -> None:
        super().__init__(command, *(() if on_stderr == 'fail' else (on_stderr,)))


class FindExecutable(_CallSubstitution):
    """`FindExecutable(name='xacro')` (`$(find-exec)`): the full path of a program on PATH."""

    _name = 'find-exec'

    def __init__(self, *, name: Any) -> None:
        super().__init__(name)


class ThisLaunchFile(_CallSubstitution):
    """The path of the launch file being read (`$(filename)`)."""

    _name = 'filename'


class ThisLaunchFileDir(_CallSubstitution):
    """The directory of the launch file being read (`$(dirname)`)."""

    _name = 'dirname'


class AnonName(_CallSubstitution):
    """`AnonName('name')` (`$(anon)`): a name made unique for this launch."""

    _name = 'anon'

    def __init__(self, name: Any) -> None:
        super().__init__(name)


class NotSubstitution(_CallSubstitution):
    """'true' when the value is false (`$(not)`)."""

    _name = 'not'

    def __init__(self, value: Any) -> None:
        super().__init__(value)


class AndSubstitution(_CallSubstitution):
    """'true' when both are true (`$(and)`)."""

    _name = 'and'

    def __init__(self, left: Any, right: Any) -> None:
        super().__init__(left, right)


class OrSubstitution(_CallSubstitution):
    """'true' when either is true (`$(or)`)."""

    _name = 'or'

    def __init__(self, left: Any, right: Any) -> None:
        super().__init__(left, right)


class AllSubstitution(_CallSubstitution):
    """'true' when every argument is true (`$(all)`)."""

    _name = 'all'


class AnySubstitution(_CallSubstitution):
    """'true' when any argument is true (`$(any)`)."""

    _name = 'any'


class EqualsSubstitution(_CallSubstitution):
    """'true' when both are equal as bools, numbers or text (`$(equals)`)."""

    _name = 'equals'

    def __init__(self, left: Any, right: Any) -> None:
        super().__init__('' if left is None else left, '' if right is None else right)   # None is ''


class NotEqualsSubstitution(EqualsSubstitution):
    """'true' when they differ (`$(not-equals)`)."""

    _name = 'not-equals'


class IfElseSubstitution(_CallSubstitution):
    """`IfElseSubstitution(condition, if_value, else_value)` (`$(if)`)."""

    _name = 'if'

    def __init__(self, condition: Any, if_value: Any = '', else_value: Any = '') -> None:
        if if_value == else_value == '':
            raise LaunchError('IfElseSubstitution: give if_value, else_value or both')   # launch's RuntimeError
        super().__init__(condition, if_value, else_value)


class LaunchLogDir(_CallSubstitution):
    """This run's log directory (`$(log_dir)`, also `$(launch_log_dir)`)."""

    _name = 'log_dir'
    _aliases = ('launch_log_dir',)


class FileContent(_CallSubstitution):
    """`FileContent(path)` (`$(file-content)`): the text of a file."""

    _name = 'file-content'

    def __init__(self, path: Any) -> None:
        super().__init__(path)
