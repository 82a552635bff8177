"""A policy as the command line names it, parsed once into a typed :class:`PolicySpec`.

A spec is one of four kinds:

* a built-in name: ``nearest``, ``fixed:0.75``, ``tour:4``, ``learned:models/model7.zip``, ... (these win
  over everything else: an installed policy called ``nearest`` is never used);
* ``FILE.py:CLASS``: a class (or factory) in a Python file, its path absolute or relative;
* ``MODULE:CLASS``: a class in a dotted module on the Python path (``my_pkg.policies:Greedy``);
* a bare name registered by an installed package under the entry-point group ``frontier_rl.policies``.

Parsing reads the text and checks a built-in policy's argument (a weight in [0, 1], a number of stops);
:func:`~frontier_rl.policies.make_policy` loads and checks what the other kinds name.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass, field, replace
from enum import StrEnum
from pathlib import Path

from frontier_rl.checked_values import check_weight
from frontier_rl.core.navigation.config import MAX_STOPS
from frontier_rl.errors import ConfigError, UnknownNameError, short_repr


class BuiltinPolicy(StrEnum):
    """The policies this project ships, as the command line names them (``fixed``, ``tour`` and
    ``learned`` with their argument: ``fixed:0.75``, ``tour:4``, ``learned:models/model7.zip``)."""

    NEAREST = "nearest"
    LARGEST = "largest"
    EXPLORE_LITE = "explore-lite"
    INFO_GAIN = "info-gain"
    RANDOM = "random"
    ORACLE = "oracle"
    TOUR = "tour"
    FIXED = "fixed"
    LEARNED = "learned"


_NEEDS_ARGUMENT = {
    BuiltinPolicy.FIXED: "fixed:W needs a weight in [0, 1]",
    BuiltinPolicy.LEARNED: "learned:PATH needs a model file",
}
"""Built-in policies that must be written ``NAME:ARGUMENT``, and what each needs."""

_TAKES_ARGUMENT = {**_NEEDS_ARGUMENT, BuiltinPolicy.TOUR: "tour:N needs a whole number of stops"}
"""Built-in policies that may be written ``NAME:ARGUMENT`` (``tour`` alone is ``tour:10``)."""

SIMPLE_POLICIES: tuple[str, ...] = tuple(p.value for p in BuiltinPolicy if p not in _NEEDS_ARGUMENT)
"""The built-in policies named without an argument."""

BUILTIN_NAMES: frozenset[str] = frozenset(p.value for p in BuiltinPolicy)
"""Every built-in policy's name (``fixed`` and ``learned`` without their argument)."""

TOUR_STOPS = 10
"""The stops of the tour ``tour`` plans without an argument (``tour`` is ``tour:10``)."""

POLICY_NAMES: tuple[str, ...] = (*SIMPLE_POLICIES, "fixed:W", "tour:N", "learned:PATH.zip")
"""The built-in policies as the command line's help lists them."""

ENTRY_POINT_GROUP = "frontier_rl.policies"
"""The entry-point group installed packages register policies under (name -> class or factory)."""

USER_POLICY_FORMS = "FILE.py:CLASS, MODULE:CLASS or an installed policy"
"""How error messages name the ways to give a policy of one's own."""

_DOTTED = re.compile(r"^[A-Za-z_]\w*(\.[A-Za-z_]\w*)*$")


def unknown_policy(spec: str, installed: str = "") -> UnknownNameError:
    """The error for a spec that names no policy, listing the built-in ones and the other forms
    (and ``installed``: the names installed packages register, when known)."""
    more = f" ({installed})" if installed else ""
    return UnknownNameError(
        f"unknown policy {short_repr(spec)}; choose one of {', '.join(POLICY_NAMES)}, {USER_POLICY_FORMS}{more}"
    )


class PolicyKind(StrEnum):
    """Where a policy comes from."""

    BUILTIN = "builtin"
    FILE = "file"
    MODULE = "module"
    ENTRY_POINT = "entry-point"


@dataclass(frozen=True)
class PolicySpec:
    """A parsed policy spec (see the module docstring for the four kinds). A built-in policy's argument
    is checked and typed when the spec is made: :attr:`builtin`, :attr:`weight`, :attr:`stops`.

    Attributes:
        kind: where the policy comes from.
        name: a built-in policy's name (``fixed``, ``learned``, ``nearest``, ...); a policy file's path as
            given; a module's dotted name; an entry point's name.
        argument: a built-in policy's argument as written (``0.75``, ``4``, a model file; "" for none); for
            a file or a module, the name of the class or factory in it (dotted for a nested one); "" for an
            entry point.
        builtin: the built-in policy; None for the user's own.
        weight: ``fixed:W``'s weight W, in [0, 1]; None for any other policy.
        stops: ``tour:N``'s number of stops N (:data:`TOUR_STOPS` for ``tour``); None for any other policy.

    Raises:
        ConfigError: a built-in policy whose argument is missing or bad (naming the spec).
        UnknownNameError: a built-in kind whose name is no built-in policy, or that takes no argument
            and has one.
    """

    kind: PolicyKind
    name: str
    argument: str = ""
    builtin: BuiltinPolicy | None = field(init=False, repr=False)
    weight: float | None = field(init=False, repr=False)
    stops: int | None = field(init=False, repr=False)

    def __post_init__(self) -> None:
        builtin = _builtin(self) if self.kind is PolicyKind.BUILTIN else None
        object.__setattr__(self, "builtin", builtin)
        object.__setattr__(self, "weight", _weight(str(self)) if builtin is BuiltinPolicy.FIXED else None)
        object.__setattr__(self, "stops", _stops(str(self)) if builtin is BuiltinPolicy.TOUR else None)

    @classmethod
    def parse(cls, text: str) -> PolicySpec:
        """The spec ``text`` names (surrounding blanks ignored).

        Raises:
            ConfigError: ``fixed:``, ``tour:`` or ``learned:`` without its argument or with a bad one (a
                weight out of [0, 1], stops out of 1 to :data:`MAX_STOPS`), a file without its class, or a
                file or module without a valid class name after its last colon.
            UnknownNameError: text that is none of the four kinds (an empty one, ``nearest:3``, ...).
        """
        spec = text.strip()
        head, colon, tail = spec.partition(":")
        if head in _TAKES_ARGUMENT and colon and not tail.strip():
            raise ConfigError(f"{_TAKES_ARGUMENT[BuiltinPolicy(head)]}, got {short_repr(spec)}")
        if (head in _TAKES_ARGUMENT and colon) or spec in BUILTIN_NAMES:
            return cls(PolicyKind.BUILTIN, head, tail)
        if not spec:
            raise unknown_policy(spec)
        if not colon:
            if spec.endswith(".py") or "/" in spec:
                raise ConfigError(f"policy {short_repr(spec)} names a file: write FILE.py:CLASS")
            return cls(PolicyKind.ENTRY_POINT, spec)
        source, _, member = spec.rpartition(":")
        if source.endswith(".py"):
            kind = PolicyKind.FILE
        elif _DOTTED.match(source) and head not in SIMPLE_POLICIES:  # built-in names win: nearest:3 is no module
            kind = PolicyKind.MODULE
        else:
            raise unknown_policy(spec)
        if not _DOTTED.match(member):
            form = "FILE.py:CLASS" if kind is PolicyKind.FILE else "MODULE:CLASS"
            raise ConfigError(f"policy {short_repr(spec)} needs a class name after its last colon ({form})")
        return cls(kind, source, member)

    def __str__(self) -> str:
        return f"{self.name}:{self.argument}" if self.argument else self.name

    @property
    def file(self) -> Path | None:
        """The file the policy is read from: a policy file or a ``learned:`` model file; None otherwise."""
        if self.kind is PolicyKind.FILE:
            return Path(self.name)
        if self.builtin is BuiltinPolicy.LEARNED:
            return Path(self.argument)
        return None

    @property
    def canonical(self) -> str:
        """The spec written one way, to tell a method written two ways: a weight as a number
        (``fixed:1`` and ``fixed:1.0`` alike), a tour by its stops (``tour`` and ``tour:`` its :data:`TOUR_STOPS`), a
        policy or model file by its absolute path (a relative one resolved against the working folder)."""
        if self.weight is not None:
            return f"{BuiltinPolicy.FIXED.value}:{self.weight + 0.0!r}"  # -0.0 as 0.0
        if self.stops is not None:
            return f"{BuiltinPolicy.TOUR.value}:{self.stops}"
        path = self.file
        if path is None:
            return str(self)
        resolved = os.path.abspath(path)  # links not followed: a loop of them is refused where the file is read
        return str(replace(self, name=resolved) if self.kind is PolicyKind.FILE else replace(self, argument=resolved))

    @property
    def is_user_code(self) -> bool:
        """Whether the policy is code the user named (a file, a module or an installed package)."""
        return self.kind is not PolicyKind.BUILTIN

    def against(self, base_dir: Path) -> PolicySpec:
        """This spec with a relative policy or model file resolved against ``base_dir``."""
        path = self.file
        if path is None or path.is_absolute():
            return self
        resolved = str(base_dir / path)
        return replace(self, name=resolved) if self.kind is PolicyKind.FILE else replace(self, argument=resolved)


def _builtin(spec: PolicySpec) -> BuiltinPolicy:
    """The built-in policy ``spec`` names, its argument present where it needs one and absent where it
    takes none (its value is checked by :func:`_weight` and :func:`_stops`)."""
    text = str(spec)
    try:
        builtin = BuiltinPolicy(spec.name)
    except ValueError:
        raise unknown_policy(text) from None
    if spec.argument and builtin not in _TAKES_ARGUMENT:
        raise unknown_policy(text)
    if not spec.argument.strip() and (builtin in _NEEDS_ARGUMENT or spec.argument):
        raise ConfigError(f"{_TAKES_ARGUMENT[builtin]}, got {short_repr(text)}")
    return builtin


def _weight(text: str) -> float:
    """The weight of ``fixed:W`` (``text``), a number in [0, 1]."""
    try:
        weight = float(text.partition(":")[2])
    except ValueError:
        raise ConfigError(f"{_TAKES_ARGUMENT[BuiltinPolicy.FIXED]}, got {short_repr(text)}") from None
    try:
        return check_weight(weight)
    except ConfigError as exc:
        raise ConfigError(f"{short_repr(text)}: {exc}") from None


def _stops(text: str) -> int:
    """The stops of ``tour:N`` (``text``), a whole number from 1 to :data:`MAX_STOPS`; ``tour``'s
    :data:`TOUR_STOPS`."""
    _, colon, argument = text.partition(":")
    if not colon:
        return TOUR_STOPS
    if not (argument.isascii() and argument.isdigit()):
        raise ConfigError(f"{_TAKES_ARGUMENT[BuiltinPolicy.TOUR]}, got {short_repr(text)}")
    stops = int(argument) if len(argument.lstrip("0")) <= len(str(MAX_STOPS)) else MAX_STOPS + 1  # no 5000-digit int
    if not 1 <= stops <= MAX_STOPS:
        raise ConfigError(f"tour:N takes 1 to {MAX_STOPS} stops, got {short_repr(text)}")
    return stops
