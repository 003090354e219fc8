"""A file is its content: attached paths read as the names the scenario's world gave that content.

A scenario names a file by the path it has in the world (its seed data, or a file an event creates):
``attachments: {contains: payslip_apr_2025.txt}``. An assistant may attach a renamed or moved copy of it
(``/Downloads/april.txt``), which is the right file; or a file that only bears the right name
(``/Downloads/payslip_apr_2025.txt`` holding something else), which is not. So before an attachment is
matched, each attached path is replaced by the world's paths of the same content:

* content the world has under one or more paths: those paths (the path attached itself is not kept: a
  right file under a wrong name is the right file);
* content the world never had, under a name (the last part of the path) that a world file has: nothing,
  since it is another file wearing a known file's name;
* other content under a new name (a file the assistant wrote): its own path.
"""

from __future__ import annotations

import posixpath
from collections.abc import Iterable, Mapping
from typing import Any

from pare.apps.files import normalize_path
from pare.errors import ToolError
from pare.scenarios.model import Scenario

ATTACHMENT_FIELDS = frozenset({"attachments", "attachment"})
"""Arguments and item fields that hold attached files' paths (email's list, messaging's one path)."""


class FileIdentity:
    """The world's files of one scenario, by content, to read attached paths as their content's names."""

    __slots__ = ("_names", "_paths")

    def __init__(self, world: Mapping[str, str]) -> None:
        paths: dict[str, list[str]] = {}
        for path, content in world.items():
            paths.setdefault(content, []).append(path)
        self._paths = {content: tuple(sorted(found)) for content, found in paths.items()}
        """Each content the world has, with its paths."""
        self._names = frozenset(posixpath.basename(path) for path in world)
        """The last part of every world file's path."""

    @classmethod
    def of(cls, scenario: Scenario) -> FileIdentity:
        """The files of ``scenario``'s world: its seed, and those its events create."""
        return cls(dict(_world_files(scenario)))

    def names(self, path: str, files: Mapping[str, Any]) -> list[str]:
        """What the attached ``path`` is, by its content in ``files`` (the Files app's ``files``)."""
        stored = files.get(path)
        content = stored.get("content") if isinstance(stored, Mapping) else None
        if not isinstance(content, str):
            return [path]  # gone since: the path is all there is to go by
        known = self._paths.get(content)
        if known is not None:
            return list(known)
        return [] if posixpath.basename(path) in self._names else [path]

    def read(self, value: Any, files: Mapping[str, Any]) -> Any:
        """An attachments value (a path, a list of paths, or nothing) read as its files' names: a list
        stays a list, one path becomes the one name it has (a list when several, ``None`` when none).
        """
        if isinstance(value, str):
            found = self.names(value, files)
            return found[0] if len(found) == 1 else (found or None)
        if isinstance(value, list):
            return [
                name
                for item in value
                for name in (self.names(item, files) if isinstance(item, str) else [item])
            ]
        return value


def _world_files(scenario: Scenario) -> Iterable[tuple[str, str]]:
    seeded = scenario.seed.get("files", {}).get("files") or {}
    if isinstance(seeded, Mapping):
        for path, stored in seeded.items():
            content = stored.get("content", "") if isinstance(stored, Mapping) else ""
            yield from _normal(path, content)
    for event in scenario.events:
        calls = [(event.tool, event.args)]
        if event.otherwise is not None:
            calls.append((event.otherwise.tool, event.otherwise.args))
        for tool, args in calls:
            if tool == "files__create_file":
                yield from _normal(args.get("path"), args.get("content", ""))


def _normal(path: Any, content: Any) -> Iterable[tuple[str, str]]:
    if isinstance(path, str) and isinstance(content, str):
        try:
            yield normalize_path(path), content
        except ToolError:
            return  # the loader reports a bad path
