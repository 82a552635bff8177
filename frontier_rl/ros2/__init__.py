"""ROS 2 interface (the ``ros2`` extra: rclpy and the Kilted message wheels, nav2_msgs built by
``make setup``): the explorer that drives a robot through Nav2 (:mod:`~frontier_rl.ros2.explorer_node`)
and the simulator as a ROS 2 robot (:mod:`~frontier_rl.ros2.sim_node`). Their decisions and the
simulated robot are ROS-free, in :mod:`frontier_rl.robot`."""
