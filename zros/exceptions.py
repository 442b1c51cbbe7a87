"""The exceptions rclpy users catch by name (rclpy.exceptions), raised by zros's parameter API."""
from __future__ import annotations

from zros.errors import (InvalidHandle, InvalidNamespaceException, InvalidNodeNameException,
                         InvalidServiceNameException, InvalidTopicNameException, NotInitializedError, ZrosError)

__all__ = ['ParameterException', 'ParameterNotDeclaredException', 'ParameterAlreadyDeclaredException',
           'InvalidParameterException', 'InvalidParameterValueException', 'InvalidParameterTypeException',
           'ParameterImmutableException', 'ParameterUninitializedException', 'InvalidServiceNameException',
           'InvalidTopicNameException', 'InvalidNodeNameException', 'InvalidNamespaceException',
           'ROSInterruptException', 'NotInitializedException', 'InvalidHandle', 'NoTypeSupportImportedException']



# rclpy's name for what zros raises when an operation needs `zros.init()` first.
NotInitializedException = NotInitializedError


class ParameterException(ZrosError):
    def __init__(self, error_msg: str, parameters: object = None) -> None:
        super().__init__(error_msg if parameters is None else f'{error_msg}: {parameters}')


class ParameterNotDeclaredException(ParameterException):
    def __init__(self, parameters: object) -> None:
        super().__init__('Invalid access to undeclared parameter(s)', parameters)


class ParameterAlreadyDeclaredException(ParameterException):
    def __init__(self, parameters: object) -> None:
        super().__init__('Parameter(s) already declared', parameters)


class InvalidParameterException(ParameterException):
    def __init__(self, parameter: object) -> None:
        super().__init__('Invalid parameter name', parameter)


class InvalidParameterValueException(ParameterException):
    def __init__(self, parameter: object, value: object, reason: str) -> None:
        ZrosError.__init__(self, f"Invalid parameter value ({value!r}) for parameter '{parameter}'. Reason: {reason}")
        self.reason = reason


class InvalidParameterTypeException(ParameterException):
    def __init__(self, desired_parameter: object, expected_type: str) -> None:
        kind = getattr(desired_parameter, 'type_', None)
        ZrosError.__init__(self, f"Trying to set parameter '{getattr(desired_parameter, 'name', desired_parameter)}' "
                                 f"to '{getattr(desired_parameter, 'value', '?')}' of type "
                                 f"'{getattr(kind, 'name', kind)}', expecting type '{expected_type}'")


class ParameterImmutableException(ParameterException):
    def __init__(self, parameters: object) -> None:
        super().__init__('Attempted to modify read-only parameter', parameters)


class ParameterUninitializedException(ParameterException):
    def __init__(self, parameter_name: str) -> None:
        ZrosError.__init__(self, f"The parameter '{parameter_name}' is not initialized")


class ROSInterruptException(ZrosError):
    """`Rate.sleep()` was interrupted: the context shut down (a signal, `zros.shutdown()`)."""

    def __init__(self) -> None:
        super().__init__('zros was shut down while sleeping')


class NoTypeSupportImportedException(ZrosError):
    """A class declares type support (rclpy's `_TYPE_SUPPORT`) but none could be imported."""

    def __init__(self) -> None:
        super().__init__('no type_support imported')
