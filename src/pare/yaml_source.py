"""Reading YAML files safely while remembering where each value was written, so errors can name a line.

Every YAML file PARE reads from a user (scenarios, run and sweep configurations) goes through here, and
so is held to bounds that keep a hostile file from exhausting the machine:

* only a regular file is read (a FIFO would hang, ``/dev/zero`` would fill memory), and at most
  :data:`MAX_FILE_BYTES` of it;
* nesting is at most :data:`MAX_DEPTH` levels deep (libyaml's composer recurses in C and overflows the
  stack on some tens of thousands of levels, killing the process);
* aliases may not refer to the collection that contains them, and the document they expand to is at most
  :data:`MAX_EXPANDED_NODES` values and :data:`MAX_EXPANDED_CHARS` characters of keys and values (a few
  hundred bytes of nested aliases, or one long string named many times, otherwise expand to gigabytes as
  soon as the data is copied, validated or written out).

Every refusal is a :class:`YamlSyntaxError` with the line where it was found. YAML is only ever read with
the safe loader: no tag in a file can run code.
"""

from __future__ import annotations

import os
import re
import stat
from dataclasses import dataclass, field
from pathlib import Path as FilePath
from typing import Any

import yaml

Path = tuple[str | int, ...]

MAX_FILE_BYTES = 4 * 1024 * 1024
"""The largest YAML file read (the largest library scenario is under 40 KB)."""
MAX_DEPTH = 64
"""The deepest nesting of mappings and lists accepted (library scenarios nest about 10 deep)."""
MAX_EXPANDED_NODES = 200_000
"""The most values a document may hold once its aliases are expanded (a scenario holds a few thousand)."""
MAX_EXPANDED_CHARS = 2 * MAX_FILE_BYTES
"""The most characters the keys and scalar values of a document may add up to once its aliases are
expanded: twice what a file without aliases can hold, so an alias may repeat text but not multiply it."""
_INDICATORS = "[{-:?"
"""Characters without one of which no nesting level can open: fewer than :data:`_CHEAP_DEPTH_BOUND` of
them in a text bounds its depth without parsing it."""
_CHEAP_DEPTH_BOUND = 5_000

# libyaml's parser when PyYAML was built with it (the wheels are), else the pure-Python one
_Loader: Any = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
_SEXAGESIMAL_TAGS = frozenset({"tag:yaml.org,2002:int", "tag:yaml.org,2002:float"})
"""The tags YAML 1.1 gives a plain scalar written in base 60 ("1:1" is 61, 9:30 is 570, 1:30.5 is 90.5)."""
_STRING_TAG = "tag:yaml.org,2002:str"
_OPENING = (yaml.MappingStartEvent, yaml.SequenceStartEvent)
_CLOSING = (yaml.MappingEndEvent, yaml.SequenceEndEvent)


@dataclass
class YamlDocument:
    """Parsed data plus the line (1-based) of every mapping value and list item in it."""

    data: Any
    lines: dict[Path, int] = field(default_factory=dict)
    duplicate_keys: list[Path] = field(default_factory=list)
    """Keys written twice in one mapping (YAML keeps the last silently; we report them)."""

    def line_of(self, path: Path) -> int | None:
        """The line of ``path``, or of its nearest ancestor that has one."""
        for end in range(len(path), -1, -1):
            line = self.lines.get(path[:end])
            if line is not None:
                return line
        return None


class YamlSyntaxError(ValueError):
    """A file that is not valid YAML, or is beyond the bounds; carries the line where it was found."""

    def __init__(self, message: str, line: int | None) -> None:
        super().__init__(message)
        self.line = line


class UnreadableFile(OSError):
    """A file that cannot be read as text: missing, not a regular file, too large, or not UTF-8."""


READ_PIECE_BYTES = 1024 * 1024
"""How much of a file is read at a time (the whole file is never asked for at once)."""


def read_text_file(path: str | FilePath, *, max_bytes: int = MAX_FILE_BYTES) -> str:
    """Return the UTF-8 text of the regular file at ``path``.

    Raises:
        FileNotFoundError: there is no such file.
        UnreadableFile: it is a folder, a device, a FIFO or a socket; it is larger than ``max_bytes``; it
            is not UTF-8; or the system refused to read it. The message says which.
    """
    file = FilePath(path)
    try:
        found = os.stat(file)  # before opening: opening a FIFO blocks until a writer comes
    except FileNotFoundError:
        raise
    except OSError as error:
        raise UnreadableFile(f"cannot read it ({error.strerror})") from None
    if not stat.S_ISREG(found.st_mode):
        kind = "a folder" if stat.S_ISDIR(found.st_mode) else "not a regular file (a device, FIFO or socket)"
        raise UnreadableFile(f"cannot read it: it is {kind}")
    too_large = UnreadableFile(f"it is larger than {max_bytes // (1024 * 1024)} MiB, more than PARE reads")
    if found.st_size > max_bytes:
        raise too_large
    # Read in pieces: a read of max_bytes at once allocates that much whatever the file's size, and a
    # file may grow after the size was taken.
    pieces: list[bytes] = []
    total = 0
    try:
        with open(file, "rb") as handle:
            while total <= max_bytes:
                piece = handle.read(min(READ_PIECE_BYTES, max_bytes + 1 - total))
                if not piece:
                    break
                pieces.append(piece)
                total += len(piece)
    except OSError as error:
        raise UnreadableFile(f"cannot read it ({error.strerror})") from None
    if total > max_bytes:
        raise too_large
    data = b"".join(pieces)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as error:
        line = data[: error.start].count(b"\n") + 1
        raise UnreadableFile(f"line {line}: it is not UTF-8 text ({error.reason})") from None


def parse_yaml(text: str, *, clip_block_scalars: bool = False) -> YamlDocument:
    """Parse ``text`` (one YAML document) within the bounds, and record the line of every value.

    With ``clip_block_scalars``, a folded or literal block (``>`` or ``|``) written without a chomping
    indicator loses the one line break YAML ends it with: ``content: >`` followed by a paragraph is that
    paragraph, as the author meant it, not the paragraph and a newline (``>+`` and ``|+`` keep theirs).
    """
    if len(text) > MAX_FILE_BYTES:
        raise YamlSyntaxError(
            f"the text is longer than {MAX_FILE_BYTES} characters, more than PARE reads", None
        )
    if sum(text.count(mark) for mark in _INDICATORS) >= _CHEAP_DEPTH_BOUND:
        _check_depth(text)  # before composing, which recurses in C
    loader = _Loader(text)
    document = YamlDocument(None)
    try:
        node = loader.get_single_node()
        if node is not None:
            _check_expansion(node)
            _walk(node, document)  # before constructing: that expands merge keys (<<) in place
            if clip_block_scalars:
                _clip_block_scalars(node, text)
            document.data = loader.construct_document(node)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        line = mark.line + 1 if mark is not None else None
        problem = getattr(error, "problem", None) or str(error)
        raise YamlSyntaxError(f"not valid YAML: {problem}", line) from None
    finally:
        loader.dispose()
    return document


def load_yaml(text: str) -> Any:
    """The data of ``text`` (one YAML document), read within the same bounds as :func:`parse_yaml`."""
    return parse_yaml(text).data


def _check_depth(text: str) -> None:
    """Refuse nesting deeper than :data:`MAX_DEPTH`, reading the parser's events (which do not recurse)."""
    loader = _Loader(text)
    depth = 0
    try:
        while (event := loader.get_event()) is not None:
            if isinstance(event, _OPENING):
                depth += 1
                if depth > MAX_DEPTH:
                    raise YamlSyntaxError(
                        f"nested more than {MAX_DEPTH} levels deep, more than PARE reads",
                        event.start_mark.line + 1 if event.start_mark is not None else None,
                    )
            elif isinstance(event, _CLOSING):
                depth -= 1
    except yaml.YAMLError:
        pass  # a syntax error: composing reports it with its line
    finally:
        loader.dispose()


def _check_expansion(root: yaml.Node) -> None:
    """Refuse an alias inside the collection it refers to, nesting deeper than :data:`MAX_DEPTH` and
    documents that expand to more than :data:`MAX_EXPANDED_NODES` values or :data:`MAX_EXPANDED_CHARS`
    characters; each node is visited once (an alias shares its anchor's node, and so its sizes).
    """
    sizes: dict[int, int] = {}
    chars: dict[int, int] = {}
    on_path: set[int] = set()
    # An explicit stack: (node, depth, children left to enter); a node's size is known once it is left.
    stack: list[tuple[yaml.Node, int, list[yaml.Node]]] = []

    def enter(node: yaml.Node, depth: int) -> None:
        if id(node) in on_path:
            raise YamlSyntaxError(
                "an alias refers to a collection that contains it (the data would be infinite)",
                node.start_mark.line + 1,
            )
        if depth > MAX_DEPTH:
            raise YamlSyntaxError(
                f"nested more than {MAX_DEPTH} levels deep, more than PARE reads", node.start_mark.line + 1
            )
        on_path.add(id(node))
        stack.append((node, depth, list(_children(node))))

    enter(root, 1)
    while stack:
        node, depth, pending = stack[-1]
        while pending and id(pending[-1]) in sizes:
            pending.pop()
        if pending:
            enter(pending.pop(), depth + 1)
            continue
        stack.pop()
        on_path.discard(id(node))
        children = _children(node)
        size = 1 + sum(sizes[id(child)] for child in children)
        if size > MAX_EXPANDED_NODES:
            raise YamlSyntaxError(
                f"its aliases expand to more than {MAX_EXPANDED_NODES} values, more than PARE reads",
                node.start_mark.line + 1,
            )
        length = len(node.value) if isinstance(node, yaml.ScalarNode) else 0
        length += sum(chars[id(child)] for child in children)
        if length > MAX_EXPANDED_CHARS:
            raise YamlSyntaxError(
                f"its aliases expand to more than {MAX_EXPANDED_CHARS:,} characters, more than PARE reads",
                node.start_mark.line + 1,
            )
        sizes[id(node)] = size
        chars[id(node)] = length


def _children(node: yaml.Node) -> list[yaml.Node]:
    if isinstance(node, yaml.MappingNode):
        return [part for pair in node.value for part in pair]
    if isinstance(node, yaml.SequenceNode):
        return list(node.value)
    return []


_BLOCK_HEADER = re.compile(r"(?:[&!]\S*\s+)*[|>][1-9]?([+-]?)")
"""The start of a block scalar, from its node's start: an anchor or a tag, its style, then a chomping
indicator (``-``, ``+``) before or after an indentation digit (``|2-``, ``|-2``)."""
_STR_TAG = "tag:yaml.org,2002:str"


def _clip_block_scalars(root: yaml.Node, text: str) -> None:
    """Drop the final line break of every block scalar whose header has no chomping indicator (YAML's
    "clip", which keeps exactly one); each node once, since an alias shares its anchor's node.
    """
    seen: set[int] = set()
    stack = [root]
    while stack:
        node = stack.pop()
        if id(node) in seen:
            continue
        seen.add(id(node))
        if not isinstance(node, yaml.ScalarNode):
            stack.extend(_children(node))
            continue
        if node.style not in ("|", ">") or node.tag != _STR_TAG or not node.value.endswith("\n"):
            continue
        header = _BLOCK_HEADER.match(text, node.start_mark.index)
        if header is not None and not header.group(1):
            node.value = node.value[:-1]


def _walk(root: yaml.Node, document: YamlDocument) -> None:
    """Record every value's line (a mapping value's is its key's) and the keys written twice, in document
    order; iterative, so deep documents cannot exhaust Python's recursion limit.
    """
    stack: list[tuple[yaml.Node, Path, int]] = [(root, (), root.start_mark.line + 1)]
    while stack:
        node, path, line = stack.pop()
        document.lines[path] = line
        if isinstance(node, yaml.ScalarNode) and node.tag in _SEXAGESIMAL_TAGS and ":" in node.value:
            node.tag = _STRING_TAG  # "1:1" and 9:30 are text, as YAML 1.2 reads them, not 61 and 570
        children: list[tuple[yaml.Node, Path, int]] = []
        if isinstance(node, yaml.MappingNode):
            seen: set[str] = set()
            for key_node, value_node in node.value:
                key = key_node.value if isinstance(key_node, yaml.ScalarNode) else str(key_node.value)
                child = (*path, key)
                if key in seen:
                    document.duplicate_keys.append(child)
                seen.add(key)
                children.append((value_node, child, key_node.start_mark.line + 1))
        elif isinstance(node, yaml.SequenceNode):
            children = [
                (item, (*path, index), item.start_mark.line + 1) for index, item in enumerate(node.value)
            ]
        stack.extend(reversed(children))
