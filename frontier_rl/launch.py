"""The ``frontier-rl`` script's entry point, kept apart from the command line it loads, so that a
Ctrl-C at any moment after Python has started (its first ~0.05 s) ends the command with one line on
standard error and exit code 130, as one while a command runs does
(:class:`~frontier_rl.cli.output.OneLineGroup`).

A Ctrl-C is never raised inside an import: NumPy, SciPy, torch and typer load for a second or more
(more again when a command loads what it needs), and an interrupt raised there was seen to print
Python's traceback, to fail a compiled module's initialisation with a traceback and exit code 1, or
to be swallowed in importlib's weakref callback, the command then running to its end. It is
delivered again once the import is over (a SIGALRM timer: no thread is started in a handler). The
same holds inside numba's own Python code, which compiled kernels call back into (to unpickle a
constant): an interrupt raised there comes out of the kernel as a ``SystemError``, a traceback where
``tour`` was interrupted; one that still comes out so, caused by a Ctrl-C, ends the command as one.

The first Ctrl-C ends the command; more while it ends (its workers get up to 5 s) are ignored,
which would otherwise print tracebacks from wherever they landed, unless the end takes longer than
:data:`FORCE_AFTER_S`: then one ends the process at once. A run started with Ctrl-C ignored (a
shell's background job) keeps ignoring it.
"""

from __future__ import annotations

import os
import signal
import sys
import time
from types import FrameType

from frontier_rl.errors import caused_by_interrupt

REDELIVER_S = 0.05
"""How soon a Ctrl-C that came during an import is delivered again (s)."""

FORCE_AFTER_S = 10.0
"""A Ctrl-C this long after the first (s) ends the process at once, if it is still ending."""


def main() -> None:
    """Load the command line and run it."""
    handled = signal.getsignal(signal.SIGINT) is signal.default_int_handler
    if handled:
        interrupts = CommandInterrupts()
        signal.signal(signal.SIGINT, interrupts.on_sigint)
        signal.signal(signal.SIGALRM, interrupts.on_redelivery)
    try:
        from frontier_rl.cli import app

        app()
    except (KeyboardInterrupt, SystemError) as error:
        if not caused_by_interrupt(error):
            raise
        print("interrupted", file=sys.stderr)
        raise SystemExit(130) from None
    finally:  # the command is over: a late Ctrl-C, or one deferred, must not land in Python's exit
        if handled:
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.signal(signal.SIGINT, signal.SIG_IGN)


class CommandInterrupts:
    """The command line's SIGINT handling: the first Ctrl-C raises KeyboardInterrupt, outside any
    import; later ones are ignored, unless the command is still ending :data:`FORCE_AFTER_S` later."""

    def __init__(self) -> None:
        self.raised_at: float | None = None
        """When the first Ctrl-C was raised (monotonic s)."""
        self.deferred = False
        """Whether a Ctrl-C waits for an import to end."""

    def on_sigint(self, signum: int, frame: FrameType | None) -> None:
        """SIGINT handler."""
        if self.raised_at is not None:
            if time.monotonic() - self.raised_at > FORCE_AFTER_S:
                os.write(2, b"interrupted again: ended at once\n")
                os._exit(130)
            return
        if _in_fragile_code(frame):
            if not self.deferred:
                self.deferred = True
                signal.setitimer(signal.ITIMER_REAL, REDELIVER_S)
            return
        self.raised_at = time.monotonic()
        raise KeyboardInterrupt

    def on_redelivery(self, signum: int, frame: FrameType | None) -> None:
        """SIGALRM handler: the deferred Ctrl-C, sent again, to whichever SIGINT handler is set now
        (a pool holds it while it spawns a worker)."""
        if self.deferred:  # else not ours: no Ctrl-C waits
            self.deferred = False
            signal.raise_signal(signal.SIGINT)


def _in_fragile_code(frame: FrameType | None) -> bool:
    """Whether ``frame`` or a caller of it is importlib's machinery, numba's own Python code (a
    compiled kernel's callback, the compiler) or torch's serialization (an interrupt inside its C++
    zip writer becomes a RuntimeError): where an interrupt must wait."""
    numba, torch_save = f"{os.sep}numba{os.sep}", f"{os.sep}torch{os.sep}serialization.py"
    while frame is not None:
        name = frame.f_code.co_filename
        if name.startswith("<frozen importlib._bootstrap") or numba in name or name.endswith(torch_save):
            return True
        frame = frame.f_back
    return False
