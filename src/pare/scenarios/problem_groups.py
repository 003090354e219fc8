"""One mistake, one line: problems with the same message said once, with every place it shows at.

A misspelt id in the seed data is reported wherever the oracle and the variants refer to it (often
through a YAML anchor), with the same message each time; read as one line, the places come compacted:
``variants[0-4,6].interventions[0].actions[0].args.event_id``.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass

_INDEX = re.compile(r"\[(\d+)\]")


@dataclass(frozen=True, slots=True)
class LocatedProblem:
    """A problem with where it is: file, line (when known) and path in the document."""

    source: str
    line: int | None
    path: str
    message: str

    def __str__(self) -> str:
        place = f"{self.source}:{self.line}" if self.line is not None else self.source
        return f"{place}: {self.path}: {self.message}"


@dataclass(frozen=True, slots=True)
class ProblemGroup:
    """Problems with one message: where the first is, every place, and how many there are."""

    source: str
    line: int | None
    places: tuple[str, ...]
    """The places, compacted (``variants[0-3].user[1].tool``)."""
    message: str
    count: int

    def __str__(self) -> str:
        where = f"{self.source}:{self.line}" if self.line is not None else self.source
        times = f" ({self.count} places)" if self.count > 1 else ""
        return f"{where}: {', '.join(self.places)}: {self.message}{times}"


def group_problems(problems: Iterable[LocatedProblem]) -> list[ProblemGroup]:
    """``problems`` with the same file and message as one group each, in the order first seen; a group's
    line is the earliest of its places'.
    """
    groups: dict[tuple[str, str], list[LocatedProblem]] = {}
    for problem in problems:
        groups.setdefault((problem.source, problem.message), []).append(problem)
    result = []
    for (source, message), members in groups.items():
        lines = [member.line for member in members if member.line is not None]
        places = compact_places([member.path for member in members])
        result.append(ProblemGroup(source, min(lines, default=None), places, message, len(members)))
    return result


def compact_places(paths: Sequence[str]) -> tuple[str, ...]:
    """Places written ``a[1].b[2]`` that differ only in their indices, merged: ``a[1-3].b[2]``.

    Merging is exact: every combination of the indices shown is one of ``paths``.
    """
    shapes: list[tuple[str, list[frozenset[int]]]] = []
    for path in dict.fromkeys(paths):  # once each, in order
        shapes.append((_INDEX.sub("[#]", path), [frozenset([int(n)]) for n in _INDEX.findall(path)]))
    for position in range(max((len(indices) for _, indices in shapes), default=0)):
        merged: dict[tuple[object, ...], tuple[str, list[frozenset[int]]]] = {}
        for shape, indices in shapes:
            if position >= len(indices):
                merged[(shape, id(indices))] = (shape, indices)
                continue
            key = (shape, *indices[:position], *indices[position + 1 :])
            if key in merged:
                kept = merged[key][1]
                kept[position] = kept[position] | indices[position]
            else:
                merged[key] = (shape, list(indices))
        shapes = list(merged.values())
    return tuple(_render(shape, indices) for shape, indices in shapes)


def _render(shape: str, indices: list[frozenset[int]]) -> str:
    parts = iter(indices)
    return re.sub(r"\[#\]", lambda _: f"[{_numbers(next(parts))}]", shape)


def _numbers(values: frozenset[int]) -> str:
    """``{0, 1, 2, 5}`` as ``0-2,5``."""
    ordered = sorted(values)
    runs: list[list[int]] = []
    for value in ordered:
        if runs and value == runs[-1][-1] + 1:
            runs[-1].append(value)
        else:
            runs.append([value])
    return ",".join(str(run[0]) if len(run) == 1 else f"{run[0]}-{run[-1]}" for run in runs)
