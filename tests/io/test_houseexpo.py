"""HouseExpo JSON floor plans: placement, free/wall split, thin interior walls, bad input."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from matplotlib.path import Path as PolygonPath
from numpy.typing import NDArray
from scipy import ndimage

from frontier_rl.core.world.grid import CellState, OccupancyGrid
from frontier_rl.errors import MapError
from frontier_rl.io import LoadedMap
from frontier_rl.io.houseexpo import load_houseexpo
from frontier_rl.io.map_size import houseexpo_size

HOUSE = "house_expo_room_0000.json"
HOUSE_WITH_SLITS = "0a1b29dba355df2ab02630133187bfab.json"

# A 4 m x 2 m room split by a wall 0.02 m thick (x = 1.99..2.01) from the floor up to y = 1.6 m,
# leaving a 0.4 m door at the top. At 0.05 m no cell centre falls inside the wall.
SLIT_ROOM = [[0, 0], [1.99, 0], [1.99, 1.6], [2.01, 1.6], [2.01, 0], [4, 0], [4, 2], [0, 2]]


def write_json(path: Path, doc: object) -> Path:
    path.write_text(json.dumps(doc))
    return path


def outline_leaks(grid: OccupancyGrid, verts: NDArray[np.float64]) -> int:
    """4-adjacent free cell pairs whose centres are separated by the polygon outline."""
    polygon = PolygonPath(np.vstack([verts, verts[:1]]), closed=True)
    free = grid.data == CellState.FREE
    leaks = 0
    for dr, dc in ((0, 1), (1, 0)):
        both = free[: free.shape[0] - dr, : free.shape[1] - dc] & free[dr:, dc:]
        for row, col in zip(*np.nonzero(both), strict=True):
            a = np.array(grid.cell_to_world(row, col))
            b = np.array(grid.cell_to_world(row + dr, col + dc))
            shrink = 1e-6 * (b - a)  # ignore an outline that merely touches a centre
            segment = PolygonPath(np.array([a + shrink, b - shrink]))
            leaks += bool(segment.intersects_path(polygon, filled=False))
    return leaks


def test_real_house_placement_and_walls(real_maps: Path) -> None:
    path = real_maps / "houseexpo" / HOUSE
    loaded = load_houseexpo(path)
    assert isinstance(loaded, LoadedMap)
    assert loaded.start is None
    assert loaded.source == path
    grid = loaded.grid
    assert grid.resolution == 0.05
    # verts span x 0.1..10.17, y 0.1..8.16 m; 0.5 m of wall around them
    assert grid.origin == pytest.approx((-0.4, -0.4))
    assert grid.shape == (182, 222)
    assert grid.count(CellState.UNKNOWN) == 0
    assert grid.count(CellState.FREE) > 20_000
    assert (grid.data[:10] == CellState.OCCUPIED).all()
    assert (grid.data[:, :10] == CellState.OCCUPIED).all()
    assert (grid.data[-10:] == CellState.OCCUPIED).all()
    # World coordinates are the file's metres: the bedroom is free, outside the outline is wall.
    assert grid.data[grid.world_to_cell(7.5, 2.0)] == CellState.FREE
    assert grid.data[grid.world_to_cell(0.05, 4.0)] == CellState.OCCUPIED


def test_interior_wall_of_real_house(real_maps: Path) -> None:
    grid = load_houseexpo(real_maps / "houseexpo" / HOUSE_WITH_SLITS).grid
    # The wall between the gym and the bedroom is the slit y = 1.90..2.02 m for x = 0.1..1.97 m.
    assert grid.data[grid.world_to_cell(1.0, 1.96)] == CellState.OCCUPIED
    assert grid.data[grid.world_to_cell(1.0, 1.8)] == CellState.FREE
    assert grid.data[grid.world_to_cell(1.0, 2.1)] == CellState.FREE


@pytest.mark.parametrize("name", [HOUSE, HOUSE_WITH_SLITS])
# Cell centres then fall at x.xx5 m, never on the files' 0.01 m outline (an outline through a row of
# centres is a tie that point-in-polygon may settle either way, not a lost wall).
@pytest.mark.parametrize("resolution", [0.17, 0.29])
def test_walls_survive_coarse_resolutions(real_maps: Path, name: str, resolution: float) -> None:
    path = real_maps / "houseexpo" / name
    verts = np.asarray(json.loads(path.read_text())["verts"], dtype=np.float64)
    grid = load_houseexpo(path, resolution=resolution).grid
    assert grid.count(CellState.FREE) > 0
    assert outline_leaks(grid, verts) == 0


@pytest.mark.parametrize("transpose", [False, True])
def test_thin_slit_stays_a_wall(tmp_path: Path, transpose: bool) -> None:
    verts = np.array(SLIT_ROOM, dtype=np.float64)
    if transpose:  # the same room turned on its side: a horizontal wall
        verts = verts[:, ::-1]
    grid = load_houseexpo(write_json(tmp_path / "slit.json", {"verts": verts.tolist()})).grid
    data = grid.data.T if transpose else grid.data
    centres_x = grid.origin[1 if transpose else 0] + (np.arange(data.shape[1]) + 0.5) * grid.resolution
    centres_y = grid.origin[0 if transpose else 1] + (np.arange(data.shape[0]) + 0.5) * grid.resolution
    near_wall = np.abs(centres_x - 2.0) < 0.1
    below_door = (centres_y > 0) & (centres_y < 1.6)
    # every row of cells beside the wall has a wall cell between the two halves
    assert (data[np.ix_(below_door, near_wall)] == CellState.OCCUPIED).any(axis=1).all()
    # ... and the halves still meet through the door
    door = (centres_y > 1.65) & (centres_y < 2.0)
    assert (data[np.ix_(door, near_wall)] == CellState.FREE).all()
    _, components = ndimage.label(data == CellState.FREE)
    assert components == 1
    assert outline_leaks(grid, verts) == 0


def test_margin_and_resolution(tmp_path: Path) -> None:
    square = write_json(tmp_path / "sq.json", {"verts": [[1, 1], [3, 1], [3, 2], [1, 2]]})
    grid = load_houseexpo(square, resolution=0.5, margin_m=0.0).grid
    assert grid.shape == (2, 4)
    assert grid.origin == (1.0, 1.0)
    assert grid.count(CellState.FREE) == 8
    grid = load_houseexpo(square, resolution=0.5, margin_m=1.0).grid
    assert grid.shape == (6, 8)
    assert grid.count(CellState.FREE) == 8
    assert grid.data[grid.world_to_cell(2.0, 1.5)] == CellState.FREE


def test_closed_ring_is_accepted(tmp_path: Path) -> None:
    ring = [[0, 0], [1, 0], [1, 1], [0, 1], [0, 0]]
    grid = load_houseexpo(write_json(tmp_path / "ring.json", {"verts": ring}), 0.25, 0.0).grid
    assert grid.count(CellState.FREE) == 16


@pytest.mark.parametrize("resolution", [0.05, 0.03, 0.1, 0.0125])
def test_the_listed_size_is_the_loaded_grids(tmp_path: Path, real_maps: Path, resolution: float) -> None:
    odd = write_json(tmp_path / "odd.json", {"verts": [[-3.3, 0.15], [7.05, 0.15], [7.05, 4.45], [-3.3, 4.45]]})
    for path in (real_maps / "houseexpo" / HOUSE, real_maps / "houseexpo" / HOUSE_WITH_SLITS, odd):
        size, grid = houseexpo_size(path, resolution), load_houseexpo(path, resolution).grid
        assert (size.height_cells, size.width_cells, size.resolution_m) == (*grid.shape, grid.resolution)


@pytest.mark.parametrize(
    "verts",
    [
        [[0, 0], [2, 2], [2, 0], [0, 2]],  # a bow tie
        [[0, 0], [2e6, 0], [2e6, 1], [0, 1]],  # a coordinate beyond the bound
        [[0, 0], [1, 0], [1, 1], [True, 1]],  # a vertex that is no pair of numbers
    ],
)
def test_the_size_refuses_what_loading_refuses(tmp_path: Path, verts: list[list[object]]) -> None:
    path = write_json(tmp_path / "bad.json", {"verts": verts})
    with pytest.raises(MapError) as loading:
        load_houseexpo(path)
    with pytest.raises(MapError) as sizing:
        houseexpo_size(path)
    assert str(sizing.value) == str(loading.value)


# --- bad input -------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("content", "match"),
    [
        ("{not json", "cannot parse"),
        ("[1, 2]", "'verts'"),
        ('{"id": "x"}', "'verts'"),
        ('{"verts": [[1, 2, 3], [4, 5, 6]]}', "verts"),
        ('{"verts": [["a", 0], [1, 1], [0, 1]]}', "verts"),
        ('{"verts": [[0, 0], [1, 1]]}', "degenerate"),
        ('{"verts": [[0, 0], [1, 1], [2, 2], [3, 3]]}', "degenerate.*area 0"),
        ('{"verts": [[0, 0], [1, NaN], [0, 1]]}', "finite"),
    ],
)
def test_malformed_file(tmp_path: Path, content: str, match: str) -> None:
    path = tmp_path / "bad.json"
    path.write_text(content)
    with pytest.raises(MapError, match=match) as info:
        load_houseexpo(path)
    assert "\n" not in str(info.value)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(MapError, match=r"not found.*gone\.json"):
        load_houseexpo(tmp_path / "gone.json")


@pytest.mark.parametrize(("resolution", "margin"), [(0.0, 0.5), (-0.1, 0.5), (0.05, -1.0), (1e-7, 0.5)])
def test_bad_sizes(tmp_path: Path, resolution: float, margin: float) -> None:
    path = write_json(tmp_path / "sq.json", {"verts": [[0, 0], [20, 0], [20, 20], [0, 20]]})
    with pytest.raises(MapError, match=r"resolution|margin_m"):
        load_houseexpo(path, resolution=resolution, margin_m=margin)
