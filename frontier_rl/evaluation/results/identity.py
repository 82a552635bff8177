"""What an experiment's rows depend on (``experiment.json``): :class:`ExperimentIdentity`, its JSON
codec, the experiment id its row checksums bind to, and the check of a folder's stored identity
against the one a run brings (:func:`merged_identity`).

Rows of two runs may be mixed only where their identities agree: methods may be added and episodes
extended; the seed, the worlds (with their maps' hashes), the resolution and the settings not.
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Collection, Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TypeVar

from frontier_rl.config_diff import ABSENT, contrast, describe_differences, differences_between
from frontier_rl.errors import ConfigError, FrontierRLError, short_path, short_repr
from frontier_rl.map_fingerprint import MapFingerprint
from frontier_rl.swarm import TeamMethod

_T = TypeVar("_T")


@dataclass(frozen=True)
class TeamIdentity:
    """A team experiment's settings: the communication range (m, None for unlimited) and the
    failures as the command line writes them (``1@30``)."""

    comm_range: float | None
    failures: tuple[str, ...]


@dataclass(frozen=True)
class ExperimentIdentity:
    """Everything a row's values depend on.

    Attributes:
        seed: the experiment's first seed.
        worlds: each world's fingerprint (a generator's name, or a map with its grid's hash).
        resolution: the cell size (m) given for maps that carry none, or None.
        sim: the simulator's settings, as ``experiment.json`` holds them (nested JSON objects).
        methods: each method's fingerprint (a learned policy's names its model file's hash).
        team: a team experiment's settings; None for one without (older folders have none).
    """

    seed: int
    worlds: tuple[str, ...]
    resolution: float | None
    sim: Mapping[str, object]
    methods: Mapping[str, str]
    team: TeamIdentity | None = None

    def to_json(self) -> dict[str, object]:
        """The object ``experiment.json`` holds (``team`` only when there is one)."""
        data: dict[str, object] = {
            "seed": self.seed,
            "worlds": list(self.worlds),
            "resolution": self.resolution,
            "sim": json.loads(json.dumps(self.sim)),  # tuples become lists, as read back
            "methods": dict(self.methods),
        }
        if self.team is not None:
            data["team"] = {"comm_range": self.team.comm_range, "failures": list(self.team.failures)}
        return data

    @classmethod
    def from_json(cls, data: object) -> ExperimentIdentity:
        """The identity of an ``experiment.json`` object.

        Raises:
            ValueError: a part is missing or of the wrong type (the message names it).
        """
        if not isinstance(data, dict):
            raise ValueError("not a JSON object")
        team = data.get("team")
        if team is not None:
            team = TeamIdentity(_optional_number(team, "comm_range"), tuple(_strings(team, "failures")))
        return cls(
            seed=_part(data, "seed", int),
            worlds=tuple(_strings(data, "worlds")),
            resolution=_optional_number(data, "resolution"),
            sim=_part(data, "sim", dict),
            methods=_methods(data),
            team=team,
        )

    @property
    def experiment_id(self) -> str:
        """The SHA-256 (hex) of the identity without its methods: what rows of every method share,
        and what their checksums bind to."""
        parts = {part: value for part, value in self.to_json().items() if part != "methods"}
        text = json.dumps(parts, sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode("utf-8")).hexdigest()


def merged_identity(
    out: Path, stored: Mapping[str, object], identity: ExperimentIdentity, with_rows: Collection[str]
) -> ExperimentIdentity:
    """``identity`` with the methods of the identity ``stored`` in folder ``out`` added, where the two
    agree (``stored``: an ``experiment.json`` object that :meth:`ExperimentIdentity.from_json` reads).
    A method of no row there (``with_rows``: those of some) may have changed: every episode of one
    that failed is still to run, with the policy file fixed.

    Raises:
        ConfigError: a setting differs (each named with its value there and now, up to a few), or
            the fingerprint of a method with rows does (its model file or policy code changed).
    """
    _refuse_renamed_worlds(out, stored, identity.worlds)
    now = identity.to_json()
    parts = [*now, *(part for part in stored if part not in now)]
    differences = [
        d
        for part in parts
        if part != "methods"
        for d in differences_between(stored.get(part, ABSENT), now.get(part, ABSENT), part)
    ]
    if differences:
        raise ConfigError(
            f"--out {str(out)!r} holds results of a different configuration "
            f"({describe_differences(differences)}); choose another --out"
        )
    old_methods = _methods(stored)
    _refuse_methods_written_otherwise(out, old_methods, identity.methods)
    for method, fingerprint in identity.methods.items():
        old = old_methods.get(method)
        if old is not None and old != fingerprint and method in with_rows:
            there, here = contrast(old.removeprefix(f"{method}#"), fingerprint.removeprefix(f"{method}#"))
            raise ConfigError(
                f"--out {str(out)!r} holds results of {short_repr(method)} from another version of its model "
                f"file or policy code ({there} there, {here} now: any edit counts, a comment too); choose another "
                "--out or give the new version another file name"
            )
    return replace(identity, methods={**old_methods, **identity.methods})


def _refuse_renamed_worlds(out: Path, stored: Mapping[str, object], worlds: tuple[str, ...]) -> None:
    """Refuse a run that names a map of the folder's another way (``./maps/a.yaml``, an absolute
    path): the same map, by its hash, where the folder has its rows under the name it was given."""
    try:
        there = _strings(stored, "worlds")
    except ValueError:
        return  # said by the comparison of the parts that follows
    for old, new in zip(there, worlds, strict=False):
        was, now = MapFingerprint.parse(old), MapFingerprint.parse(new)
        if was.digest and was.digest == now.digest and was.spec != now.spec:
            raise ConfigError(
                f"--out {str(out)!r} has its rows of the map {short_path(now.spec)} under the name "
                f"{short_path(was.spec)}: name the map as there (or choose another --out)"
            )


def _refuse_methods_written_otherwise(out: Path, there: Mapping[str, str], now: Mapping[str, str]) -> None:
    """Refuse a method the folder holds written another way (``fixed:1`` for ``fixed:1.0``, a policy
    file by another path): its rows would be run again as a method of their own."""

    def canonical(method: str) -> str:
        try:
            return TeamMethod.parse(method).canonical
        except FrontierRLError:  # a name an older version wrote: compared as it is
            return method

    held = {canonical(method): method for method in there}
    for method, fingerprint in now.items():
        twin = held.get(canonical(method))
        # the same content too: a relative path there was resolved against the folder it was run from
        same_content = twin is not None and there[twin].removeprefix(twin) == fingerprint.removeprefix(method)
        if method not in there and same_content:
            raise ConfigError(
                f"--out {str(out)!r} holds the results of {short_repr(twin)}, which {short_repr(method)} writes "
                "another way: name it as there (or choose another --out)"
            )


def _part(data: Mapping[str, object], name: str, kind: type[_T]) -> _T:
    value = data.get(name)
    if not isinstance(value, kind) or (isinstance(value, bool) and kind is not bool):
        raise ValueError(f"{name} is not {kind.__name__}: {short_repr(value)}")
    return value


def _optional_number(data: object, name: str) -> float | None:
    value = data.get(name) if isinstance(data, dict) else ABSENT
    if value is None or (isinstance(value, int | float) and not isinstance(value, bool)):
        return value
    raise ValueError(f"{name} is not a number or null: {short_repr(value)}")


def _strings(data: object, name: str) -> list[str]:
    value = data.get(name) if isinstance(data, dict) else None
    if not isinstance(value, list) or not all(isinstance(item, str) for item in value):
        raise ValueError(f"{name} is not a list of strings: {short_repr(value)}")
    return value


def _methods(data: Mapping[str, object]) -> dict[str, str]:
    value = data.get("methods", {})
    if not isinstance(value, dict) or not all(isinstance(v, str) for v in value.values()):
        raise ValueError(f"methods is not an object of fingerprints: {short_repr(value)}")
    return value
