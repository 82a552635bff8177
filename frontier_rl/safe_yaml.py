"""The one YAML reader of frontier_rl: bounded, alias-free, and YAML-1.2 numbers everywhere.

Every YAML file the tool reads (a ROS map YAML, a ``--config`` file, a training run's
``config.yaml``) may come from a stranger, so :func:`load_yaml_file`

* refuses a file larger than :data:`MAX_YAML_BYTES` before reading it, and reads no more than that;
* refuses text that is not UTF-8;
* refuses every anchor (``&name``) and alias (``*name``), even a harmless one: an alias is how a
  1 KB "billion laughs" document grows without bound, and no file the tool writes uses one;
* refuses documents with more than :data:`MAX_YAML_NODES` nodes or nested deeper than
  :data:`MAX_YAML_DEPTH`;
* refuses a mapping that gives a key twice (YAML forbids it; PyYAML would keep the last value
  without a word, so a setting written twice, one of them a slip, would pass unnoticed);
* resolves plain scalars as YAML 1.2 (the ``yaml-cpp`` of ROS's ``map_server``) does for numbers:
  ``6e2``, ``-1E3``, ``1e-3``, ``.5`` and ``1.`` are floats, ``010`` is the integer 10, ``0o17``
  and ``0x1F`` are octal and hex; ``_`` may separate digits (``100_000``). Dates stay strings
  (YAML 1.2 has no timestamps) and ``1:30`` stays a string (no base-60 numbers).

Every refusal is one line naming the file.
"""

from __future__ import annotations

import codecs
import re
from collections.abc import Hashable
from enum import Enum
from pathlib import Path
from typing import Any

import yaml
from yaml.constructor import ConstructorError
from yaml.events import AliasEvent
from yaml.nodes import MappingNode, Node, ScalarNode

from frontier_rl.bounded_read import UnreadableFileError, read_bounded
from frontier_rl.errors import FrontierRLError, short_text

#: Largest YAML file read (bytes): 1 MiB. The tool's own files are under 2 KB.
MAX_YAML_BYTES = 1 << 20
#: Most nodes (scalars, lists and mappings) in one YAML document; the tool's own files have under 100.
MAX_YAML_NODES = 10_000
#: Deepest nesting of lists and mappings in one YAML document.
MAX_YAML_DEPTH = 32
#: Longest integer literal read (digits); Python refuses to parse ints beyond 4300 digits anyway.
MAX_INT_DIGITS = 100

_INT_TAG = "tag:yaml.org,2002:int"
_FLOAT_TAG = "tag:yaml.org,2002:float"
_TIMESTAMP_TAG = "tag:yaml.org,2002:timestamp"
_MERGE_TAG = "tag:yaml.org,2002:merge"
_DIGITS = r"[0-9][0-9_]*"
# YAML 1.2 core schema, with "_" allowed between digits as PyYAML allows.
_INT_RE = re.compile(rf"^(?:[-+]?{_DIGITS}|0o[0-7_]+|0x[0-9a-fA-F_]+)$")
_FLOAT_RE = re.compile(
    rf"^(?:[-+]?(?:\.{_DIGITS}|{_DIGITS}(?:\.[0-9_]*)?)(?:[eE][-+]?[0-9]+)?"
    r"|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$"
)
_NUMBER_START = list("-+0123456789.")


class YamlRefusedError(yaml.MarkedYAMLError):
    """A well-formed YAML document that the tool refuses to read (an alias, too many nodes, ...)."""


class _BoundedLoader(yaml.SafeLoader):
    """SafeLoader without anchors or aliases, with bounded size and YAML-1.2 numbers."""

    def __init__(self, stream: str) -> None:
        super().__init__(stream)
        self._node_count = 0
        self._depth = 0

    def compose_node(self, parent: Node | None, index: Any) -> Node | None:
        event = self.peek_event()  # type: ignore[no-untyped-call]
        if isinstance(event, AliasEvent) or getattr(event, "anchor", None) is not None:
            raise YamlRefusedError(
                problem="YAML anchors and aliases (&name, *name) are not allowed, not even a harmless one: "
                "write each value out in full",
                problem_mark=event.start_mark,
            )
        self._node_count += 1
        if self._node_count > MAX_YAML_NODES:
            raise YamlRefusedError(problem=f"more than {MAX_YAML_NODES} YAML nodes", problem_mark=event.start_mark)
        self._depth += 1
        try:
            if self._depth > MAX_YAML_DEPTH:
                raise YamlRefusedError(
                    problem=f"lists or mappings nested more than {MAX_YAML_DEPTH} deep", problem_mark=event.start_mark
                )
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_mapping(self, node: MappingNode, deep: bool = False) -> dict[Any, Any]:
        """A mapping, each key given once."""
        seen: set[Any] = set()
        for key_node, _ in node.value:
            if key_node.tag == _MERGE_TAG:  # "<<" merges a mapping in: SafeLoader flattens it, keys may repeat
                continue
            key = self.construct_object(key_node, deep=True)
            if not isinstance(key, Hashable):
                continue  # refused by SafeLoader below, as an unhashable key
            if key in seen:
                raise YamlRefusedError(
                    problem=f"the key {short_text(str(key), 60)!r} is given twice in one mapping",
                    problem_mark=key_node.start_mark,
                )
            seen.add(key)
        return super().construct_mapping(node, deep)

    def construct_yaml_int(self, node: ScalarNode) -> int:
        """A YAML 1.2 integer: decimal (leading zeros allowed), ``0o`` octal or ``0x`` hex."""
        text = str(self.construct_scalar(node)).replace("_", "")
        if len(text) > MAX_INT_DIGITS:
            raise ConstructorError(None, None, f"an integer of more than {MAX_INT_DIGITS} digits", node.start_mark)
        if text.startswith("0o"):
            return int(text[2:], 8)
        if text.startswith("0x"):
            return int(text[2:], 16)
        return int(text, 10)


_BoundedLoader.yaml_implicit_resolvers = {
    first: [(tag, regex) for tag, regex in resolvers if tag not in (_INT_TAG, _FLOAT_TAG, _TIMESTAMP_TAG)]
    for first, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_BoundedLoader.add_implicit_resolver(_INT_TAG, _INT_RE, _NUMBER_START)  # before float: "10" is an int
_BoundedLoader.add_implicit_resolver(_FLOAT_TAG, _FLOAT_RE, _NUMBER_START)
_BoundedLoader.add_constructor(_INT_TAG, _BoundedLoader.construct_yaml_int)


class _Dumper(yaml.SafeDumper):
    """SafeDumper that quotes a string wherever :class:`_BoundedLoader` would read a number (``"1e5"``,
    ``"0o17"``), so that what the tool writes it reads back the same."""


_Dumper.yaml_implicit_resolvers = {first: list(rs) for first, rs in _BoundedLoader.yaml_implicit_resolvers.items()}
_Dumper.add_multi_representer(Enum, lambda dumper, member: dumper.represent_data(member.value))


def dump_yaml(data: Any) -> str:
    """``data`` (plain dicts, lists, strings, numbers and enum members) as YAML text that
    :func:`parse_yaml` reads back equal (an enum member as its value), keys in their order."""
    return yaml.dump(data, Dumper=_Dumper, sort_keys=False)


def _describe(exc: yaml.YAMLError) -> str:
    """One bounded line for a PyYAML error: the problem and where it is (line, column; 1-based)."""
    if isinstance(exc, yaml.MarkedYAMLError):
        problem = exc.problem or exc.context or "invalid YAML"
        mark = exc.problem_mark or exc.context_mark
        where = f" (line {mark.line + 1}, column {mark.column + 1})" if mark is not None else ""
        return short_text(str(problem), 200) + where
    if isinstance(exc, yaml.reader.ReaderError):
        return f"character {exc.character!r} at position {exc.position} is not allowed in YAML"
    return short_text(str(exc), 200)


def parse_yaml(text: str) -> Any:
    """The one document in ``text``, read with the rules of this module.

    Raises:
        yaml.YAMLError: malformed YAML, or a refused one (:class:`YamlRefusedError`).
    """
    loader = _BoundedLoader(text)
    try:
        return loader.get_single_data()
    finally:
        loader.dispose()


def load_yaml_file(path: str | Path, error: type[FrontierRLError], what: str) -> Any:
    """The document in the YAML file at ``path``, read with the rules of this module.

    Args:
        path: the file (at most :data:`MAX_YAML_BYTES` bytes of UTF-8).
        error: the exception raised for every problem (``ConfigError``, ``MapError``).
        what: the file's role in messages ("config file", "map YAML", ...).

    Raises:
        error: one line naming ``what`` and ``path``: unreadable, too large, not UTF-8, malformed,
            an anchor or alias, too many nodes or too deep.
    """
    path = Path(path)
    try:
        data = read_bounded(path, MAX_YAML_BYTES)
    except UnreadableFileError as exc:
        if exc.size is None:
            raise error(f"cannot read {what} {path}: not a regular file") from None
        raise error(f"{what} {path} is {exc.size} bytes, more than the {MAX_YAML_BYTES} allowed") from None
    except OSError as exc:
        raise error(f"cannot read {what} {path}: {exc.strerror or exc}") from None
    bom = len(codecs.BOM_UTF8) if data.startswith(codecs.BOM_UTF8) else 0
    try:
        text = data[bom:].decode("utf-8")
    except UnicodeDecodeError as exc:
        offset = bom + exc.start
        raise error(f"{what} {path} is not UTF-8 text: byte 0x{data[offset]:02x} at offset {offset}") from None
    try:
        return parse_yaml(text)
    except YamlRefusedError as exc:
        raise error(f"{what} {path}: {_describe(exc)}") from None
    except yaml.YAMLError as exc:
        raise error(f"cannot parse {what} {path}: {_describe(exc)}") from None
    except (ValueError, RecursionError, MemoryError) as exc:  # a value no constructor should build
        raise error(f"cannot parse {what} {path}: {short_text(str(exc), 200)}") from None
