"""The ``frontier-rl`` script's entry point, kept apart from the command line it loads, so that a
Ctrl-C at any moment ends the command with one line on standard error and exit code 130, as one
while a command runs does (:class:`~frontier_rl.cli_output.OneLineGroup`).

A Ctrl-C is never raised inside an import: NumPy, SciPy, torch and typer load for a second or more
(more again when a command loads what it needs), and an interrupt raised there was seen to print
Python's traceback, to fail a compiled module's initialisation with a traceback and exit code 1, or
to be swallowed in importlib's weakref callback, the command then running to its end. It is
delivered again once the import is over."""

from __future__ import annotations

import os
import signal
import sys
import threading
from types import FrameType

_REDELIVER_S = 0.05
"""How soon a Ctrl-C that came during an import is delivered again (s)."""


def main() -> None:
    """Load the command line and run it."""
    signal.signal(signal.SIGINT, _interrupt_outside_imports)
    try:
        from frontier_rl.cli import app

        app()
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        raise SystemExit(130) from None


def _interrupt_outside_imports(signum: int, frame: FrameType | None) -> None:
    """SIGINT handler: raise KeyboardInterrupt, unless an import is running, then send SIGINT
    again shortly."""
    if _in_import(frame):
        threading.Timer(_REDELIVER_S, os.kill, (os.getpid(), signal.SIGINT)).start()
        return
    raise KeyboardInterrupt


def _in_import(frame: FrameType | None) -> bool:
    """Whether ``frame`` or a caller of it is importlib's machinery."""
    while frame is not None:
        if frame.f_code.co_filename.startswith("<frozen importlib._bootstrap"):
            return True
        frame = frame.f_back
    return False
