"""Running ROS 2 processes in a network namespace of their own that has only loopback, as the
tests and benchmarks do.

Fast DDS discovers peers by multicast on every interface it finds: a test must never reach beyond
the machine. Each call gets a fresh namespace (``unshare -n`` as root, ``unshare -rn`` otherwise)
with ``lo`` up and multicast on (discovery needs it) and ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``:
processes in two namespaces never see each other, so tests run side by side.

Every script may end the processes it started in the background with ``stop PID...``: Ctrl-C
(SIGINT) to each, then its exit status; one still running 20 s later is aborted (SIGABRT: a Python
process, run with ``PYTHONFAULTHANDLER``, writes every thread's stack to its standard error, so
that its log says where it hung), killed 2 s after if it still runs, named on standard error, and
``stop`` fails, so a process that does not shut down is a clear failure, not a timeout.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

_SETUP = 'ip link set lo up && ip link set lo multicast on && exec "$@"'

STOP_GRACE_S = 20.0
"""How long ``stop`` waits for a process to end after its SIGINT before aborting it (s)."""
ABORT_GRACE_S = 2.0
"""How long ``stop`` gives an aborted process to write its stacks before killing it (s)."""


def _stop_function(grace_s: float) -> str:
    """The shell function ``stop PID...`` defined before every script (see the module's docstring)."""
    return (
        'stop() { kill -INT "$@" 2>/dev/null; '
        f'( sleep {grace_s:g}; kill -ABRT "$@"; sleep {ABORT_GRACE_S:g}; kill -KILL "$@" ) >/dev/null 2>&1 & '
        "watchdog=$!; "
        'failed=0; for p in "$@"; do wait "$p"; s=$?; '
        'if [ "$s" -eq 134 ] || [ "$s" -eq 137 ]; then '
        f'echo "process $p did not stop within {grace_s:g} s of SIGINT (its stacks, if Python, in its log)" >&2; '
        "failed=1; fi; "
        'done; kill "$watchdog" 2>/dev/null; return $failed; }; '
    )


_LOG_TAIL_CHARS = 2000
"""How much of each log a timeout's message quotes (its end)."""


class LoopbackTimeoutError(RuntimeError):
    """A script ran past its time; the message ends with the tail of each log in its folder."""


def unshare_command() -> list[str]:
    """``unshare`` with a new network namespace: as root, or as a user mapped to root."""
    return ["unshare", "-n"] if os.geteuid() == 0 else ["unshare", "-rn"]


def loopback_problem() -> str | None:
    """Why ROS 2 cannot be tested here (no rclpy, no nav2_msgs or tf2_msgs, no namespaces), or None."""
    try:
        import nav2_msgs.action  # noqa: F401
        import rclpy  # noqa: F401
        import tf2_msgs.msg  # noqa: F401
    except ImportError as error:
        return f"ROS 2 is not installed: {error}"
    if shutil.which("unshare") is None or shutil.which("ip") is None:
        return "unshare or ip is missing: no loopback-only network namespace"
    probe = subprocess.run([*unshare_command(), "sh", "-c", _SETUP, "sh", "true"], capture_output=True, timeout=30)
    if probe.returncode != 0:
        return f"no loopback-only network namespace here: {probe.stderr.decode(errors='replace').strip()}"
    return None


def loopback_env(home: Path) -> dict[str, str]:
    """The environment of a ROS 2 process: discovery on localhost, logs in ``home``."""
    env = dict(os.environ)
    env.update(
        ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
        ROS_LOG_DIR=str(home / "ros_log"),
        PYTHONUNBUFFERED="1",
        PYTHONFAULTHANDLER="1",  # a process ``stop`` aborts writes where it hung
    )
    return env


def run_in_loopback(
    script: str, home: Path, timeout: float, stop_grace_s: float = STOP_GRACE_S
) -> subprocess.CompletedProcess[str]:
    """Run the shell ``script`` in a fresh loopback-only namespace (in ``home``), its output
    captured; past ``timeout`` (s) every process it started is killed and :class:`LoopbackTimeoutError`
    raised, quoting the logs (``*.log``, ``*.err``) it left in ``home``; ``stop_grace_s``: how long
    the script's ``stop`` waits after SIGINT (s)."""
    command = [*unshare_command(), "sh", "-c", _SETUP, "sh", "sh", "-c", _stop_function(stop_grace_s) + script]
    with subprocess.Popen(
        command,
        cwd=home,
        env=loopback_env(home),
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        stdin=subprocess.DEVNULL,
        start_new_session=True,
    ) as process:
        try:
            out, err = process.communicate(timeout=timeout)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)  # the whole session: nothing is left running
            out, err = process.communicate()
            raise LoopbackTimeoutError(
                f"timed out after {timeout:g} s\n{err[-_LOG_TAIL_CHARS:]}{_log_tails(home)}"
            ) from None
    return subprocess.CompletedProcess(command, process.returncode, out, err)


def _log_tails(home: Path) -> str:
    logs = sorted(home.glob("*.log")) + sorted(home.glob("*.err"))
    return "".join(f"\n--- {log.name} (end)\n{log.read_text(errors='replace')[-_LOG_TAIL_CHARS:]}" for log in logs)


def cli() -> str:
    """The ``frontier-rl`` command of this interpreter's environment."""
    return str(Path(sys.executable).with_name("frontier-rl"))
