"""observation: what a learned policy sees and answers, without Gymnasium or torch, so that the
envs, the learned policies and the ROS node encode it the same way: the map as a fixed-size image
with optional frontier and pose channels (``map_image``), model 5's table of the cheapest
frontiers (``frontier_table``) and models 3 and 4's weight bins (``weight_bins``)."""
