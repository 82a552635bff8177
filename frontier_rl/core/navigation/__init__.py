"""navigation: the robot's map + a goal → a costmap (inflated obstacles), a path (A* and path-cost
fields) → velocity steps along it (the path follower)."""
