"""mapping: scans + poses → the robot's occupancy map (log-odds cells; free, occupied or unknown)."""
