"""Running ROS 2 processes in a network namespace of their own that has only loopback, as the
tests and benchmarks do.

Fast DDS discovers peers by multicast on every interface it finds: a test must never reach beyond
the machine. Each call gets a fresh namespace (``unshare -n`` as root, ``unshare -rn`` otherwise)
with ``lo`` up and multicast on (discovery needs it) and ``ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST``:
processes in two namespaces never see each other, so tests run side by side.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
from pathlib import Path

_SETUP = 'ip link set lo up && ip link set lo multicast on && exec "$@"'


def unshare_command() -> list[str]:
    """``unshare`` with a new network namespace: as root, or as a user mapped to root."""
    return ["unshare", "-n"] if os.geteuid() == 0 else ["unshare", "-rn"]


def loopback_problem() -> str | None:
    """Why ROS 2 cannot be tested here (no rclpy, no nav2_msgs, no namespaces), or None."""
    try:
        import nav2_msgs.action  # noqa: F401
        import rclpy  # noqa: F401
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
    )
    return env


def run_in_loopback(script: str, home: Path, timeout: float) -> subprocess.CompletedProcess[str]:
    """Run the shell ``script`` in a fresh loopback-only namespace (in ``home``), its output
    captured; past ``timeout`` (s) every process it started is killed and TimeoutExpired raised."""
    command = [*unshare_command(), "sh", "-c", _SETUP, "sh", "sh", "-c", script]
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
            process.communicate()
            raise
    return subprocess.CompletedProcess(command, process.returncode, out, err)


def cli() -> str:
    """The ``frontier-rl`` command of this interpreter's environment."""
    return str(Path(sys.executable).with_name("frontier-rl"))
