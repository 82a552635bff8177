"""``python -m frontier_rl.ros _robots:=tb3_0,tb3_1``: run the frontier node (:mod:`frontier_rl.ros.node`).

A Ctrl-C while the node's modules load ends it at once and quietly, as it would a C program, where
Python would print a KeyboardInterrupt traceback from some import; once rospy is initialised, its
own handler shuts the node down and the node stops its workers. ``python -m`` imports the packages
above this module first (about 0.05 s): the launch file's script sets the default action before
them, so that no moment after Python's own start is left to a traceback.
"""

import signal

signal.signal(signal.SIGINT, signal.SIG_DFL)

from frontier_rl.ros.node import main  # noqa: E402  (after the handler, which must cover this import)

main()
