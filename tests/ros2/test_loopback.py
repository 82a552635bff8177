"""The loopback-namespace runner of the ROS 2 tests: a process that ignores Ctrl-C is named and
killed by ``stop``, and a script past its time is reported with the logs it left."""

from __future__ import annotations

import shlex
import subprocess
import sys
from pathlib import Path

import pytest

from frontier_rl.ros2.loopback import LoopbackTimeoutError, run_in_loopback, unshare_command


def _namespaces() -> bool:
    try:
        return subprocess.run([*unshare_command(), "true"], capture_output=True, timeout=30).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


pytestmark = pytest.mark.skipif(not _namespaces(), reason="no network namespaces here (unshare)")


def test_stop_ends_processes_with_sigint_and_names_one_that_ignores_it(tmp_path: Path) -> None:
    # a background job of sh starts with SIGINT ignored; a ROS 2 process (rclpy) handles it as this one does
    polite = (
        "import signal, sys, time; signal.signal(signal.SIGINT, lambda *_: sys.exit(0)); "
        "open('ready', 'w').close(); time.sleep(30)"
    )
    script = (
        f"{shlex.quote(sys.executable)} -c {shlex.quote(polite)} & polite=$!; "
        "sh -c 'trap \"\" INT; exec sleep 30' & stubborn=$!; "
        "until [ -e ready ]; do sleep 0.05; done; stop $polite; polite_status=$?; stop $stubborn; stubborn_status=$?; "
        "echo $polite_status $stubborn_status $stubborn"
    )
    done = run_in_loopback(script, tmp_path, 20, stop_grace_s=1)
    polite, stubborn, pid = done.stdout.split()
    assert (polite, stubborn) == ("0", "1"), done.stderr
    assert f"process {pid} did not stop within 1 s of SIGINT" in done.stderr
    assert "did not stop" not in done.stderr.replace(f"process {pid} did not stop", "")


def test_a_python_process_that_hangs_on_sigint_leaves_its_stacks_in_its_log(tmp_path: Path) -> None:
    hung = (
        "import signal, time; signal.signal(signal.SIGINT, signal.SIG_IGN); open('ready', 'w').close(); time.sleep(30)"
    )
    script = (
        f"{shlex.quote(sys.executable)} -c {shlex.quote(hung)} > hung.log 2>&1 & hung=$!; "
        "until [ -e ready ]; do sleep 0.05; done; stop $hung; echo $? $hung"
    )
    done = run_in_loopback(script, tmp_path, 20, stop_grace_s=1)
    status, pid = done.stdout.split()
    assert status == "1" and f"process {pid} did not stop within 1 s of SIGINT" in done.stderr
    log = (tmp_path / "hung.log").read_text()
    assert "Fatal Python error: Aborted" in log and 'File "<string>", line 1' in log  # where it hung


def test_a_script_past_its_time_is_reported_with_its_logs(tmp_path: Path) -> None:
    with pytest.raises(LoopbackTimeoutError, match=r"(?s)timed out after 1 s.*--- sim\.log \(end\)\nsimulator started"):
        run_in_loopback("echo simulator started > sim.log; sleep 30", tmp_path, 1)
