"""Untrusted model files (issue 14): every metadata field is checked before anything is imported or
built, zip members are size-checked before they are read, and torch's errors become one line."""

from __future__ import annotations

import io
import json
import os
import pickle
import struct
import subprocess
import sys
import uuid
import warnings
import zipfile
from pathlib import Path
from typing import Any

import pytest
import torch
from typer.testing import CliRunner

from frontier_rl.cli import app
from frontier_rl.errors import ConfigError, FrontierRLError
from frontier_rl.inference import bounded_zip
from frontier_rl.inference.bounded_zip import MAX_ARCHIVE_BYTES, MAX_MEMBER_BYTES
from frontier_rl.inference.model_file import MAX_METADATA_BYTES, METADATA_ENTRY, WEIGHTS_ENTRY, read_metadata
from frontier_rl.policies import make_policy
from frontier_rl.rl.model_file import check_model_zip, env_spaces, load_policy

REPO = Path(__file__).resolve().parents[2]
MODEL4, MODEL5 = REPO / "models" / "model4.zip", REPO / "models" / "model5.zip"
MESSAGE_CHARS = 400
"""No error message about a model file is longer than this (the temporary paths included)."""

pytestmark = [
    pytest.mark.slow,  # model files loaded in fresh interpreters
    pytest.mark.skipif(not MODEL4.exists() or not MODEL5.exists(), reason="shipped models missing"),
]


# ------------------------------------------------------------------------------ helpers
def _members(path: Path) -> dict[str, bytes]:
    with zipfile.ZipFile(path) as archive:
        return {name: archive.read(name) for name in archive.namelist()}


@pytest.fixture(scope="module")
def model4() -> dict[str, bytes]:
    """The members of the shipped model 4 file."""
    return _members(MODEL4)


@pytest.fixture(scope="module")
def metadata4(model4: dict[str, bytes]) -> dict[str, Any]:
    """The metadata of the shipped model 4 file."""
    return dict(json.loads(model4[METADATA_ENTRY]))


@pytest.fixture(scope="module")
def state4(model4: dict[str, bytes]) -> dict[str, torch.Tensor]:
    """The weights of the shipped model 4 file."""
    return dict(torch.load(io.BytesIO(model4[WEIGHTS_ENTRY]), weights_only=True))


def _zip(path: Path, members: dict[str, bytes], compression: int = zipfile.ZIP_DEFLATED) -> Path:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # duplicate names warn
        with zipfile.ZipFile(path, "w", compression) as archive:
            for name, data in members.items():
                archive.writestr(name.split("#")[0], data)  # "name#2" writes a second "name"
    return path


def _model(path: Path, base: dict[str, bytes], metadata: object = None, **changes: bytes | None) -> Path:
    """A copy of the model ``base`` with its metadata (JSON value, or raw bytes) and other members
    replaced (None drops a member; ``policy_pth`` stands for ``policy.pth``)."""
    members = dict(base)
    if metadata is not None:
        members[METADATA_ENTRY] = metadata if isinstance(metadata, bytes) else json.dumps(metadata).encode()
    for key, data in changes.items():
        name = key.replace("_pth", ".pth")
        if data is None:
            members.pop(name, None)
        else:
            members[name] = data
    return _zip(path, members)


def _torch_bytes(value: object, **kwargs: Any) -> bytes:
    buffer = io.BytesIO()
    torch.save(value, buffer, **kwargs)
    return buffer.getvalue()


_CENTRAL = struct.Struct("<4s4B4HL2L5H2L")
_END = struct.Struct("<4s4H2LH")


def _declare_size(data: bytes, member: str, size: int) -> bytes:
    """The zip ``data`` with ``member``'s uncompressed size declared as ``size`` bytes (in a zip64
    field); no byte of any member changes, so nothing large is ever written or held."""
    end = data.rfind(b"PK\x05\x06")
    signature, disk, disk_cd, n_disk, count, _, cd_offset, comment_len = _END.unpack_from(data, end)
    entries, at = [], cd_offset
    for _ in range(count):
        header = list(_CENTRAL.unpack_from(data, at))
        name_len, extra_len, comment = header[12], header[13], header[14]
        name = data[at + 46 : at + 46 + name_len]
        extra = data[at + 46 + name_len : at + 46 + name_len + extra_len]
        tail = data[at + 46 + name_len + extra_len : at + 46 + name_len + extra_len + comment]
        if name.decode() == member:
            header[11] = 0xFFFFFFFF
            extra = struct.pack("<HHQ", 1, 8, size) + extra
            header[13] = len(extra)
        entries.append(_CENTRAL.pack(*header) + name + extra + tail)
        at += 46 + name_len + extra_len + comment
    directory = b"".join(entries)
    end_record = _END.pack(signature, disk, disk_cd, n_disk, count, len(directory), cd_offset, comment_len)
    return data[:cd_offset] + directory + end_record + data[end + _END.size :]


def _refused(path: Path, *needles: str, trust: bool = False) -> str:
    """Load ``path``; assert a one-line ConfigError naming the file and every needle, and that no
    warning was raised; return the message."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        with pytest.raises(ConfigError) as info:
            load_policy(path, trust=trust)
    message = str(info.value)
    assert not caught, [str(w.message) for w in caught]
    assert "\n" not in message and len(message) <= MESSAGE_CHARS, message
    assert path.name in message, message
    for needle in needles:
        assert needle in message, message
    for torch_text in ("weights_only", "will likely succeed", "Weights only load failed", "Traceback"):
        assert torch_text not in message, message
    return message


# ------------------------------------------------------------------------------ shipped models
@pytest.mark.parametrize(("path", "model", "kind"), [(MODEL4, 4, "weight"), (MODEL5, 5, "frontier")])
def test_shipped_models_still_load(path: Path, model: int, kind: str, capfd: pytest.CaptureFixture[str]) -> None:
    info = read_metadata(path)
    assert info is not None and info.model == model and info.observation_size == 64
    policy = make_policy(f"learned:{path}")
    assert policy.kind == kind  # type: ignore[attr-defined]
    with zipfile.ZipFile(path) as archive:  # far inside the limits
        sizes = [member.file_size for member in archive.infolist()]
    assert max(sizes) * 100 < MAX_MEMBER_BYTES and sum(sizes) * 100 < MAX_ARCHIVE_BYTES
    assert capfd.readouterr().err == ""


# ------------------------------------------------------------------------------ imports through metadata
_PROBE_CASES = [
    ("env_id", "{probe}:FrontierRL/WeightMap64-v0"),
    ("env_id", "{probe}:WeightMap64-v0"),
    ("env_id", "{probe}.sub:FrontierRL/WeightMap64-v0"),
    ("env_id", "FrontierRL/WeightMap64-v0:{probe}"),
    ("env_id", "{probe}:FrontierRL/FrontierChoice64-v0"),
    ("model", "{probe}:4"),
    ("observation_size", "{probe}:64"),
    ("algo", "{probe}:A2C"),
    ("algo", "{probe}.A2C"),
    ("algo", "{probe}"),
    ("features_dim", "{probe}:GridCNN"),
    ("timesteps", "{probe}"),
    ("format", "{probe}:1"),
    ("entry_point", "{probe}:Env"),
    ("policy_class", "{probe}:Policy"),
    ("kwargs", {"module": "{probe}"}),
]


@pytest.mark.parametrize(("field", "value"), _PROBE_CASES)
def test_a_module_named_in_any_metadata_field_is_never_imported(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, model4: dict[str, bytes], metadata4: dict[str, Any],
    field: str, value: object,
) -> None:  # fmt: skip
    probe = f"frontier_probe_{uuid.uuid4().hex[:12]}"
    marker = tmp_path / f"{probe}.imported"
    (tmp_path / f"{probe}.py").write_text(f"open({str(marker)!r}, 'w').write('imported')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.chdir(tmp_path)
    filled = json.loads(json.dumps(value).replace("{probe}", probe))
    path = _model(tmp_path / "evil.zip", model4, {**metadata4, field: filled})
    _refused(path, repr(field))
    with pytest.raises(ConfigError):
        read_metadata(path)
    with pytest.raises(ConfigError):
        make_policy(f"learned:{path}", trust_model=True)  # trust admits pickles, not bad metadata
    assert probe not in sys.modules and not marker.exists()


def test_no_module_is_imported_in_a_fresh_interpreter(tmp_path: Path, model4: dict[str, bytes],
                                                      metadata4: dict[str, Any]) -> None:  # fmt: skip
    """The issue's case, run where ``sys.modules`` is clean and the zip's folder is on the path."""
    marker = tmp_path / "evil_probe.imported"
    (tmp_path / "evil_probe.py").write_text(f"open({str(marker)!r}, 'w').write('imported')\n")
    paths = []
    for module in ("this", "evil_probe"):
        for field, value in _PROBE_CASES:
            filled = json.loads(json.dumps(value).replace("{probe}", module))
            paths.append(str(_model(tmp_path / f"{module}_{len(paths)}.zip", model4, {**metadata4, field: filled})))
    script = (
        "import json, sys\n"
        "from frontier_rl.errors import ConfigError\n"
        "from frontier_rl.policies import make_policy\n"
        "refused = 0\n"
        "for path in sys.argv[1:]:\n"
        "    try:\n"
        "        make_policy('learned:' + path)\n"
        "    except ConfigError:\n"
        "        refused += 1\n"
        "print(json.dumps({'refused': refused, 'imported': [m for m in ('this', 'evil_probe') if m in sys.modules]}))\n"
    )
    done = subprocess.run([sys.executable, "-c", script, *paths], cwd=tmp_path, capture_output=True, text=True,
                          timeout=300, env={**os.environ, "PYTHONPATH": str(REPO)})  # fmt: skip
    assert done.returncode == 0, done.stderr
    result = json.loads(done.stdout.strip().splitlines()[-1])
    assert result == {"refused": len(paths), "imported": []}
    assert "Beautiful is better than ugly" not in done.stdout + done.stderr
    assert not marker.exists()


def test_env_spaces_builds_only_the_projects_own_ids() -> None:
    for name in ("this:FrontierRL/WeightMap64-v0", "CartPole-v1", "FrontierRL/WeightMap64-v1", "", "x" * 5000):
        with pytest.raises(ConfigError) as info:
            env_spaces(name)
        assert len(str(info.value)) <= MESSAGE_CHARS


# ------------------------------------------------------------------------------ field types and ranges
@pytest.mark.parametrize(
    ("field", "value"),
    [
        ("model", "4"), ("model", 4.0), ("model", True), ("model", None), ("model", [4]), ("model", 0),
        ("model", 8), ("model", -4), ("model", 10**30),
        ("observation_size", "64"), ("observation_size", 64.0), ("observation_size", 128), ("observation_size", 0),
        ("observation_size", True), ("observation_size", 10**12),
        ("env_id", 4), ("env_id", None), ("env_id", ["FrontierRL/WeightMap64-v0"]), ("env_id", ""),
        ("env_id", "CartPole-v1"), ("env_id", "FrontierRL/Unknown64-v0"), ("env_id", "frontierrl/weightmap64-v0"),
        ("env_id", "FrontierRL/WeightMap64-v0 "), ("env_id", "FrontierRL/WeightMap-v0"),
        ("env_id", "FrontierRL/FrontierChoice64-v0"), ("env_id", "FrontierRL/WeightMapFrontiersPose64-v0"),
        ("algo", "A2C"), ("algo", "dqn"), ("algo", 1), ("algo", None), ("algo", ["a2c"]), ("algo", "a2c\n"),
        ("features_dim", "128"), ("features_dim", 128.0), ("features_dim", 128.5), ("features_dim", True),
        ("features_dim", 0), ("features_dim", -5), ("features_dim", 10**6), ("features_dim", 10**40),
        ("timesteps", "1e5"), ("timesteps", 1e5), ("timesteps", -1), ("timesteps", 10**13), ("timesteps", False),
        ("timesteps", {"n": 1}),
        ("format", 2), ("format", 0), ("format", "1"), ("format", 1.0), ("format", True), ("format", 10**20),
    ],
)  # fmt: skip
def test_a_wrong_type_or_range_is_refused_naming_the_field(
    tmp_path: Path, model4: dict[str, bytes], metadata4: dict[str, Any], field: str, value: object
) -> None:
    path = _model(tmp_path / "bad.zip", model4, {**metadata4, field: value})
    message = _refused(path)
    assert repr(field) in message or "metadata format" in message


@pytest.mark.parametrize(
    ("changes", "needle"),
    [
        ({"model": 5}, "env_id"),  # a model-5 file claiming the model-4 env
        ({"env_id": "FrontierRL/FrontierChoice64-v0"}, "env_id"),  # and the other way round
        ({"observation_size": 250}, "env_id"),
        ({"model": 3, "env_id": "FrontierRL/WeightMap64-v0"}, "env_id"),
        ({"model": 1, "env_id": "FrontierRL/PointMapFrontiersPose-v0"}, "env_id"),
    ],
)
def test_the_env_id_must_fit_the_model_and_size(
    tmp_path: Path, model4: dict[str, bytes], metadata4: dict[str, Any], changes: dict[str, object], needle: str
) -> None:
    _refused(_model(tmp_path / "mismatch.zip", model4, {**metadata4, **changes}), needle)


def _padded(metadata: dict[str, Any], size: int) -> bytes:
    text = json.dumps(metadata)
    return (text[:-1] + " " * (size - len(text)) + "}").encode()


@pytest.mark.parametrize(
    ("make", "needle"),
    [
        (lambda m: b"", "not valid JSON"),
        (lambda m: b"{", "not valid JSON"),
        (lambda m: b"\xff\xfe{}", "not valid JSON"),
        (lambda m: b"[]", "JSON object"),
        (lambda m: b"null", "JSON object"),
        (lambda m: b"4", "JSON object"),
        (lambda m: b'"FrontierRL/WeightMap64-v0"', "JSON object"),
        (lambda m: b"[" * 100_000 + b"]" * 100_000, "unpacks to"),
        (lambda m: b"[" * 30_000 + b"]" * 30_000, "not valid JSON"),
        (lambda m: b'{"model": ' + b"9" * 5000 + b"}", "not valid JSON"),
        (lambda m: json.dumps(m).replace('"model": 4', '"model": 4, "model": 4').encode(), "twice"),
        (lambda m: json.dumps(m).replace('"timesteps": 100000', '"timesteps": NaN').encode(), "not valid JSON"),
        (lambda m: json.dumps(m).replace('"features_dim": 128', '"features_dim": Infinity').encode(), "JSON"),
        (lambda m: json.dumps({k: v for k, v in m.items() if k != "algo"}).encode(), "'algo' missing"),
        (lambda m: json.dumps({**m, "extra": 1}).encode(), "unknown metadata field"),
        (lambda m: json.dumps({**m, **{f"k{i}": i for i in range(1000)}}).encode(), "unknown metadata field"),
        (lambda m: _padded(m, MAX_METADATA_BYTES + 1), "unpacks to"),
    ],
)
def test_malformed_metadata_is_one_line(tmp_path: Path, model4: dict[str, bytes], metadata4: dict[str, Any],
                                        make: Any, needle: str) -> None:  # fmt: skip
    _refused(_model(tmp_path / "bad.zip", model4, make(metadata4)), needle)


def test_metadata_just_inside_the_limit_is_read(tmp_path: Path, model4: dict[str, bytes],
                                                metadata4: dict[str, Any]) -> None:  # fmt: skip
    path = _model(tmp_path / "padded.zip", model4, _padded(metadata4, MAX_METADATA_BYTES))
    assert read_metadata(path) == read_metadata(MODEL4)


@pytest.mark.parametrize(
    ("field", "value"),
    [("env_id", "x" * 60_000), ("algo", "\n" * 20_000), ("model", "9" * 60_000), ("features_dim", [[1] * 9000]),
     ("timesteps", {"a" * 30_000: 1}), ("model", 10**4000), ("a" * 60_000, 1)],
    ids=["long-env-id", "newlines", "long-digits", "big-list", "long-key-dict", "huge-int", "long-field-name"],
)  # fmt: skip
def test_a_huge_value_is_quoted_cut(tmp_path: Path, model4: dict[str, bytes], metadata4: dict[str, Any],
                                    field: str, value: object) -> None:  # fmt: skip
    message = _refused(_model(tmp_path / "huge.zip", model4, {**metadata4, field: value}))
    assert len(message) < 400 and "\n" not in message
    assert any(mark in message for mark in ("…", "...", "<an integer of"))  # cut, abbreviated or described


# ------------------------------------------------------------------------------ zip bombs and sizes
def test_a_training_checkpoint_is_bounded_before_sb3_reads_it(tmp_path: Path, model4: dict[str, bytes]) -> None:
    """``train --resume`` reads the newest checkpoint with SB3's ``set_parameters``; it is checked first."""
    plain = _zip(tmp_path / "plain.zip", model4)
    check_model_zip(plain)  # a checkpoint as SB3 writes it passes
    bomb = tmp_path / "model_64_steps.zip"
    bomb.write_bytes(_declare_size(plain.read_bytes(), "policy.optimizer.pth", 16 * 1024**3))
    with pytest.raises(ConfigError, match="17179869184"):
        check_model_zip(bomb)


def test_a_member_declaring_16_gib_is_refused_before_it_is_read(tmp_path: Path, model4: dict[str, bytes]) -> None:
    for member in (WEIGHTS_ENTRY, METADATA_ENTRY, "data", "policy.optimizer.pth"):
        plain = _zip(tmp_path / "plain.zip", model4).read_bytes()
        bomb = tmp_path / f"bomb_{member}.zip"
        bomb.write_bytes(_declare_size(plain, member, 16 * 1024**3))
        _refused(bomb, repr(member), "17179869184")
        _refused(bomb, trust=True)  # --trust-model does not lift the limits


def test_a_deflated_zeros_bomb_is_refused(tmp_path: Path, model4: dict[str, bytes]) -> None:
    zeros = bytes(8 * 1024**2)  # deflates ~1000:1
    _refused(_model(tmp_path / "zeros.zip", model4, policy_pth=zeros), "zip bomb")
    _refused(_model(tmp_path / "zeros_data.zip", model4, data=zeros), "zip bomb")


def test_the_member_limit_holds_whatever_the_ratio(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch, model4: dict[str, bytes]
) -> None:
    monkeypatch.setattr(bounded_zip, "MAX_MEMBER_BYTES", 1024**2)
    monkeypatch.setattr(bounded_zip, "MAX_COMPRESSION_RATIO", 10**9)
    _refused(_model(tmp_path / "big.zip", model4, policy_pth=os.urandom(1024**2 + 1)), "1048576 allowed")
    _refused(_model(tmp_path / "zeros.zip", model4, policy_pth=bytes(2 * 1024**2)), "1048576 allowed")


def test_the_archive_limit_holds(tmp_path: Path, monkeypatch: pytest.MonkeyPatch, model4: dict[str, bytes]) -> None:
    monkeypatch.setattr(bounded_zip, "MAX_ARCHIVE_BYTES", 2 * 1024**2)
    _refused(_model(tmp_path / "many.zip", model4, extra_a=os.urandom(800_000), extra_b=os.urandom(800_000)),
             "unpacks to")  # fmt: skip


@pytest.mark.parametrize(
    ("build", "needle"),
    [
        (lambda m: {**m, **{f"pad{i}": b"" for i in range(100)}}, "members"),
        (lambda m: {**m, "frontier_rl.json#2": m[METADATA_ENTRY]}, "twice"),
        (lambda m: {**m, "policy.pth#2": m[WEIGHTS_ENTRY]}, "twice"),
    ],
)
def test_odd_member_lists_are_refused(tmp_path: Path, model4: dict[str, bytes], build: Any, needle: str) -> None:
    _refused(_zip(tmp_path / "odd.zip", build(model4)), needle)


def test_a_directory_declaring_many_members_is_refused_before_it_is_parsed(
    tmp_path: Path, model4: dict[str, bytes]
) -> None:
    data = bytearray(_zip(tmp_path / "plain.zip", model4).read_bytes())
    end = data.rfind(b"PK\x05\x06")
    struct.pack_into("<2H", data, end + 8, 60_000, 60_000)
    path = tmp_path / "directory.zip"
    path.write_bytes(bytes(data))
    _refused(path, "60000 members")


@pytest.mark.parametrize("method", [zipfile.ZIP_BZIP2, zipfile.ZIP_LZMA])
def test_only_stored_or_deflated_members_are_read(tmp_path: Path, model4: dict[str, bytes], method: int) -> None:
    """bzip2 and LZMA members are not inflated in bounded steps by :mod:`zipfile`."""
    _refused(_zip(tmp_path / "method.zip", model4, method), "compression method")


def test_a_bomb_inside_policy_pth_is_refused(tmp_path: Path, model4: dict[str, bytes]) -> None:
    inner = _members_of(_torch_bytes({"w": torch.zeros(2 * 1024**2)}))
    deflated = io.BytesIO()
    with zipfile.ZipFile(deflated, "w", zipfile.ZIP_DEFLATED) as archive:
        for name, data in inner.items():
            archive.writestr(name, data)
    _refused(_model(tmp_path / "inner.zip", model4, policy_pth=deflated.getvalue()), "policy.pth", "zip bomb")
    declared = _declare_size(model4[WEIGHTS_ENTRY], "archive/data/0", 16 * 1024**3)
    _refused(_model(tmp_path / "inner16.zip", model4, policy_pth=declared), "policy.pth", "17179869184")


def _members_of(data: bytes) -> dict[str, bytes]:
    with zipfile.ZipFile(io.BytesIO(data)) as archive:
        return {name: archive.read(name) for name in archive.namelist()}


# ------------------------------------------------------------------------------ corrupt weights
class _Payload:
    """Pickles to a call of ``os.system`` (it must never run)."""

    def __init__(self, marker: Path) -> None:
        self.marker = marker

    def __reduce__(self) -> tuple[Any, ...]:
        return (os.system, (f"touch {self.marker}",))


def _weights(kind: str, state: dict[str, torch.Tensor], model4: dict[str, bytes], marker: Path) -> bytes:
    real = model4[WEIGHTS_ENTRY]
    first = next(iter(state))
    if kind == "payload":
        return _torch_bytes({**state, first: _Payload(marker)})
    if kind == "payload_only":
        return pickle.dumps(_Payload(marker))
    if kind == "empty":
        return b""
    if kind == "random":
        return os.urandom(4096)
    if kind == "truncated":
        return real[: len(real) // 2]
    if kind == "legacy":
        return _torch_bytes(state, _use_new_zipfile_serialization=False)
    if kind == "tensor":
        return _torch_bytes(torch.zeros(3))
    if kind == "list":
        return _torch_bytes(list(state.values()))
    if kind == "int_keys":
        return _torch_bytes(dict(enumerate(state.values())))
    if kind == "other_model":
        return _members(MODEL5)[WEIGHTS_ENTRY]
    if kind == "nan":
        return _torch_bytes({**state, first: torch.full_like(state[first], float("nan"))})
    if kind == "float64":
        return _torch_bytes({**state, first: state[first].double()})
    if kind == "missing":
        return _torch_bytes({k: v for k, v in state.items() if k != first})
    if kind == "extra":
        return _torch_bytes({**state, "extra.weight": torch.zeros(2)})
    if kind == "shape":
        return _torch_bytes({**state, first: state[first].flatten()})
    if kind == "broadcast":  # a 10^12-element view of one float: its shape is refused, nothing is computed
        return _torch_bytes({**state, first: torch.zeros(1).expand(10**6, 10**6)})
    if kind == "short_record":
        members = _members_of(real)
        record = next(name for name in members if name.endswith("data/0"))
        members[record] = members[record][:4]
        buffer = io.BytesIO()
        with zipfile.ZipFile(buffer, "w") as archive:
            for name, data in members.items():
                archive.writestr(name, data)
        return buffer.getvalue()
    raise AssertionError(kind)


@pytest.mark.parametrize(
    ("kind", "needle"),
    [
        ("payload", "objects other than tensors"), ("payload_only", "torch"), ("empty", "torch"),
        ("random", "torch"), ("truncated", "policy.pth"), ("legacy", "torch's zip format"),
        ("tensor", "named tensors"), ("list", "named tensors"), ("int_keys", "named tensors"),
        ("other_model", "does not fit"), ("nan", "not finite"), ("float64", "does not fit"),
        ("missing", "missing"), ("extra", "unexpected"), ("shape", "does not fit"), ("broadcast", "does not fit"),
        ("short_record", "corrupt"),
    ],
)  # fmt: skip
def test_a_tampered_policy_pth_is_one_line(
    tmp_path: Path, model4: dict[str, bytes], state4: dict[str, torch.Tensor], kind: str, needle: str,
    capfd: pytest.CaptureFixture[str],
) -> None:  # fmt: skip
    marker = tmp_path / "payload_ran"
    path = _model(tmp_path / "tampered.zip", model4, policy_pth=_weights(kind, state4, model4, marker))
    _refused(path, needle)
    assert not marker.exists()
    assert capfd.readouterr().err == ""


def test_corrupt_compressed_bytes_are_one_line(tmp_path: Path, model4: dict[str, bytes]) -> None:
    data = bytearray(_zip(tmp_path / "plain.zip", model4).read_bytes())
    with zipfile.ZipFile(io.BytesIO(bytes(data))) as archive:
        member = archive.getinfo(WEIGHTS_ENTRY)
    start = member.header_offset + 30 + len(member.filename.encode()) + len(member.extra)
    for at in range(start + 1000, start + 1100):
        data[at] ^= 0xFF
    path = tmp_path / "flipped.zip"
    path.write_bytes(bytes(data))
    _refused(path, "policy.pth", "corrupt")


# ------------------------------------------------------------------------------ not model files
@pytest.mark.parametrize(
    ("content", "needle"),
    [
        (b"", "not a frontier_rl model"),
        (b"not a zip at all", "not a frontier_rl model"),
        (b"\x89PNG\r\n\x1a\n" + bytes(100), "not a frontier_rl model"),
        (b"PK\x05\x06" + bytes(18), "--trust-model"),  # an empty zip: no metadata
        (None, "not a frontier_rl model"),  # the first half of a model file
    ],
)
def test_a_file_that_is_not_a_model_is_one_line(tmp_path: Path, content: bytes | None, needle: str) -> None:
    path = tmp_path / "notmodel.zip"
    path.write_bytes(content if content is not None else MODEL4.read_bytes()[: MODEL4.stat().st_size // 2])
    _refused(path, needle)


def test_a_missing_file_a_folder_or_a_device_is_one_line_naming_which(tmp_path: Path) -> None:
    _refused(tmp_path / "none.zip", "not found")
    (tmp_path / "folder.zip").mkdir()
    _refused(tmp_path / "folder.zip", "is a folder")
    if Path("/dev/zero").exists():  # endless: must be refused before it is read
        _refused(Path("/dev/zero"), "not a regular file")


# ------------------------------------------------------------------------------ --trust-model
def _serialized_payload(marker: Path) -> bytes:
    """SB3 ``data`` whose policy class is a pickle that calls ``os.system`` when loaded."""
    import base64

    blob = base64.b64encode(pickle.dumps(_Payload(marker))).decode()
    return json.dumps({"policy_class": {":type:": "<class 'abc.ABCMeta'>", ":serialized:": blob}}).encode()


def test_pickled_code_never_runs_without_trust(tmp_path: Path, model4: dict[str, bytes]) -> None:
    marker = tmp_path / "payload_ran"
    members = {**model4, "data": _serialized_payload(marker)}
    foreign = _zip(tmp_path / "foreign.zip", {k: v for k, v in members.items() if k != METADATA_ENTRY})
    _refused(foreign, "--trust-model")
    with_metadata = _model(tmp_path / "with_metadata.zip", model4, data=_serialized_payload(marker))
    _, info = load_policy(with_metadata, trust=True)  # metadata present: rebuilt, never unpickled
    assert info is not None and info.model == 4
    assert not marker.exists()


def test_a_trusted_foreign_zip_still_loads(tmp_path: Path, model4: dict[str, bytes]) -> None:
    foreign = _zip(tmp_path / "foreign.zip", {k: v for k, v in model4.items() if k != METADATA_ENTRY})
    _refused(foreign, "--trust-model")
    policy, info = load_policy(foreign, trust=True)
    assert info is None and int(policy.action_space.n) == 100  # type: ignore[attr-defined]
    broken = _zip(tmp_path / "broken.zip", {k: v for k, v in model4.items() if k not in (METADATA_ENTRY, "data")})
    _refused(broken, "could not be loaded", trust=True)


# ------------------------------------------------------------------------------ policy names and the CLI
@pytest.mark.parametrize("spec", ["bogus" * 2000, "fixed:" + "9" * 5000, "fixed:x" + "[" * 3000])
def test_a_long_policy_name_is_quoted_cut(spec: str) -> None:
    with pytest.raises(FrontierRLError) as info:
        make_policy(spec)
    assert len(str(info.value)) <= MESSAGE_CHARS and "…" in str(info.value)


_CLI_CASES = ["env_this", "features_str", "huge_env", "bomb16", "zeros", "payload", "not_zip", "no_metadata"]


def _cli_model(kind: str, tmp_path: Path, model4: dict[str, bytes], metadata4: dict[str, Any]) -> Path:
    path = tmp_path / f"{kind}.zip"
    if kind == "env_this":
        return _model(path, model4, {**metadata4, "env_id": "this:FrontierRL/WeightMap64-v0"})
    if kind == "features_str":
        return _model(path, model4, {**metadata4, "features_dim": "128"})
    if kind == "huge_env":
        return _model(path, model4, {**metadata4, "env_id": "x" * 40_000})
    if kind == "bomb16":
        path.write_bytes(_declare_size(_zip(tmp_path / "plain.zip", model4).read_bytes(), WEIGHTS_ENTRY, 16 << 30))
        return path
    if kind == "zeros":
        return _model(path, model4, policy_pth=bytes(8 << 20))
    if kind == "payload":
        return _model(path, model4, policy_pth=_torch_bytes({"a": _Payload(tmp_path / "payload_ran")}))
    if kind == "not_zip":
        path.write_text("hello\n")
        return path
    if kind == "no_metadata":
        return _zip(path, {k: v for k, v in model4.items() if k != METADATA_ENTRY})
    raise AssertionError(kind)


@pytest.mark.parametrize("kind", _CLI_CASES)
def test_explore_with_a_bad_model_file_is_one_line_and_exit_2(
    tmp_path: Path, model4: dict[str, bytes], metadata4: dict[str, Any], kind: str
) -> None:
    path = _cli_model(kind, tmp_path, model4, metadata4)
    result = CliRunner().invoke(app, ["explore", "--world", "office", "--policy", f"learned:{path}", "--json"])
    assert result.exit_code == 2, result.output
    lines = [line for line in result.stderr.splitlines() if line.strip()]
    assert len(lines) == 1 and path.name in lines[0], result.stderr
    assert len(lines[0]) <= MESSAGE_CHARS + 20
    assert result.stdout.strip() == "" and "Traceback" not in result.output
    assert not (tmp_path / "payload_ran").exists()


@pytest.mark.parametrize("metadata", [7, "x", [1, 2], {"": 7}])
def test_attributes_the_pickle_sets_on_the_weights_are_dropped(
    tmp_path: Path, model4: dict[str, bytes], state4: dict[str, torch.Tensor], metadata: object
) -> None:
    """torch reads ``state_dict._metadata``; a tampered one must neither crash nor reach it."""
    from collections import OrderedDict

    state: Any = OrderedDict(state4)
    state._metadata = metadata
    path = _model(tmp_path / "attrs.zip", model4, policy_pth=_torch_bytes(state))
    policy, info = load_policy(path)
    assert info is not None and all(torch.equal(policy.state_dict()[k], v) for k, v in state4.items())


def test_a_training_checkpoint_is_named_as_one_not_as_a_strangers_file(
    tmp_path: Path, model4: dict[str, bytes]
) -> None:
    """A checkpoint of ``frontier-rl train`` (no metadata: it keeps the whole training state) was
    said not to be written by ``frontier-rl train``."""
    members = {name: data for name, data in model4.items() if name != METADATA_ENTRY}
    folder = tmp_path / "checkpoints"
    folder.mkdir()
    with pytest.raises(ConfigError, match=r"is a checkpoint of 'frontier-rl train'.*model\.zip or best_model\.zip"):
        make_policy(f"learned:{_zip(folder / 'model_240_steps.zip', members)}")
    with pytest.raises(ConfigError, match="was not written by 'frontier-rl train'"):
        make_policy(f"learned:{_zip(tmp_path / 'downloaded.zip', members)}")
