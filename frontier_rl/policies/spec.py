"""A policy as the command line names it, parsed once into a typed :class:`PolicySpec`.

A spec is one of four kinds:

* a built-in name: ``nearest``, ``fixed:0.75``, ``tour:4``, ``learned:models/model7.zip``, ... (these win
  over everything else: an installed policy called ``nearest`` is never used);
* ``FILE.py:CLASS``: a class (or factory) in a Python file, its path absolute or relative;
* ``MODULE:CLASS``: a class in a dotted module on the Python path (``my_pkg.policies:Greedy``);
* a bare name registered by an installed package under the entry-point group ``frontier_rl.policies``.

Parsing only reads the text; :func:`~frontier_rl.policies.make_policy` loads and checks what it names.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, replace
from enum import StrEnum
from pathlib import Path

from frontier_rl.errors import ConfigError, UnknownNameError, short_repr

SIMPLE_POLICIES: tuple[str, ...] = ("nearest", "largest", "explore-lite", "info-gain", "random", "oracle", "tour")
"""The built-in policies named without an argument."""

_PARAMETERISED = {
    "fixed": "fixed:W needs a weight in [0, 1]",
    "tour": "tour:N needs a whole number of stops",
    "learned": "learned:PATH needs a model file",
}
"""Built-in policies written ``NAME:ARGUMENT`` (a weight, a number of stops, a model file), and what each needs."""

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
    """A parsed policy spec (see the module docstring for the four kinds).

    Attributes:
        kind: where the policy comes from.
        name: a built-in policy's name (``fixed``, ``learned``, ``nearest``, ...); a policy file's path as
            given; a module's dotted name; an entry point's name.
        argument: a built-in policy's argument (``0.75``, ``4``, a model file; "" for none); for a file or
            a module, the name of the class or factory in it (dotted for a nested one); "" for an entry point.
    """

    kind: PolicyKind
    name: str
    argument: str = ""

    @classmethod
    def parse(cls, text: str) -> PolicySpec:
        """The spec ``text`` names (surrounding blanks ignored).

        Raises:
            ConfigError: ``fixed:``, ``tour:`` or ``learned:`` without its argument, a file without its
                class, or a file or module without a valid class name after its last colon.
            UnknownNameError: text that is none of the four kinds (an empty one, ``nearest:3``, ...).
        """
        spec = text.strip()
        head, colon, tail = spec.partition(":")
        if head in _PARAMETERISED and colon and not tail.strip():
            raise ConfigError(f"{_PARAMETERISED[head]}, got {short_repr(spec)}")
        if (head in _PARAMETERISED and colon) or spec in (*SIMPLE_POLICIES, *_PARAMETERISED):
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
        if self.kind is PolicyKind.BUILTIN and self.name == "learned" and self.argument:
            return Path(self.argument)
        return None

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
