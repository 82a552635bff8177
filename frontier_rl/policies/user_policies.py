"""Policies of the user's own: a class in a Python file, in a module on the Python path, or registered
by an installed package under the entry-point group ``frontier_rl.policies``.

Naming code on the command line (``--policy my_policy.py:Greedy``) is the user's consent to run it;
a model file (``learned:``) never names code. The class (or factory) is called with no arguments and
must give an object with a ``name`` (str) and a ``rank(context, rng)`` method
(:class:`~frontier_rl.core.sim.episode.ExplorationPolicy`). Whatever goes wrong on the way (a missing
file, a syntax error, a module not found, no such class, an exception on import or construction, an
object that is not a policy) is one :class:`~frontier_rl.errors.FrontierRLError` line naming the spec.

An installed package registers a policy in its ``pyproject.toml``::

    [project.entry-points."frontier_rl.policies"]
    my-policy = "my_package.policies:MyPolicy"
"""

from __future__ import annotations

import hashlib
import importlib
import importlib.util
import inspect
import sys
from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache
from importlib.metadata import EntryPoint, entry_points
from pathlib import Path
from types import ModuleType
from typing import cast

from frontier_rl.core.sim.episode import ExplorationPolicy
from frontier_rl.errors import ConfigError, FrontierRLError, UnknownNameError, short_path, short_repr, short_text
from frontier_rl.file_digest import file_sha256
from frontier_rl.policies.spec import (
    BUILTIN_NAMES,
    ENTRY_POINT_GROUP,
    PolicyKind,
    PolicySpec,
    unknown_policy,
)

_FILE_MODULE_PREFIX = "frontier_rl_user_policy_"
"""Prefix of the ``sys.modules`` names policy files are loaded as (with a hash of their path)."""

PolicyFactory = Callable[[], object]
"""A class or function that, called with no arguments, gives a policy."""


@dataclass(frozen=True)
class UserPolicyInfo:
    """Where a user policy comes from, for a report.

    Attributes:
        origin: ``file PATH``, ``module NAME`` or ``package DIST VERSION (entry point NAME)``.
        member: the class or factory's name.
        summary: the first line of its docstring ("" if it has none).
    """

    origin: str
    member: str
    summary: str


def build_user_policy(spec: PolicySpec) -> ExplorationPolicy:
    """The policy a file, module or entry-point ``spec`` names: its factory called with no arguments.

    Raises:
        FrontierRLError: anything that stops it (see the module docstring), in one line.
    """
    factory = load_factory(spec)
    label = f"policy {short_repr(str(spec))}"
    shown = getattr(factory, "__name__", None) or spec.argument or spec.name
    try:
        policy = factory()
    except (Exception, SystemExit) as exc:  # the user's code may raise anything (sys.exit() too): one line
        raise ConfigError(f"{label}: calling {shown}() with no arguments raised {exception_line(exc)}") from None
    return checked_policy(policy, f"{label}: {shown}() gave")


def checked_policy(value: object, given: str = "got") -> ExplorationPolicy:
    """``value`` if it is a policy object: a ``name`` that is a non-blank string and a ``rank`` method.

    Args:
        value: the object to check.
        given: how the message starts, saying where ``value`` came from (``policy 'my.py:Greedy':
            Greedy() gave``); it goes on with what ``value`` is and what it lacks.

    Raises:
        ConfigError: ``value`` is not a policy (a class where an instance is needed, no name, no
            rank method), in one line.
    """
    if inspect.isclass(value):
        raise ConfigError(f"{given} {_kind(value)}, not a policy object: pass an instance, {value.__qualname__}()")
    try:
        name = getattr(value, "name", None)
    except (Exception, SystemExit) as exc:  # a property of the user's that raises
        raise ConfigError(f"{given} {_kind(value)}, whose name raised {exception_line(exc)}") from None
    if not isinstance(name, str) or not name.strip():
        raise ConfigError(f"{given} {_kind(value)}, not a policy: it needs a 'name' string")
    rank = getattr(value, "rank", None)
    if not callable(rank):
        raise ConfigError(f"{given} {_kind(value)}, not a policy: it needs a rank(context, rng) method")
    try:
        signature: inspect.Signature | None = inspect.signature(rank)
    except (TypeError, ValueError):  # a callable without a signature to read (a C function's)
        signature = None
    if signature is not None and not _takes_two_arguments(signature):
        raise ConfigError(f"{given} {_kind(value)}, whose rank{signature} cannot be called as rank(context, rng)")
    return cast(ExplorationPolicy, value)


def _takes_two_arguments(signature: inspect.Signature) -> bool:
    """Whether a callable of ``signature`` can be called with two positional arguments."""
    try:
        signature.bind(None, None)
    except TypeError:
        return False
    return True


def load_factory(spec: PolicySpec) -> PolicyFactory:
    """The class or factory ``spec`` names, loaded (its module imported) but not called."""
    if spec.kind is PolicyKind.ENTRY_POINT:
        return _entry_point_factory(spec)
    if spec.kind is PolicyKind.FILE:
        module = _file_module(spec)
    elif spec.kind is PolicyKind.MODULE:
        module = _import_module(spec)
    else:
        raise ConfigError(f"policy {short_repr(str(spec))} is built in, not user code")
    target: object = module
    for part in spec.argument.split("."):
        if not hasattr(target, part):
            found = ", ".join(_policy_classes(module)) or "none"
            raise UnknownNameError(
                f"policy {short_repr(str(spec))}: {_origin(spec)} has no {spec.argument!r} (classes with a rank "
                f"method there: {found})"
            )
        target = getattr(target, part)
    if not callable(target):
        raise ConfigError(f"policy {short_repr(str(spec))}: {spec.argument!r} is {_kind(target)}, not a class")
    return cast(PolicyFactory, target)


def describe_user_policy(spec: PolicySpec) -> UserPolicyInfo:
    """Where ``spec``'s policy comes from and the first line of its docstring (loads its module)."""
    factory = load_factory(spec)
    doc = inspect.getdoc(factory) or ""
    summary = doc.strip().splitlines()[0] if doc.strip() else ""
    if spec.kind is PolicyKind.ENTRY_POINT:
        point = _entry_point(spec)
        dist = point.dist
        where = f"package {dist.name} {dist.version}" if dist is not None else "an installed package"
        origin = f"{where} (entry point {point.name} = {point.value})"
    else:
        origin = _origin(spec)
    return UserPolicyInfo(origin, spec.argument or getattr(factory, "__qualname__", spec.name), summary)


def installed_policies() -> tuple[str, ...]:
    """The names installed packages register under :data:`ENTRY_POINT_GROUP`, sorted; a name of a
    built-in policy is left out (built-in names win)."""
    names = {point.name for point in entry_points(group=ENTRY_POINT_GROUP)}
    return tuple(sorted(names - BUILTIN_NAMES))


def user_policy_fingerprint(spec: PolicySpec) -> str:
    """What a user policy's results depend on besides its spec: a hash of the file's content for a
    file, of the module's source file for a module (when it is one), the distribution's name and
    version for an entry point ("" where none is known).

    A resumed experiment sees only these change: a ``MODULE:CLASS``'s hash covers the named module's
    file alone, not the modules it imports, and an entry point's version stays the same while the
    code of an editable install changes. Use a new results folder after changing such code."""
    if spec.kind is PolicyKind.FILE:
        return f"sha256:{file_sha256(_policy_file(spec))}"
    if spec.kind is PolicyKind.MODULE:
        origin = getattr(_import_module(spec), "__file__", None)
        return f"sha256:{file_sha256(Path(origin))}" if origin and Path(origin).is_file() else ""
    if spec.kind is PolicyKind.ENTRY_POINT:
        dist = _entry_point(spec).dist
        return f"dist:{dist.name}=={dist.version}" if dist is not None else ""
    return ""


def _policy_file(spec: PolicySpec) -> Path:
    path = Path(spec.name)
    if not path.exists():
        raise ConfigError(f"policy file {short_path(spec.name)} does not exist")
    if not path.is_file():
        raise ConfigError(f"policy file {short_path(spec.name)} is not a file")
    return path


def _file_module(spec: PolicySpec) -> ModuleType:
    """The policy file's module, executed once per process and version of the file."""
    path = _policy_file(spec).resolve()
    stat = path.stat()
    return _load_file(str(path), stat.st_size, stat.st_mtime_ns, spec.name)


@lru_cache(maxsize=32)
def _load_file(path: str, size: int, mtime_ns: int, shown: str) -> ModuleType:
    """Execute the file at ``path`` as a module of its own (``size`` and ``mtime_ns`` key its version)."""
    name = _FILE_MODULE_PREFIX + hashlib.sha256(path.encode()).hexdigest()[:16]
    module_spec = importlib.util.spec_from_file_location(name, path)
    if module_spec is None or module_spec.loader is None:
        raise ConfigError(f"policy file {short_path(shown)} cannot be loaded as Python")
    module = importlib.util.module_from_spec(module_spec)
    sys.modules[name] = module  # dataclasses and pickle look their classes' modules up here
    try:
        module_spec.loader.exec_module(module)
    except SyntaxError as exc:
        del sys.modules[name]
        raise ConfigError(f"policy file {short_path(shown)}: {_syntax_line(exc)}") from None
    except (Exception, SystemExit) as exc:  # a script that parses its command line on import exits
        del sys.modules[name]
        raise ConfigError(f"policy file {short_path(shown)} {_import_failure(exc)}") from None
    return module


def _import_module(spec: PolicySpec) -> ModuleType:
    try:
        return importlib.import_module(spec.name)
    except ModuleNotFoundError as exc:
        missing = exc.name or ""
        if missing == spec.name or spec.name.startswith(missing + "."):
            if Path(spec.name).is_file():  # run.png:Policy reads as module "png" of a package "run"
                raise ConfigError(
                    f"policy {short_repr(str(spec))}: {short_path(spec.name)} is a file but not Python: a policy "
                    "file's name ends in .py (FILE.py:CLASS)"
                ) from None
            raise UnknownNameError(
                f"policy {short_repr(str(spec))}: no module named {missing!r} on the Python path (add its folder "
                "to PYTHONPATH)"
            ) from None
        raise ConfigError(f"module {spec.name!r} raised on import: {exception_line(exc)}") from None
    except SyntaxError as exc:
        raise ConfigError(f"module {spec.name!r}: {_syntax_line(exc)}") from None
    except (Exception, SystemExit) as exc:
        raise ConfigError(f"module {spec.name!r} {_import_failure(exc)}") from None


def _entry_point(spec: PolicySpec) -> EntryPoint:
    points = entry_points(group=ENTRY_POINT_GROUP, name=spec.name)
    for point in points:
        return point
    installed = ", ".join(installed_policies()) or "none installed"
    raise unknown_policy(spec.name, f"{ENTRY_POINT_GROUP}: {installed}")


def _entry_point_factory(spec: PolicySpec) -> PolicyFactory:
    point = _entry_point(spec)
    try:
        loaded = point.load()
    except FrontierRLError:
        raise
    except (Exception, SystemExit) as exc:
        raise ConfigError(
            f"installed policy {spec.name!r} ({point.value}) raised on load: {exception_line(exc)}"
        ) from None
    if not callable(loaded):
        raise ConfigError(f"installed policy {spec.name!r} ({point.value}) is {_kind(loaded)}, not a class")
    return cast(PolicyFactory, loaded)


def _origin(spec: PolicySpec) -> str:
    return f"file {spec.name}" if spec.kind is PolicyKind.FILE else f"module {spec.name}"


def _policy_classes(module: ModuleType) -> list[str]:
    """Names of the classes defined in ``module`` that have a ``rank`` attribute."""
    return [
        name
        for name, value in vars(module).items()
        if inspect.isclass(value) and value.__module__ == module.__name__ and hasattr(value, "rank")
    ]


def _syntax_line(exc: SyntaxError) -> str:
    where = f"{exc.filename}:{exc.lineno}" if exc.filename else f"line {exc.lineno}"
    return f"syntax error at {where}: {exc.msg}"


def _import_failure(exc: BaseException) -> str:
    """What importing a policy's module raised, for a message that starts with the module's name."""
    if isinstance(exc, SystemExit):
        return (
            f"exited on import ({exception_line(exc)}): a script's command-line code belongs under "
            "if __name__ == '__main__'"
        )
    return f"raised on import: {exception_line(exc)}"


def exception_line(exc: BaseException) -> str:
    """An exception for a message: its type and message, on one line, cut short."""
    return short_text(f"{type(exc).__name__}: {exc}")


def _kind(value: object) -> str:
    """A value for a message: a class by its name, an object of the user's by its type (its repr would
    name the module a policy file is loaded as), a built-in value by its repr, cut short, and its type."""
    if inspect.isclass(value):
        return f"the class {value.__qualname__}"
    kind = type(value)
    if kind.__module__ != "builtins":
        return f"an object of type {kind.__qualname__}"
    return f"{short_repr(value, 40)} (type {kind.__name__})"
