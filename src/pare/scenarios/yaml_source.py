"""Reading YAML while remembering where each value was written, so errors can name a line."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import yaml

Path = tuple[str | int, ...]

# libyaml's parser when PyYAML was built with it (the wheels are), else the pure-Python one
_Loader: Any = getattr(yaml, "CSafeLoader", yaml.SafeLoader)


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
    """A file that is not valid YAML; carries the line where the parser gave up."""

    def __init__(self, message: str, line: int | None) -> None:
        super().__init__(message)
        self.line = line


def parse_yaml(text: str) -> YamlDocument:
    """Parse ``text`` (one YAML document) and record the line of every value."""
    loader = _Loader(text)
    document = YamlDocument(None)
    try:
        node = loader.get_single_node()
        if node is not None:
            _walk(node, (), document)  # before constructing: that expands merge keys (<<) in place
            document.data = loader.construct_document(node)
    except yaml.YAMLError as error:
        mark = getattr(error, "problem_mark", None)
        line = mark.line + 1 if mark is not None else None
        problem = getattr(error, "problem", None) or str(error)
        raise YamlSyntaxError(f"not valid YAML: {problem}", line) from None
    finally:
        loader.dispose()
    return document


def _walk(node: yaml.Node, path: Path, document: YamlDocument) -> None:
    document.lines[path] = node.start_mark.line + 1
    if isinstance(node, yaml.MappingNode):
        seen: set[str] = set()
        for key_node, value_node in node.value:
            key = key_node.value if isinstance(key_node, yaml.ScalarNode) else str(key_node.value)
            child = (*path, key)
            if key in seen:
                document.duplicate_keys.append(child)
            seen.add(key)
            _walk(value_node, child, document)
            document.lines[child] = key_node.start_mark.line + 1
    elif isinstance(node, yaml.SequenceNode):
        for index, item in enumerate(node.value):
            _walk(item, (*path, index), document)
