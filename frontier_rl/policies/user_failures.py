"""An exception that the user's own policy code raised during an episode, as one line: which policy,
in which of its methods, what was raised, and the user's file and line it was raised at.

User code is every file of the traceback outside frontier_rl and the installed libraries (the Python
standard library, site-packages), and the file that defines the policy's class, wherever it lies
(an installed package's policy is in site-packages)."""

from __future__ import annotations

import inspect
import site
import sysconfig
import traceback
from functools import cache
from pathlib import Path

from frontier_rl.errors import PolicyError, short_repr
from frontier_rl.policies.spec import PolicySpec
from frontier_rl.policies.user_policies import exception_line

_PLACE_LIMIT = 120
"""Most characters of the file name a message shows (its end, with the file's name, is kept)."""


def user_code_failure(spec: PolicySpec, policy: object, exc: BaseException) -> PolicyError | None:
    """``exc``, raised while an episode ran the user's policy ``spec`` (built as ``policy``), as one line
    (``policy 'bad.py:Raises' failed in rank(): RuntimeError: boom (bad.py:4)``): the method of the
    policy frontier_rl called, the exception, and the innermost line of user code it passed through.
    None for a built-in policy, or where no frame of the traceback is user code (frontier_rl's own
    error, which is not the user's to fix)."""
    if not spec.is_user_code:
        return None
    own_file = _source_file(policy)
    frames = [f for f in traceback.extract_tb(exc.__traceback__) if _is_user_file(f.filename, own_file)]
    if not frames:
        return None
    called, raised_at = frames[0], frames[-1]
    return PolicyError(
        f"policy {short_repr(str(spec))} failed in {called.name}(): {exception_line(exc)} ({_place(raised_at)})"
    )


def _source_file(policy: object) -> Path | None:
    """The file that defines ``policy``'s class, if it has one."""
    try:
        source = inspect.getsourcefile(type(policy))
    except TypeError:  # a built-in class
        return None
    return Path(source).resolve() if source else None


def _is_user_file(filename: str, own_file: Path | None) -> bool:
    if filename.startswith("<"):  # <frozen ...>, <string>: no file to point at
        return False
    path = Path(filename).resolve()
    if path == own_file:
        return True
    return not any(path.is_relative_to(root) for root in _library_roots())


@cache
def _library_roots() -> tuple[Path, ...]:
    """The folders that hold frontier_rl and the installed libraries."""
    folders = [Path(__file__).resolve().parent.parent]  # frontier_rl
    paths = sysconfig.get_paths()
    folders += [Path(paths[key]) for key in ("stdlib", "platstdlib", "purelib", "platlib") if key in paths]
    folders += [Path(p) for p in (*site.getsitepackages(), site.getusersitepackages())]
    return tuple(folder.resolve() for folder in folders)


def _place(frame: traceback.FrameSummary) -> str:
    """``FILE:LINE`` of ``frame``, the file relative to the working folder where it lies inside."""
    path = Path(frame.filename)
    try:
        shown = str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        shown = frame.filename
    if len(shown) > _PLACE_LIMIT:
        shown = "…" + shown[-(_PLACE_LIMIT - 1) :]
    return f"{shown}:{frame.lineno}"
