"""A node's parameters: declarations, ROS 2's typing and range rules, callbacks and events.

Node's parameter methods delegate here. Every change, local or remote, goes through
`set_atomically`, so the rules, the user's callbacks and the /parameter_events message are
the same whichever way a value arrives.
"""
from __future__ import annotations

import copy
import math
import threading
import warnings
from typing import TYPE_CHECKING, Any, Callable

from zros.exceptions import (InvalidParameterException, InvalidParameterTypeException, InvalidParameterValueException,
                             ParameterAlreadyDeclaredException, ParameterImmutableException,
                             ParameterNotDeclaredException, ParameterUninitializedException)
from zros.parameter import Parameter, load_parameter_file, parameter_value_to_python, parse_parameter_value

if TYPE_CHECKING:
    from zros.node import Node

__all__ = ['ParameterStore', 'CALLBACK_STAGES']

#: When a set runs the user's callbacks: `pre_set` may change the list, `on_set` may reject it,
#: `post_set` sees what was set.
CALLBACK_STAGES = ('pre_set', 'on_set', 'post_set')

_FLOAT_TOLERANCE = 1e-6
T = Parameter.Type


def _descriptor_class():
    from interfaces.rcl_interfaces.msg import ParameterDescriptor
    return ParameterDescriptor


def _value_class():
    from interfaces.rcl_interfaces.msg import ParameterValue
    return ParameterValue


def _result(successful: bool, reason: str = ''):
    from interfaces.rcl_interfaces.msg import SetParametersResult
    return SetParametersResult(successful=successful, reason=reason)


def _parameter(name: str, value: Any) -> Parameter:
    """A Parameter from a declared default or an override (a value, or a Parameter)."""
    if isinstance(value, Parameter):
        value = value.value
    try:
        return Parameter(name, value=value)
    except TypeError as exc:
        raise InvalidParameterValueException(name, value, str(exc)) from None


class ParameterStore:
    def __init__(self, node: 'Node', *, overrides: dict[str, Any], allow_undeclared: bool) -> None:
        self._node = node
        self._lock = threading.RLock()
        self._values: dict[str, Parameter] = {}
        self._descriptors: dict[str, Any] = {}
        self.overrides = overrides
        self.allow_undeclared = allow_undeclared
        #: The user's callbacks by stage (CALLBACK_STAGES), newest first as rclpy runs them.
        self._callbacks: dict[str, list[Callable]] = {stage: [] for stage in CALLBACK_STAGES}
        self._events = None  # publisher of /parameter_events, set by the node

    @staticmethod
    def collect_overrides(node_fqn: str, arg_sets: list, explicit: list[Parameter] | None) -> dict[str, Any]:
        """Overrides in ROS 2's order: `-p` values and parameter files as the command line
        gives them (a later one wins), then the constructor's list."""
        values: dict[str, Any] = {}
        for args in reversed(arg_sets):  # global arguments first, the node's own win
            for source in args.parameter_sources:
                if isinstance(source, str):
                    values.update(load_parameter_file(source, node_fqn))
                else:
                    values[source[0]] = parse_parameter_value(source[1])
        for param in explicit or []:
            values[param.name] = param.value
        return values

    # -- declaration -----------------------------------------------------------------------
    def declare(self, name: str, value: Any = None, descriptor: Any = None, ignore_override: bool = False) -> Parameter:
        with self._lock:
            if name in self._values:
                raise ParameterAlreadyDeclaredException([name])
            if not isinstance(name, str):
                raise TypeError(f'a parameter name must be a str, got {type(name).__name__} {name!r}')
            if not name:
                raise InvalidParameterException(name)
            if descriptor is not None and not isinstance(descriptor, _descriptor_class()):
                raise TypeError(f"the descriptor of parameter '{name}' must be an rcl_interfaces/msg/"
                                f'ParameterDescriptor, got {type(descriptor).__name__}')
            name_only = value is None and descriptor is None
            descriptor = descriptor if descriptor is not None else _descriptor_class()()
            descriptor.name = name
            if name_only:
                warnings.warn(f"declaring parameter '{name}' by its name alone is deprecated (as in rclpy): "
                              'give a default value, a Parameter.Type, or a descriptor with '
                              'dynamic_typing=True', UserWarning, stacklevel=4)
                descriptor.dynamic_typing = True
            if isinstance(value, _value_class()):
                value = parameter_value_to_python(value)
            if isinstance(value, Parameter.Type):
                if value == T.NOT_SET:
                    raise ValueError(f"parameter '{name}' cannot be statically typed as NOT_SET")
                if descriptor.dynamic_typing:
                    raise ValueError(f"parameter '{name}' is given a type and a descriptor with dynamic_typing")
                declared_type, value = value, None
            else:
                declared_type = None
                if value is None and not descriptor.dynamic_typing:
                    raise ValueError(f"parameter '{name}' is statically typed but its default is NOT_SET: "
                                     'give a value or a Parameter.Type, or use dynamic_typing')
            param = _parameter(name, value)
            if declared_type is None and not descriptor.dynamic_typing and param.type_ != T.NOT_SET:
                declared_type = param.type_   # as rclpy: the default's type is the parameter's type
            if not ignore_override and name in self.overrides:
                param = _parameter(name, self.overrides[name])
            if declared_type is not None and param.type_ != T.NOT_SET and param.type_ != declared_type:
                if not (declared_type == T.DOUBLE and param.type_ == T.INTEGER):
                    raise InvalidParameterTypeException(param, declared_type.name)
                param = Parameter(name, T.DOUBLE, float(param.value))
            if not descriptor.dynamic_typing:
                descriptor.type = int(declared_type if declared_type is not None else param.type_)
            result = self.set_atomically([param], descriptors={name: descriptor}, declaring=True)
            if not result.successful:
                raise InvalidParameterValueException(name, param.value, result.reason)
            return self._values[name]

    def undeclare(self, name: str) -> None:
        with self._lock:
            if name not in self._values:
                raise ParameterNotDeclaredException([name])
            if self._descriptors[name].read_only:
                raise ParameterImmutableException([name])
            del self._values[name]
            del self._descriptors[name]
        self._publish_event(deleted=[Parameter(name)])

    def set_descriptor(self, name: str, descriptor: Any, alternative: Parameter | None = None) -> Parameter:
        """Give a declared parameter a new descriptor (rclpy's Node.set_descriptor).

        The descriptor takes the parameter's name and, when it types dynamically or names no
        type, the value's type. The current value is kept if it meets the new descriptor, else
        `alternative` replaces it. Like a declaration, this runs no set-parameters callbacks.

        :return: The parameter after the change (NOT_SET for an undeclared one, when allowed).
        :raises ParameterNotDeclaredException: If it is not declared (and undeclared are not allowed).
        :raises ParameterImmutableException: If its current descriptor is read-only.
        :raises InvalidParameterValueException: If neither value meets the descriptor.
        """
        with self._lock:
            if name not in self._values:
                if self.allow_undeclared:
                    return Parameter(name, T.NOT_SET, None)
                raise ParameterNotDeclaredException([name])
            if self._descriptors[name].read_only:
                raise ParameterImmutableException([name])
            candidates = [self._values[name]] if alternative is None else [self._values[name], alternative]
            for param in candidates:
                fitted = copy.copy(descriptor)
                fitted.name = name
                if fitted.dynamic_typing or fitted.type == T.NOT_SET:
                    fitted.type = int(param.type_)
                result = self.set_atomically([param], descriptors={name: fitted}, declaring=True)
                if result.successful:
                    return self._values[name]
            raise InvalidParameterValueException(name, candidates[-1].value, result.reason)

    # -- reads -----------------------------------------------------------------------------
    def has(self, name: str) -> bool:
        return name in self._values

    def get(self, name: str) -> Parameter:
        param = self._values.get(name)
        if param is None:
            if self.allow_undeclared:
                return Parameter(name, T.NOT_SET, None)
            raise ParameterNotDeclaredException([name])
        if param.type_ == T.NOT_SET and self._descriptors[name].type != T.NOT_SET:
            raise ParameterUninitializedException(name)
        return param

    def get_or(self, name: str, alternative: Parameter | None = None) -> Parameter:
        """The parameter, or `alternative` if it is undeclared or has no value yet."""
        param = self._values.get(name)
        if param is None or param.type_ == T.NOT_SET:
            return alternative if alternative is not None else Parameter(name, T.NOT_SET)
        return param

    def names(self) -> list[str]:
        return sorted(self._values)

    def describe(self, name: str) -> Any:
        if name not in self._descriptors:
            if self.allow_undeclared:
                return _descriptor_class()()   # as rclpy: a blank descriptor, not even the name
            raise ParameterNotDeclaredException([name])
        return self._descriptors[name]

    def list(self, prefixes: list[str], depth: int) -> tuple[list[str], list[str]]:
        """(names, prefixes) as rclpy's list_parameters and the ListParameters service answer.

        Without prefixes, a name is listed if it has fewer than `depth` dots; under a prefix,
        if it is the prefix or below it with fewer than `depth` dots after it. Depth 0
        (DEPTH_RECURSIVE) lists at any depth.
        """
        def shallow(rest: str) -> bool:
            return not depth or rest.count('.') < depth

        def wanted(name: str) -> bool:
            if not prefixes:
                return shallow(name)
            return any(name == p or (name.startswith(p + '.') and shallow(name[len(p) + 1:])) for p in prefixes)

        names = [name for name in self._values if wanted(name)]
        found_prefixes = dict.fromkeys(name.rsplit('.', 1)[0] for name in names if '.' in name)
        return names, list(found_prefixes)

    # -- callbacks -------------------------------------------------------------------------
    def add_callback(self, stage: str, callback: Callable) -> None:
        """Register `callback` for one of CALLBACK_STAGES; it runs before those added earlier."""
        self._callbacks[stage].insert(0, callback)

    def remove_callback(self, stage: str, callback: Callable) -> None:
        """Unregister `callback` from `stage` (only there: one function may serve two stages).

        Raises:
            ValueError: it is not registered for that stage.
        """
        try:
            self._callbacks[stage].remove(callback)
        except ValueError:
            raise ValueError(f'callback is not registered as a {stage} parameters callback') from None

    def callbacks(self, stage: str) -> tuple[Callable, ...]:
        """The callbacks of `stage`, in the order they run (a snapshot)."""
        return tuple(self._callbacks[stage])

    # -- writes ----------------------------------------------------------------------------
    def set_each(self, parameters: list[Parameter], *, raise_undeclared: bool = False) -> list[Any]:
        return [self.set_atomically([p], raise_undeclared=raise_undeclared) for p in parameters]

    def set_atomically(self, parameters: list[Parameter], *, descriptors: dict | None = None,
                       declaring: bool = False, raise_undeclared: bool = False) -> Any:
        """Apply all or none of `parameters`; a SetParametersResult says which and why.

        :param raise_undeclared: Raise ParameterNotDeclaredException for an undeclared name (as
            rclpy's Node methods do) instead of failing the result (as the services do). The
            names are checked after the pre-set callbacks, which may add some.
        """
        with self._lock:
            if self._callbacks['pre_set'] and not declaring:
                for callback in self._callbacks['pre_set']:
                    parameters = callback(list(parameters))
                if not parameters:
                    return _result(False, 'parameter list cannot be empty, this might be due to '
                                          'pre_set_parameters_callback modifying the original parameters list.')
            if raise_undeclared and not self.allow_undeclared:
                missing = [p.name for p in parameters if p.name not in self._values]
                if missing:
                    raise ParameterNotDeclaredException(missing)
            staged: list[tuple[Parameter, Any]] = []
            for param in parameters:
                descriptor = (descriptors or {}).get(param.name) or self._descriptors.get(param.name)
                if descriptor is None:
                    if not self.allow_undeclared:
                        return _result(False, f"parameter '{param.name}' is not declared")
                    descriptor = _descriptor_class()(name=param.name, dynamic_typing=True)
                if (param.type_ == T.INTEGER and descriptor.type == T.DOUBLE
                        and not descriptor.dynamic_typing):
                    param = Parameter(param.name, T.DOUBLE, float(param.value))  # `set x 2` on a double
                reason = self._check(param, descriptor, declaring)
                if reason:
                    return _result(False, reason)
                staged.append((param, descriptor))
            for callback in self._callbacks['on_set']:
                result = callback([p for p, _ in staged])
                if result is None or not getattr(result, 'successful', False):
                    return result if result is not None else _result(False, 'on_set_parameters_callback returned None')
            new, changed, deleted = [], [], []
            for param, descriptor in staged:
                if param.type_ == T.NOT_SET and not declaring:
                    if param.name in self._values:
                        del self._values[param.name]
                        del self._descriptors[param.name]
                        deleted.append(param)
                    continue
                (changed if param.name in self._values else new).append(param)
                self._values[param.name] = param
                self._descriptors[param.name] = descriptor
        self._publish_event(new=new, changed=changed, deleted=deleted)
        if not declaring:
            for callback in self._callbacks['post_set']:
                callback([p for p, _ in staged])
        return _result(True)

    @staticmethod
    def _check(param: Parameter, descriptor: Any, declaring: bool) -> str:
        """Why `param` may not be set under `descriptor` ('' when it may)."""
        if descriptor.read_only and not declaring:
            return f'Trying to set a read-only parameter: {param.name}.'
        if param.type_ == T.NOT_SET:
            # Setting NOT_SET undeclares; a statically typed parameter stays (as rclpy).
            return '' if declaring or descriptor.dynamic_typing else 'Static parameter cannot be undeclared'
        if not descriptor.dynamic_typing and descriptor.type not in (T.NOT_SET, param.type_):
            return (f'Wrong parameter type, parameter {{{param.name}}} is of type {{{T(descriptor.type).name}}}, '
                    f'setting it to {{{param.type_.name}}} is not allowed.')
        if param.type_ == T.INTEGER and len(descriptor.integer_range):
            rng = descriptor.integer_range[0]
            value = param.value
            if not rng.from_value <= value <= rng.to_value:
                return f'Parameter {param.name} out of range. Min: {rng.from_value}, Max: {rng.to_value}'
            if rng.step and value != rng.to_value and (value - rng.from_value) % rng.step:
                return (f'The parameter value ({value}) is not a valid step from {rng.from_value} '
                        f'with step {rng.step}')
        if param.type_ == T.DOUBLE and len(descriptor.floating_point_range):
            rng = descriptor.floating_point_range[0]
            value = param.value
            if not (rng.from_value - _FLOAT_TOLERANCE <= value <= rng.to_value + _FLOAT_TOLERANCE):
                return f'Parameter {param.name} out of range. Min: {rng.from_value}, Max: {rng.to_value}'
            if rng.step and not math.isclose(value, rng.to_value, abs_tol=_FLOAT_TOLERANCE):
                steps = (value - rng.from_value) / rng.step
                if abs(steps - round(steps)) * rng.step > _FLOAT_TOLERANCE:
                    return (f'The parameter value ({value}) is not a valid step from {rng.from_value} '
                            f'with step {rng.step}')
        return ''

    # -- events ----------------------------------------------------------------------------
    def attach_event_publisher(self, publisher: Any) -> None:
        self._events = publisher

    def _publish_event(self, new: list = (), changed: list = (), deleted: list = ()) -> None:
        if self._events is None or not (new or changed or deleted):
            return
        from interfaces.rcl_interfaces.msg import ParameterEvent
        event = ParameterEvent(node=self._node.get_fully_qualified_name(),
                               new_parameters=[p.to_parameter_msg() for p in new],
                               changed_parameters=[p.to_parameter_msg() for p in changed],
                               deleted_parameters=[p.to_parameter_msg() for p in deleted])
        event.stamp = self._node.get_clock().now().to_msg()
        try:
            self._events.publish(event)
        except Exception:  # noqa: BLE001 - events are best effort once the node is going away
            pass
