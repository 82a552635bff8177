"""SLAM artefacts drawn onto a layout (:mod:`frontier_rl.core.world.slam_artefacts`), and the
``slam_building`` generator that draws them onto a building (issue 58's harder survey)."""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from frontier_rl.core.world.catalog import building_world, generate_world
from frontier_rl.core.world.grid import CellState
from frontier_rl.core.world.slam_artefacts import SlamArtefacts, with_slam_artefacts

RES = 0.05


def _room(size_m: float = 10.0) -> np.ndarray:
    """A square room: walls of two cells round free floor."""
    cells = int(size_m / RES)
    occ = np.zeros((cells, cells), np.bool_)
    occ[:2, :] = occ[-2:, :] = occ[:, :2] = occ[:, -2:] = True
    return occ


def test_streaks_run_from_the_room_into_the_band_round_it() -> None:
    room = _room()
    artefacts = SlamArtefacts(specks_per_100m2=0.0, rough_wall_share=0.0)
    occ = with_slam_artefacts(room, np.random.default_rng(0), RES, artefacts)
    band = int(np.ceil(artefacts.band_m / RES))
    assert occ.shape == (room.shape[0] + 2 * band, room.shape[1] + 2 * band)
    inner = occ[band:-band, band:-band]
    beyond = ~occ.copy()
    beyond[band:-band, band:-band] = False
    assert beyond.any()  # streaks through the outer wall, into what was solid
    labels, _ = ndimage.label(~occ)  # 4-connected: every streak is one region with the room
    assert set(np.unique(labels[beyond])) == {labels[band + 100, band + 100]}
    longest = max(artefacts.streak_m) / RES
    assert np.count_nonzero(beyond.any(axis=0)) <= room.shape[1] + 2 * longest
    assert occ[[0, -1], :].all() and occ[:, [0, -1]].all()  # the world stays closed
    assert np.array_equal(inner[2:-2, 2:-2], room[2:-2, 2:-2])  # the floor is untouched


def test_specks_stand_in_open_floor_and_rough_walls_stand_beside_walls() -> None:
    room = _room()
    specks = with_slam_artefacts(
        room, np.random.default_rng(1), RES, SlamArtefacts(scans_per_100m2=0.0, rough_wall_share=0.0)
    )
    band = int(np.ceil(SlamArtefacts().band_m / RES))
    added = specks[band:-band, band:-band] & ~room
    assert 0 < np.count_nonzero(added) <= 2 * 3 * SlamArtefacts().specks_per_100m2  # 100 m²: about 15 specks
    assert not added[:3, :].any() and not added[:, :3].any()  # none on a wall
    rough = with_slam_artefacts(
        room, np.random.default_rng(1), RES, SlamArtefacts(scans_per_100m2=0.0, specks_per_100m2=0.0)
    )
    grown = rough[band:-band, band:-band] & ~room
    beside_wall = ndimage.binary_dilation(room) & ~room
    assert grown.any() and not (grown & ~beside_wall).any()
    assert np.count_nonzero(grown) < 0.1 * np.count_nonzero(beside_wall)


def test_a_slam_building_is_the_building_of_its_seed_with_the_artefacts() -> None:
    for seed in (0, 3):
        world = generate_world("slam_building", seed)
        again = generate_world("slam_building", seed)
        plain = building_world(np.random.default_rng(seed))
        assert np.array_equal(world.grid.data, again.grid.data) and world.start == again.start
        band = int(np.ceil(SlamArtefacts().band_m / RES))
        assert world.grid.shape == (plain.grid.shape[0] + 2 * band, plain.grid.shape[1] + 2 * band)
        free = world.grid.data == CellState.FREE
        outside = free.copy()
        outside[band:-band, band:-band] = False
        assert outside.any()  # streaks beyond the outer walls
        inside = world.grid.data[band:-band, band:-band]
        changed = np.count_nonzero(inside != plain.grid.data)
        assert 0 < changed < 0.02 * inside.size  # the same building, with a few per cent of its cells changed
        assert world.explorable[int(world.start.y / RES), int(world.start.x / RES)]
