"""Values from untrusted places (YAML files, ROS parameters, the command line) checked against the
type they must have, with a one-line error that names where they came from."""

from __future__ import annotations

import math
import numbers
from enum import Enum
from typing import Any, TypeVar

from frontier_rl.errors import ConfigError, short_repr

_E = TypeVar("_E", bound=Enum)


def enum_member(kind: type[_E], value: object, where: str) -> _E:
    """The member of ``kind`` whose value is ``value``.

    Raises:
        ConfigError: naming ``where``, quoting ``value`` and listing the values ``kind`` has.
    """
    try:
        return kind(value)
    except ValueError:
        names = ", ".join(str(member.value) for member in kind)
        raise ConfigError(f"{where} must be one of {names}, got {short_repr(value)}") from None


def python_integer(value: object) -> object:
    """``value`` as Python's ``int`` where it is another kind of integer (a NumPy one), else as it
    is: a check that asks for an ``int`` then takes it, and refuses a ``bool`` as before."""
    if isinstance(value, numbers.Integral) and not isinstance(value, bool | int):
        return int(value)
    return value


def check_weight(weight: float) -> float:
    """``weight`` (eq. 3.1's w) as a float, or a :class:`ConfigError` if it is not in [0, 1]."""
    w = float(weight)
    if not (0.0 <= w <= 1.0):  # also rejects NaN
        raise ConfigError(f"weight must be in [0, 1], got {weight!r}")
    return w


def not_a_boolean(value: object) -> str:
    """What is wrong with ``value`` where a boolean must be: "must be true or false (a boolean), got ..."
    (text such as "false" named as text: it would be true)."""
    given = f"the text {short_repr(value)}" if isinstance(value, str) else short_repr(value)
    return f"must be true or false (a boolean), got {given}"


def coerce(hint: Any, value: Any, where: str) -> Any:
    """``value`` checked against type ``hint`` (bool, int, float, float | None, str, an Enum: the member
    of that value); others pass as they are.

    Raises:
        ConfigError: naming ``where`` and quoting ``value`` (cut to a bounded length).
    """
    if hint is bool:
        if not isinstance(value, bool):
            raise ConfigError(f"{where} {not_a_boolean(value)}")
        return value
    if hint is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise ConfigError(f"{where} must be an integer, got {short_repr(value)}")
        return value
    if hint == float | None:
        return None if value is None else coerce(float, value, where)
    if hint is float:
        if isinstance(value, bool) or not isinstance(value, int | float) or math.isnan(value):
            raise ConfigError(f"{where} must be a number, got {short_repr(value)}")
        return float(value)
    if isinstance(hint, type) and issubclass(hint, Enum):
        return enum_member(hint, value, where)
    if hint is str:
        if not isinstance(value, str):
            raise ConfigError(f"{where} must be a string, got {short_repr(value)}")
        return value
    return value
