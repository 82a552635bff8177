"""HouseExpo files from strangers (issue 14): self-crossing, degenerate, oversized and malformed
polygons are one-line MapErrors naming the file; repeated vertices are dropped consistently."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from numpy.typing import NDArray
from typer.testing import CliRunner

import frontier_rl.io.houseexpo as houseexpo
from frontier_rl.cli import app
from frontier_rl.core.world.grid import CellState
from frontier_rl.errors import MapError
from frontier_rl.io import load_map
from frontier_rl.io.houseexpo import _crossings, load_houseexpo


def write(path: Path, verts: object) -> Path:
    path.write_text(json.dumps({"verts": verts}))
    return path


def refused(path: Path, match: str, resolution: float = 0.05) -> str:
    with pytest.raises(MapError, match=match) as info:
        load_houseexpo(path, resolution=resolution)
    message = str(info.value)
    assert "\n" not in message and str(path) in message
    return message


# --------------------------------------------------------------------------- crossing outlines
CROSSING = {
    "bow tie": [[0, 0], [2, 2], [2, 0], [0, 2]],
    "bow tie, closed": [[0, 0], [2, 2], [2, 0], [0, 2], [0, 0]],
    "bow tie, off centre": [[0, 0], [5, 1], [5, 0], [0, 1.5]],
    "spike through a wall": [[0, 0], [4, 0], [4, 2], [2, 2], [2, -1], [1.5, 1], [0, 2]],
    "spike out and back across": [[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [1.5, 0.5], [2, 3], [0, 3]],
    "pentagram": [[np.cos(a) * 3, np.sin(a) * 3] for a in np.deg2rad([90, 234, 18, 162, 306])],
    "closing edge crosses": [[0, 0], [2, 0], [2, 2], [1, -1], [0, 2]],
    "figure eight": [[0, 0], [1, 1], [2, 0], [2, 2], [1, 1.5], [0, 2], [0.5, 1], [2.5, 1]],
    "crossing through a vertex": [[0, 0], [1, 1], [3, 3], [2, 0], [0, 2]],
    "grid-aligned edges crossing": [[0, 0], [4, 0], [4, 4], [2, 4], [2, 2], [2, -2], [0, -2]],
}


@pytest.mark.parametrize("name", list(CROSSING))
def test_self_crossing_polygons_are_refused(tmp_path: Path, name: str) -> None:
    verts = np.asarray(CROSSING[name], dtype=np.float64).tolist()
    message = refused(write(tmp_path / "bad.json", verts), r"crosses itself.*edge \d+-\d+ \(.*\) crosses edge \d+-\d+")
    assert message.count(" crosses edge ") == 1


def test_the_message_names_the_crossing_edges_by_the_files_vertex_numbers(tmp_path: Path) -> None:
    # the repeated vertex 1 is dropped, yet the edges keep the file's numbers
    path = write(tmp_path / "bowtie.json", [[0, 0], [2, 2], [2, 2], [2, 0], [0, 2]])
    message = refused(path, "crosses itself")
    assert "edge 0-2 (0, 0)-(2, 2) crosses edge 3-4 (2, 0)-(0, 2)" in message


@pytest.mark.parametrize(
    "verts",
    [
        [[0, 0], [5, 5], [10, 10], [10, 0], [5, 5], [0, 8]],  # two lobes of 25 and 20 m² (was: the second lost)
        [[0, 0], [5, 5], [10, 10], [10, 0], [5, 5], [0, 10]],  # two of 25 m² (was: "area 0 m^2")
        [[5, 5], [10, 10], [10, 0], [5, 5], [0, 10], [0, 0]],  # the same, starting at the shared point
    ],
)
def test_an_outline_crossing_itself_at_a_shared_vertex_is_refused(tmp_path: Path, verts: list[list[float]]) -> None:
    message = refused(write(tmp_path / "eight.json", verts), r"crosses itself")
    assert "passes through (5, 5) as vertex" in message and "crossing its first pass" in message


@pytest.mark.parametrize(
    "verts",
    [
        [[0, 0], [2, 0], [2, 1], [1, 1], [1, 0], [1, 1], [0, 1]],  # a slit of zero width: edges overlap
        [[0, 0], [1, 0], [1, 1], [2, 1], [2, 2], [1, 2], [1, 1], [0, 1]],  # two rooms touching at a corner
        [[0, 0], [4, 0], [4, 2], [2, 2], [2, 0], [2, 2], [0, 2]],  # a wall of zero width, touching the floor
        [[0, 0], [4, 0], [4, 4], [0, 4], [0, 2], [2, 2], [0, 2]],  # a zero-width spike from the outline
    ],
)
def test_outlines_that_only_touch_are_accepted(tmp_path: Path, verts: list[list[float]]) -> None:
    grid = load_houseexpo(write(tmp_path / "ok.json", verts), resolution=0.05).grid
    assert grid.count(CellState.FREE) > 0


@pytest.mark.parametrize("seed", range(30))
def test_crossings_match_a_brute_force_check(seed: int) -> None:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 30))
    verts = rng.integers(0, 5, size=(n, 2)).astype(np.float64) if seed % 2 else rng.random((n, 2)) * 10
    verts = verts[np.any(verts != np.roll(verts, -1, axis=0), axis=1)]
    if len(verts) < 3:
        return
    i, j = _crossings(verts)
    assert list(zip(i.tolist(), j.tolist(), strict=True)) == brute_force_crossings(verts)


def brute_force_crossings(verts: NDArray[np.float64], tol: float = 1e-6) -> list[tuple[int, int]]:
    n = len(verts)

    def side(k: int, p: NDArray[np.float64]) -> float:
        a, b = verts[k], verts[(k + 1) % n]
        d = b - a
        return float((d[0] * (p[1] - a[1]) - d[1] * (p[0] - a[0])) / np.hypot(d[0], d[1]))

    def straddles(k: int, m: int) -> bool:
        s, t = side(k, verts[m]), side(k, verts[(m + 1) % n])
        return (s > tol and t < -tol) or (s < -tol and t > tol)

    def through_vertex(k: int, m: int) -> bool:  # m ends inside k and the outline crosses k's line there
        a, b = verts[k], verts[(k + 1) % n]
        length = float(np.hypot(*(b - a)))
        for v in (m, (m + 1) % n):
            along = float(np.dot(verts[v] - a, b - a)) / length
            if abs(side(k, verts[v])) <= tol and tol < along < length - tol:
                before, after = side(k, verts[(v - 1) % n]), side(k, verts[(v + 1) % n])
                if (before > tol and after < -tol) or (before < -tol and after > tol):
                    return True
        return False

    return [(k, m) for k in range(n) for m in range(k + 2, n)
            if not (k == 0 and m == n - 1)
            and ((straddles(k, m) and straddles(m, k)) or through_vertex(k, m) or through_vertex(m, k))]  # fmt: skip


def test_a_large_outline_is_checked_quickly(tmp_path: Path) -> None:
    angles = np.linspace(0, 2 * np.pi, houseexpo.MAX_VERTICES, endpoint=False)
    circle = np.column_stack((5 * np.cos(angles), 5 * np.sin(angles)))
    assert (
        load_houseexpo(write(tmp_path / "circle.json", circle.tolist()), resolution=0.1).grid.count(CellState.FREE) > 0
    )
    circle[100], circle[5000] = circle[5000].copy(), circle[100].copy()  # two edges now cross the circle
    refused(write(tmp_path / "crossed.json", circle.tolist()), "crosses itself", resolution=0.1)


# ----------------------------------------------------------------------- repeated and degenerate
@pytest.mark.parametrize(
    "verts",
    [
        [[1, 1], [3, 1], [3, 2], [1, 2]],
        [[1, 1], [1, 1], [3, 1], [3, 2], [1, 2]],
        [[1, 1], [3, 1], [3, 1], [3, 1], [3, 2], [1, 2], [1, 2]],
        [[1, 1], [3, 1], [3, 2], [1, 2], [1, 1]],
        [[1, 1], [3, 1], [3, 2], [1, 2], [1, 1], [1, 1]],
        [[3, 2], [1, 2], [1, 1], [3, 1]],
    ],
)
def test_repeated_vertices_are_dropped_consistently(tmp_path: Path, verts: list[list[float]]) -> None:
    grid = load_houseexpo(write(tmp_path / "sq.json", verts), resolution=0.5, margin_m=0.0).grid
    assert grid.shape == (2, 4) and grid.origin == (1.0, 1.0) and grid.count(CellState.FREE) == 8


@pytest.mark.parametrize(
    "verts",
    [
        [],
        [[1, 1]],
        [[1, 1], [1, 1], [1, 1], [1, 1]],
        [[0, 0], [1, 1]],
        [[0, 0], [1, 1], [0, 0], [1, 1]],
        [[0, 0], [1, 0], [2, 0], [3, 0]],
        [[0, 0], [3, 0], [1, 0]],
        [[0, 0], [1e-6, 0], [0, 1e-6]],
    ],
)
def test_degenerate_polygons_are_refused(tmp_path: Path, verts: list[list[float]]) -> None:
    refused(write(tmp_path / "flat.json", verts), "degenerate polygon")


# ------------------------------------------------------------------------ malformed and oversized
@pytest.mark.parametrize(
    ("content", "match"),
    [
        ('{"verts": [[true, 0], [1, 0], [0, 1]]}', "vertex 0 is \\[true, 0\\]"),
        ('{"verts": [[0, 0], ["1", 0], [0, 1]]}', "vertex 1 is"),
        ('{"verts": [[0, 0], [1, 0], [0, 1, 2]]}', "vertex 2 is"),
        ('{"verts": [[0, 0], [1, 0], {"x": 0}]}', "vertex 2 is"),
        ('{"verts": [[0, 0], [1, 0], null]}', "vertex 2 is null"),
        ('{"verts": {"0": [0, 0]}}', "got dict"),
        ('{"verts": "0,0 1,0 0,1"}', "got str"),
        ('{"verts": [[0, 0], [1' + "0" * 400 + ", 0], [0, 1]]}", "too large"),
        ('{"verts": [[0, 0], [1e400, 0], [0, 1]]}', "finite"),
        ('{"verts": [[0, 0], [Infinity, 0], [0, 1]]}', "finite"),
        ('{"verts": ' + "[" * 100_000 + "]" * 100_000 + "}", "nested too deeply"),
        ("\xff\xfe not text", "cannot parse"),
    ],
)
def test_malformed_files(tmp_path: Path, content: str, match: str) -> None:
    path = tmp_path / "bad.json"
    path.write_bytes(content.encode("latin-1"))
    message = refused(path, match)
    assert len(message) < 300 + len(str(path))


def test_too_many_vertices(tmp_path: Path) -> None:
    angles = np.linspace(0, 2 * np.pi, houseexpo.MAX_VERTICES + 1, endpoint=False)
    path = write(tmp_path / "many.json", np.column_stack((np.cos(angles), np.sin(angles))).tolist())
    refused(path, f"{houseexpo.MAX_VERTICES + 1} vertices, more than the {houseexpo.MAX_VERTICES}")


def test_too_many_vertices_for_its_grid(tmp_path: Path) -> None:
    """A 99 m circle of 10,000 vertices (within both limits) was sampled for minutes."""
    angles = np.linspace(0, 2 * np.pi, houseexpo.MAX_VERTICES, endpoint=False)
    path = write(tmp_path / "round.json", (99 * np.column_stack((np.cos(angles), np.sin(angles)))).tolist())
    refused(path, "a polygon of 10000 vertices on a 3980 x 3980 grid is too much to rasterise")


def test_too_large_a_file(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(houseexpo, "MAX_FILE_BYTES", 100)
    path = write(tmp_path / "big.json", [[0, 0], [1, 0], [1, 1], [0, 1]] * 5)
    refused(path, "bytes is too large")


@pytest.mark.parametrize("resolution", [1e-300, 5e-324, 1e-7, 1e-4])
def test_grids_are_bounded_before_they_are_allocated(tmp_path: Path, resolution: float) -> None:
    path = write(tmp_path / "sq.json", [[0, 0], [10, 0], [10, 10], [0, 10]])
    refused(path, "more than 16000000 cells", resolution=resolution)


@pytest.mark.parametrize(
    ("verts", "match"),
    [
        ([[0, 0], [1e300, 0], [0, 1e300]], "within"),
        ([[-1e308, 0], [1e308, 0], [0, 1e308]], "within"),
        ([[0, 0], [2e6, 0], [0, 1]], "within"),
        ([[0, 0], [9e5, 0], [9e5, 9e5], [0, 9e5]], "more than 16000000 cells"),
    ],
)
def test_huge_coordinates_are_bounded(tmp_path: Path, verts: list[list[float]], match: str) -> None:
    refused(write(tmp_path / "huge.json", verts), match)


# ---------------------------------------------------------------------------------- at the CLI
@pytest.mark.parametrize("name", ["bow tie", "spike through a wall", "pentagram"])
def test_cli_refuses_a_crossing_outline_in_one_line(tmp_path: Path, name: str) -> None:
    folder = tmp_path / "a["
    folder.mkdir()
    path = write(folder / "x] [red]bad.json", np.asarray(CROSSING[name], dtype=np.float64).tolist())  # "a[/x] ..."
    result = CliRunner().invoke(app, ["explore", "--world", str(path)])
    assert result.exit_code == 2 and result.stdout == ""
    lines = result.stderr.splitlines()
    assert len(lines) == 1 and "crosses itself" in lines[0] and str(path) in lines[0], result.stderr


def test_load_map_refuses_a_crossing_outline(tmp_path: Path) -> None:
    with pytest.raises(MapError, match="crosses itself"):
        load_map(write(tmp_path / "bowtie.json", CROSSING["bow tie"]))


def test_an_integer_too_long_to_read_is_a_map_error(tmp_path: Path) -> None:
    path = tmp_path / "big.json"
    path.write_text('{"verts": [[0, ' + "1" * 5000 + "], [1, 0], [1, 1]]}")
    with pytest.raises(MapError, match="cannot parse HouseExpo JSON"):
        load_map(path)
