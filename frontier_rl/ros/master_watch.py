"""Notice a restarted ROS master. A rospy node does not register its topics again with a new
master, so it would stay alive and silent; the node exits instead, and ``respawn="true"`` in its
launch file starts it afresh on the new master."""

from __future__ import annotations

import threading
import xmlrpc.client
from collections.abc import Callable
from typing import Any

EXIT_MASTER_RESTARTED = 3
"""The node's exit status when its master was restarted under it."""


def master_identity(uri: str, caller_id: str, timeout_s: float = 2.0) -> tuple[int, bool]:
    """The process id of the ROS master at ``uri`` and whether it knows the node ``caller_id``
    (raises ``OSError`` when it does not answer)."""
    transport = _TimeoutTransport(timeout_s)
    with xmlrpc.client.ServerProxy(uri, transport=transport) as master:
        reply: Any = master.getPid(caller_id)
        known: Any = master.lookupNode(caller_id, caller_id)
    code, message, pid = reply
    if code != 1:
        raise OSError(f"master at {uri} refused getPid: {message}")
    return int(pid), known[0] == 1


class MasterWatch(threading.Thread):
    """Polls the master every ``period_s`` and calls ``on_restart`` (once, with a description) when
    the process answering at ``uri`` is not the one that answered first, or no longer knows the
    node after it did (a new master whose process got the same id, as in a fresh container);
    ``on_lost`` (with the error) while it does not answer, or answers with something that is no
    XML-RPC reply."""

    def __init__(
        self,
        uri: str,
        caller_id: str,
        period_s: float,
        on_restart: Callable[[str], None],
        on_lost: Callable[[str], None] | None = None,
        identity: Callable[[str, str], tuple[int, bool]] = master_identity,
    ) -> None:
        super().__init__(name="master-watch", daemon=True)
        self.uri, self.caller_id, self.period_s = uri, caller_id, period_s
        self._on_restart, self._on_lost, self._identity = on_restart, on_lost, identity
        self._stop = threading.Event()

    def stop(self) -> None:
        """End the polling."""
        self._stop.set()

    def run(self) -> None:
        first: int | None = None
        was_known = False
        while not self._stop.is_set():
            try:
                pid, known = self._identity(self.uri, self.caller_id)
            except Exception as exc:  # refused, timed out, HTTP or XML garbage: this thread must go on
                if self._on_lost is not None:
                    self._on_lost(str(exc) or type(exc).__name__)
            else:
                first = pid if first is None else first
                if pid != first:
                    self._on_restart(f"the ROS master at {self.uri} was restarted (pid {first}, now {pid})")
                    return
                if was_known and not known:
                    self._on_restart(f"the ROS master at {self.uri} no longer knows {self.caller_id}: restarted")
                    return
                was_known = was_known or known
            self._stop.wait(self.period_s)


class _TimeoutTransport(xmlrpc.client.Transport):
    """An XML-RPC transport whose connections give up after ``timeout_s``."""

    def __init__(self, timeout_s: float) -> None:
        super().__init__()
        self.timeout_s = timeout_s

    def make_connection(self, host: Any) -> Any:
        connection = super().make_connection(host)
        connection.timeout = self.timeout_s
        return connection
