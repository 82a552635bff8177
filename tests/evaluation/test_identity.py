"""An experiment's identity (``experiment.json``) as a typed value: its codec reads back what it
writes, refuses a malformed file by the part that is wrong, and binds row checksums to the same id
as before it was typed (results folders written earlier keep opening)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from frontier_rl.core.sim.config import SimConfig
from frontier_rl.errors import ConfigError
from frontier_rl.evaluation.results.identity import ExperimentIdentity, TeamIdentity
from frontier_rl.evaluation.results.row_checksums import RowChecksum, row_checksum, sha256_hex
from frontier_rl.evaluation.results.store import ResultStore
from frontier_rl.evaluation.running.experiment import ExperimentConfig
from frontier_rl.evaluation.running.fingerprints import identity
from frontier_rl.swarm import Failure


def _team_identity() -> ExperimentIdentity:
    config = ExperimentConfig(
        methods=("fixed:0.75", "nearest@2:coordinated"), worlds=("office",), episodes=1, seed=7,
        failures=(Failure(1, 30.0),), comm_range=4.0,
    )  # fmt: skip
    return identity(config)


def test_the_identity_reads_back_what_it_writes() -> None:
    written = _team_identity()
    assert written.team == TeamIdentity(4.0, ("1@30",))
    text = json.dumps(written.to_json(), indent=1)
    read = ExperimentIdentity.from_json(json.loads(text))
    assert read.to_json() == written.to_json() and read.experiment_id == written.experiment_id


def test_the_experiment_id_is_the_hash_of_the_settings_without_the_methods() -> None:
    written = _team_identity()
    parts = {k: v for k, v in written.to_json().items() if k != "methods"}
    text = json.dumps(parts, sort_keys=True, separators=(",", ":"))
    assert written.experiment_id == sha256_hex(text)
    more = ExperimentIdentity.from_json({**written.to_json(), "methods": {"tour": "tour"}})
    assert more.experiment_id == written.experiment_id  # methods may be added to an experiment
    reseeded = ExperimentIdentity.from_json({**written.to_json(), "seed": 8})
    assert reseeded.experiment_id != written.experiment_id


@pytest.mark.parametrize(
    ("change", "part"),
    [({"seed": "7"}, "seed"), ({"seed": True}, "seed"), ({"worlds": "office"}, "worlds"),
     ({"resolution": "0.05"}, "resolution"), ({"sim": []}, "sim"), ({"methods": {"nearest": 1}}, "methods"),
     ({"team": {"comm_range": 4.0}}, "failures"), ({"team": {"comm_range": "far", "failures": []}}, "comm_range")],
)  # fmt: skip
def test_a_malformed_identity_is_refused_by_its_part(change: dict[str, object], part: str) -> None:
    with pytest.raises(ValueError, match=part):
        ExperimentIdentity.from_json({**_team_identity().to_json(), **change})


def test_a_folder_whose_identity_is_malformed_is_refused(tmp_path: Path) -> None:
    data = {**_team_identity().to_json(), "methods": {"nearest": ["nearest"]}}
    (tmp_path / "experiment.json").write_text(json.dumps(data))
    with pytest.raises(ConfigError, match=r"experiment\.json is not an experiment description"):
        ResultStore(tmp_path, _team_identity())


def test_a_row_checksum_line_reads_back_and_binds_row_trace_and_experiment() -> None:
    key = ("nearest", "office", 0)
    checksum = RowChecksum.of("e" * 64, "nearest", key, "nearest,office,0,...", '{"trace":1}')
    entry = json.loads(checksum.line())
    assert (entry["method"], entry["world"], entry["episode"]) == key
    assert RowChecksum.from_json(key, entry) == checksum
    assert checksum.trace_sha256 == sha256_hex('{"trace":1}')
    assert checksum.row_sha256 == row_checksum("e" * 64, "nearest", "nearest,office,0,...", checksum.trace_sha256)
    assert RowChecksum.of("f" * 64, "nearest", key, "nearest,office,0,...", '{"trace":1}') != checksum
    with pytest.raises(TypeError):
        RowChecksum.from_json(key, {**entry, "row_sha256": 1})


def test_the_simulator_settings_are_stored_as_json_holds_them() -> None:
    stored = _team_identity().to_json()["sim"]
    assert isinstance(stored, dict) and stored == json.loads(json.dumps(stored))
    assert stored["max_sim_time"] == SimConfig().max_sim_time
