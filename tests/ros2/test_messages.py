"""ROS 2 messages to and from the engine's values (no DDS: the message classes only)."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("rclpy", reason="ROS 2 is not installed (the ros2 extra)")

from builtin_interfaces.msg import Time
from geometry_msgs.msg import Pose

from frontier_rl.core.sensing.lidar import Lidar
from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.core.world.robot import Pose as RobotPose
from frontier_rl.errors import MapError
from frontier_rl.robot.explorer_decision import Goal
from frontier_rl.robot.explorer_params import Nav2Plugins
from frontier_rl.robot.map_message import yaw_of
from frontier_rl.ros2.messages import (
    grid_message,
    grid_of,
    laser_scan,
    path_message,
    path_points,
    pose_message,
    quaternion_of,
    robot_pose,
)
from frontier_rl.ros2.nav2_goals import Nav2Action, goal_request


def _grid() -> OccupancyGrid:
    data = np.full((20, 30), CellState.UNKNOWN, np.int8)
    data[2:18, 2:15] = CellState.FREE
    data[1, :] = CellState.OCCUPIED
    return OccupancyGrid(data, 0.05, (-1.25, 3.5))


def test_a_map_comes_back_cell_for_cell_in_its_frame() -> None:
    grid = _grid()
    back = grid_of(grid_message(grid, Time(sec=3)))
    assert np.array_equal(back.data, grid.data) and back.resolution == 0.05 and back.origin == (-1.25, 3.5)
    assert back.world_to_cell(0.0, 4.0) == grid.world_to_cell(0.0, 4.0)


def test_a_rotated_or_malformed_map_is_a_map_error() -> None:
    message = grid_message(_grid(), Time())
    message.info.origin.orientation = quaternion_of(0.3)
    with pytest.raises(MapError, match=r"rotated by 0\.3 rad"):
        grid_of(message)
    message = grid_message(_grid(), Time())
    message.data = message.data[:10]
    with pytest.raises(MapError, match="map data has 10 values"):
        grid_of(message)
    message = grid_message(_grid(), Time())
    message.info.origin.position.x = math.nan
    with pytest.raises(MapError, match="not finite"):
        grid_of(message)


@pytest.mark.parametrize("yaw", [0.0, 1.0, -2.5, math.pi - 1e-9])
def test_a_pose_and_its_yaw_come_back(yaw: float) -> None:
    pose = robot_pose(pose_message(RobotPose(1.5, -2.0, yaw)))
    assert (pose.x, pose.y) == (1.5, -2.0) and math.isclose(yaw_of(quaternion_of(yaw)), yaw, abs_tol=1e-9)
    assert math.isclose(pose.theta, yaw, abs_tol=1e-9)


def test_a_pose_that_is_not_finite_is_refused_naming_it() -> None:
    message = Pose()
    message.position.x = math.inf
    message.orientation.w = 1.0
    with pytest.raises(ValueError, match=r"pose \(inf, 0.0, yaw 0.0\) is not finite"):
        robot_pose(message)


def test_a_scan_is_laid_out_counter_clockwise_from_the_heading() -> None:
    grid = _grid()
    scan = Lidar(grid).scan(RobotPose(-0.5, 4.0, 0.7), None)
    message = laser_scan(scan, 0.12, 3.5, Time())
    assert len(message.ranges) == len(scan.ranges) == 360
    assert math.isclose(message.angle_increment, 2 * math.pi / 360)
    first = math.atan2(scan.dir_y[0], scan.dir_x[0]) - 0.7
    assert math.isclose(math.remainder(message.angle_min - first, 2 * math.pi), 0.0, abs_tol=1e-6)
    finite = np.isfinite(scan.ranges)
    assert np.allclose(np.array(message.ranges)[finite], scan.ranges[finite], atol=1e-5)


def test_a_path_message_faces_each_pose_to_the_next_and_reads_back() -> None:
    points = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 2.0)])
    message = path_message(points, Time(sec=3), "tb3_0/map")
    assert message.header.frame_id == "tb3_0/map" and [p.header.stamp.sec for p in message.poses] == [3, 3, 3]
    assert [yaw_of(p.pose.orientation) for p in message.poses] == pytest.approx([0.0, math.pi / 2, math.pi / 2])
    np.testing.assert_array_equal(path_points(message), points)
    assert yaw_of(path_message(points[:1], Time()).poses[0].pose.orientation) == 0.0
    message.poses[1].pose.position.y = math.inf
    with pytest.raises(ValueError, match="not finite"):
        path_points(message)
    with pytest.raises(ValueError, match="no poses"):
        path_points(path_message(np.zeros((0, 2)), Time()))


def test_goals_name_the_nav2_plugins_given_and_none_by_default() -> None:
    path = np.array([(0.0, 0.0), (1.0, 0.5)])
    goal = Goal(1.0, 0.5, np.zeros((0, 2)), path=path)
    plugins = Nav2Plugins("/opt/explore_bt.xml", "FollowPath", "precise_goal_checker", "simple_progress_checker")
    follow = goal_request(goal, Nav2Action.FOLLOW, "map", Time(sec=2), plugins)
    assert (follow.controller_id, follow.goal_checker_id, follow.progress_checker_id) == (
        "FollowPath",
        "precise_goal_checker",
        "simple_progress_checker",
    )
    np.testing.assert_array_equal(path_points(follow.path), path)
    navigate = goal_request(goal, Nav2Action.NAVIGATE, "map", Time(sec=2), plugins)
    assert navigate.behavior_tree == "/opt/explore_bt.xml"
    assert (navigate.pose.pose.position.x, navigate.pose.pose.position.y) == (1.0, 0.5)
    plain = goal_request(goal, Nav2Action.FOLLOW, "map", Time(), Nav2Plugins())
    assert (plain.controller_id, plain.goal_checker_id, plain.progress_checker_id) == ("", "", "")
    assert goal_request(goal, Nav2Action.NAVIGATE, "map", Time(), Nav2Plugins()).behavior_tree == ""
