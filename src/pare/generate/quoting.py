"""Loader problems as the generator can act on them: the place in the document and the lines quoted.

The candidate the loader reads is the stages' sections joined (with stand-ins for the sections still to
come), a file the model never saw with line numbers, so ``candidate.yaml:57`` tells it nothing. Each
problem instead names its section and quotes the offending line with a line either side.
"""

from __future__ import annotations

import re
from collections.abc import Collection, Sequence

from pare.scenarios.problem_groups import ProblemGroup

CONTEXT_LINES = 1
"""Lines quoted before and after the offending one."""
MAX_QUOTED_WIDTH = 160
"""Longer lines are cut in a quote (a seed email's body can be one long line)."""
_TOP_KEY = re.compile(r"^([A-Za-z_][A-Za-z0-9_]*)\s*:")


def describe_problem(group: ProblemGroup, text: str, written: Collection[str] | None = None) -> str:
    """``group`` without the joined file's name and line: its places and message, then, when the line is
    known, the section it is in and that line with its neighbours, the offending one marked ``>``.

    A syntax error found in a section not among ``written`` (a stand-in for a later stage), or on the line
    a section starts, is where the parser noticed something left open above it, and is said so.
    """
    times = f" ({group.count} places)" if group.count > 1 else ""
    head = f"{', '.join(group.places)}: {group.message}{times}"
    lines = text.splitlines()
    if group.line is None or not 1 <= group.line <= len(lines):
        return head
    quote = quoted_lines(lines, group.line)
    section = section_at(lines, group.line)
    syntax = group.places == ("(file)",)
    if section and written is not None and section not in written:
        where = f" (the stand-in for `{section}`, after your sections: something above is left open)"
    elif section and syntax and _TOP_KEY.match(lines[group.line - 1]):
        where = f" (where `{section}` starts: something above it is left open)"
    else:
        where = f" in the `{section}` section" if section else ""
    return f"{head}\n  at this line{where}:\n{quote}"


def quoted_lines(lines: Sequence[str], line: int) -> str:
    """Line ``line`` (1-based) of ``lines`` and its neighbours, indented, the line itself marked ``>``."""
    first = max(1, line - CONTEXT_LINES)
    last = min(len(lines), line + CONTEXT_LINES)
    quoted = []
    for number in range(first, last + 1):
        content = lines[number - 1]
        if len(content) > MAX_QUOTED_WIDTH:
            content = content[: MAX_QUOTED_WIDTH - 1] + "…"
        quoted.append(f"  {'>' if number == line else ' '} | {content}")
    return "\n".join(quoted)


def section_at(lines: Sequence[str], line: int) -> str | None:
    """The top-level key whose section holds line ``line`` (1-based), if any."""
    for content in reversed(lines[:line]):
        match = _TOP_KEY.match(content)
        if match is not None:
            return match.group(1)
    return None
