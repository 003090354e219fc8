"""Matching action-log entries against the action patterns of scenario files."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime
from typing import Any

from pare.scenarios.file_identity import ATTACHMENT_FIELDS
from pare.scenarios.matchers import Matcher, compile_matcher, written_at
from pare.scenarios.model import ActionPattern
from pare.scenarios.reading import CallReader
from pare.sim.log import LogEntry


def event_positions(log: Iterable[LogEntry]) -> dict[str, int]:
    """Log index at which each scheduled event fired (its first successful call)."""
    positions: dict[str, int] = {}
    for entry in log:
        if entry.actor == "env" and entry.event_id and entry.ok and entry.event_id not in positions:
            positions[entry.event_id] = entry.index
    return positions


@dataclass(frozen=True, slots=True)
class CompiledPattern:
    """An :class:`ActionPattern` ready to test log entries."""

    pattern: ActionPattern
    args: tuple[tuple[str, Matcher], ...]
    result: Matcher | None
    start: datetime
    tools: frozenset[str] | None = None
    screen: Matcher | None = None
    people: frozenset[str] | None = None
    """With ``to``: who the call must have told."""
    via: frozenset[str] | None = None
    reads_files: bool = False
    """Whether an argument matcher reads attached files (which are read by their content)."""
    reads_days: bool = False
    """Whether an argument matcher reads days or times in text: they are read as of the call's time."""

    @classmethod
    def of(cls, pattern: ActionPattern, start: datetime) -> CompiledPattern:
        """Compile ``pattern``; relative times in its matchers resolve against ``start``.

        Compiled once per pattern and start, and kept on the pattern: every episode of a scenario
        compiles its patterns (its event triggers, the oracle's conditions) from the same two, and a
        compiled pattern holds no state, so the episodes can share it.
        """
        return pattern.derived((CompiledPattern, start), lambda: cls._compile(pattern, start))

    @classmethod
    def _compile(cls, pattern: ActionPattern, start: datetime) -> CompiledPattern:
        args = tuple((name, compile_matcher(raw)) for name, raw in pattern.args.items())
        result = compile_matcher(pattern.result) if pattern.result is not None else None
        tools = None if pattern.tools is None else frozenset(pattern.tools)
        screen = compile_matcher(pattern.screen) if pattern.screen is not None else None
        via = None if pattern.via is None else frozenset(pattern.via)
        reads_files = any(name in ATTACHMENT_FIELDS for name in pattern.args)
        reads_days = any(matcher.reads_days for _, matcher in args)
        return cls(pattern, args, result, start, tools, screen, pattern.people, via, reads_files, reads_days)

    @property
    def needs_reader(self) -> bool:
        """Whether matching reads app data beyond the call (whom it told, attached files' content)."""
        return self.people is not None or self.reads_files

    @property
    def needs_event_positions(self) -> bool:
        """Whether matching depends on when events fired (``after_event`` / ``before_event``)."""
        return self.pattern.after_event is not None or self.pattern.before_event is not None

    def matches_call(self, entry: LogEntry) -> bool:
        """Whether ``entry`` is the kind of call meant: actor, tool, app, kind, mode, outcome."""
        pattern = self.pattern
        if pattern.actor != "any" and entry.actor != pattern.actor:
            return False
        if self.tools is not None and f"{entry.app}__{entry.tool}" not in self.tools:
            return False
        if pattern.app is not None and entry.app != pattern.app:
            return False
        if pattern.kind is not None and entry.kind != pattern.kind:
            return False
        if pattern.mode is not None and entry.mode != pattern.mode:
            return False
        return pattern.ok is None or entry.ok == pattern.ok

    def matches(
        self, entry: LogEntry, events: Mapping[str, int] | None = None, reader: CallReader | None = None
    ) -> bool:
        """Whether ``entry`` matches everything: the call, whom it told, its arguments, its result, its
        timing. ``reader`` reads the app data a pattern with ``to`` needs (without one, such a pattern
        matches nothing) and attached files by their content (without one, by their paths).
        """
        if not self.matches_call(entry) or not self.tells(entry, reader):
            return False
        if not self.matches_args(entry, reader):
            return False
        if self.result is not None and not self.result.test(entry.result, self.start):
            return False
        if self.screen is not None and not self.screen.test(entry.screen, self.start):
            return False
        if self.needs_event_positions:
            positions = events or {}
            after, before = self.pattern.after_event, self.pattern.before_event
            if after is not None and (after not in positions or entry.index < positions[after]):
                return False
            if before is not None and before in positions and entry.index > positions[before]:
                return False
        return True

    def tells(self, entry: LogEntry, reader: CallReader | None) -> bool:
        """Whether ``entry`` told the person of ``to`` (through a channel of ``via``); true without ``to``."""
        if self.people is None:
            return True
        sent = reader.delivery(entry) if reader is not None else None
        return sent is not None and sent.reaches(self.people, self.via)

    def arguments(
        self, entry: LogEntry, reader: CallReader | None, *, told: bool | None = None
    ) -> Mapping[str, Any]:
        """The arguments the matchers read: as the reader reads them (``told``: the text and files as
        delivered; default: when the pattern has ``to``), or as logged without a reader.
        """
        if reader is None:
            return entry.args
        return reader.args(entry, told=self.people is not None if told is None else told)

    def matches_args(
        self, entry: LogEntry, reader: CallReader | None = None, *, told: bool | None = None
    ) -> bool:
        """Whether the entry's arguments (:meth:`arguments`) satisfy every argument matcher."""
        if not self.args:
            return True
        reads = self.reads_files or (told if told is not None else self.people is not None)
        args = self.arguments(entry, reader, told=told) if reads else entry.args
        if self.reads_days:  # "tomorrow" and "the 2nd" as of when the call was made
            with written_at(entry.time):
                return all(matcher.test(args.get(name), self.start) for name, matcher in self.args)
        return all(matcher.test(args.get(name), self.start) for name, matcher in self.args)

    def find(self, log: Sequence[LogEntry], reader: CallReader | None = None) -> list[LogEntry]:
        """Every matching entry of ``log``."""
        events = event_positions(log) if self.needs_event_positions else None
        return [entry for entry in log if self.matches(entry, events, reader)]

    def describe(self) -> str:
        """A reading such as ``assistant email__send_email(recipients: contains ['bob'])``."""
        pattern = self.pattern
        tools = pattern.tools
        what = " or ".join(tools) if tools else (f"any {pattern.app} tool" if pattern.app else "any tool")
        who = "anyone" if pattern.actor == "any" else pattern.actor
        extras = [f"{name}: {matcher.describe()}" for name, matcher in self.args]
        qualifiers = [
            f"{label} {value}"
            for label, value in (
                ("kind", pattern.kind),
                ("mode", pattern.mode),
                ("after event", pattern.after_event),
                ("before event", pattern.before_event),
            )
            if value is not None
        ]
        if self.result is not None:
            qualifiers.append(f"result {self.result.describe()}")
        if self.screen is not None:
            qualifiers.append(f"on a screen {self.screen.describe()}")
        if pattern.ok is False:
            qualifiers.append("failed")
        if pattern.to is not None:
            people = pattern.to if isinstance(pattern.to, str) else " or ".join(pattern.to)
            sent = "email or message" if tools is None and pattern.app is None else what
            channels = f" via {' or '.join(pattern.via)}" if pattern.via else ""
            what = f"{sent} telling {people}{channels}"
        text = f"{who} {what}({', '.join(extras)})"
        return text + (f" [{', '.join(qualifiers)}]" if qualifiers else "")
