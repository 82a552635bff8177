"""ROS 1 interface: the frontier node (``frontier_rl.ros.node``, needs rospy) and the ROS-free
ranking it serves (:mod:`frontier_rl.robot`)."""
