"""The robot's frames in the plane (what ``/tf`` says): composing a chain of transforms gives the
base's pose in the map, and a chain that does not reach the map says where it ends."""

from __future__ import annotations

import math

import pytest

from frontier_rl.robot.transforms import IDENTITY, PlanarTransform, TransformTree


def _close(a: PlanarTransform, b: PlanarTransform) -> bool:
    turn = math.atan2(math.sin(a.yaw - b.yaw), math.cos(a.yaw - b.yaw))
    return math.hypot(a.x - b.x, a.y - b.y) < 1e-9 and abs(turn) < 1e-9


def test_a_pose_in_a_turned_frame_is_turned_and_moved() -> None:
    odom = PlanarTransform(2.0, 1.0, math.pi / 2)  # odom's origin at (2, 1) in the map, turned left
    base = PlanarTransform(1.0, 0.0, 0.0)  # a metre ahead in odom: to the map's +y
    assert _close(odom.then(base), PlanarTransform(2.0, 2.0, math.pi / 2))


@pytest.mark.parametrize("transform", [PlanarTransform(1.5, -2.0, 0.7), PlanarTransform(-3.0, 0.25, -2.9)])
def test_a_transform_then_its_inverse_is_the_identity(transform: PlanarTransform) -> None:
    assert _close(transform.then(transform.inverse()), IDENTITY)
    assert _close(transform.inverse().then(transform), IDENTITY)


def test_the_base_in_the_map_through_odom_and_a_static_link() -> None:
    tree = TransformTree()
    start = PlanarTransform(3.0, 4.0, math.pi)
    pose = PlanarTransform(5.0, 1.0, 0.3)  # where the robot is in the map
    tree.set("map", "odom", start)  # odometry starts at the start pose
    tree.set("/odom", "base_footprint", start.inverse().then(pose))  # ROS 1's leading slash is the same frame
    tree.set("base_footprint", "base_link", IDENTITY)
    assert _close(tree.lookup("map", "base_link"), pose)
    assert _close(tree.lookup("odom", "base_footprint"), start.inverse().then(pose))
    assert tree.lookup("base_link", "base_link") == IDENTITY


def test_the_latest_transform_of_a_frame_wins() -> None:
    tree = TransformTree()
    tree.set("map", "base_link", PlanarTransform(1.0, 0.0, 0.0))
    tree.set("map", "base_link", PlanarTransform(2.0, 0.0, 0.0))
    assert tree.lookup("map", "base_link").x == 2.0


def test_a_chain_that_does_not_reach_the_map_says_where_it_ends() -> None:
    tree = TransformTree()
    with pytest.raises(LookupError, match="no transform of 'base_link' yet"):
        tree.lookup("map", "base_link")
    tree.set("odom", "base_link", IDENTITY)
    with pytest.raises(LookupError, match="'odom' has no parent"):
        tree.lookup("map", "base_link")


def test_a_loop_of_transforms_is_refused_not_followed_for_ever() -> None:
    tree = TransformTree()
    tree.set("a", "b", IDENTITY)
    tree.set("b", "a", IDENTITY)
    with pytest.raises(LookupError, match="loop"):
        tree.lookup("map", "a")


@pytest.mark.parametrize(
    ("parent", "child", "transform", "needle"),
    [("", "base_link", IDENTITY, "names no frame"), ("map", "/map", IDENTITY, "to itself"),
     ("map", "base_link", PlanarTransform(math.nan, 0.0, 0.0), "not finite")],
)  # fmt: skip
def test_a_bad_transform_is_refused_by_name(parent: str, child: str, transform: PlanarTransform, needle: str) -> None:
    with pytest.raises(ValueError, match=needle):
        TransformTree().set(parent, child, transform)
