"""What a real robot's exploration needs, without ROS: map messages as grids
(:mod:`~frontier_rl.robot.map_message`), the ranked frontiers of a map
(:mod:`~frontier_rl.robot.ranking`), the explorer's decisions (:mod:`~frontier_rl.robot.explorer`)
and a simulated robot that takes goals as a navigation stack does (:mod:`~frontier_rl.robot.sim_robot`).
The ROS 1 node and the ROS 2 nodes only convert messages to and from these."""
