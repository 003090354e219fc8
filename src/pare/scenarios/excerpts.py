"""Texts quoted on one line, shortened around what matters: how explanations show what they read."""

from __future__ import annotations

from collections.abc import Sequence

TEXT_WIDTH = 80
"""The most characters of a text quoted in an explanation."""
CLAUSE_WIDTH = 60
"""The most characters of a clause quoted in an explanation."""


def quote(text: str, width: int = TEXT_WIDTH) -> str:
    """``text`` on one line in double quotes, shortened in the middle to about ``width`` characters."""
    return '"' + excerpt(text, (), width) + '"'


def excerpt(text: str, marks: Sequence[str] = (), width: int = CLAUSE_WIDTH) -> str:
    """``text`` on one line, at most about ``width`` characters: its start and its end, or when ``marks``
    are given, the words around each of them (``not Fri ... could we move it``), cut at spaces.
    """
    text = " ".join(text.split())
    if len(text) <= width:
        return text
    lowered = text.lower()
    spans = [(at, at + len(mark)) for mark in marks if mark and (at := lowered.find(mark.lower())) >= 0]
    if not spans:
        head = width * 3 // 5
        return _cut(text, 0, head) + " … " + _cut(text, len(text) - (width - head - 3), len(text))
    pad = max(6, (width - sum(end - begin for begin, end in spans)) // (2 * len(spans)))
    windows: list[tuple[int, int]] = []
    for begin, end in sorted(spans):
        window = (max(0, begin - pad), min(len(text), end + pad))
        if windows and window[0] <= windows[-1][1]:
            windows[-1] = (windows[-1][0], max(windows[-1][1], window[1]))
        else:
            windows.append(window)
    pieces = [_cut(text, begin, end) for begin, end in windows]
    shown = " … ".join(pieces)
    if windows[0][0] > 0:
        shown = "… " + shown
    if windows[-1][1] < len(text):
        shown += " …"
    return shown


def _cut(text: str, begin: int, end: int) -> str:
    """``text[begin:end]`` without the partial words at its edges (unless that leaves nothing)."""
    part = text[begin:end]
    if begin > 0 and text[begin - 1] != " " and " " in part:
        part = part[part.index(" ") + 1 :]
    if end < len(text) and text[end] != " " and " " in part:
        part = part[: part.rindex(" ")]
    return part.strip()
