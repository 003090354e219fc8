"""A thinking model's reasoning, told apart from its answer.

Servers hand reasoning back in one of two ways: as a separate field of the message (``reasoning_content``,
as vLLM with a reasoning parser and DeepSeek do, or ``reasoning``), read by the backends; or inline, in
the message's text, as think blocks. :func:`split_reasoning` takes the inline kind out of a text:

* every ``<think> ... </think>`` block;
* a leading block whose opening tag is missing (the chat template put ``<think>`` in the prompt, so the
  text starts mid-thought and holds only ``</think>``): everything before the first ``</think>``;
* a block opened but never closed (the answer was cut off while thinking): everything after ``<think>``.

What remains is the answer. Reasoning is kept for the record and never read as the answer: a thought that
drafts an ``Action:`` must not count as one.
"""

from __future__ import annotations

import re

__all__ = ["join_reasoning", "split_reasoning"]

_TAG_RE = re.compile(r"<(/?)think>", re.IGNORECASE)


def split_reasoning(text: str) -> tuple[str, str | None]:
    """Return ``text``'s answer and its inline reasoning (``None`` when it has none).

    A text without think tags is returned as it is; otherwise the answer is what lies outside the blocks,
    stripped.

    Empty think blocks (a model told not to think writes ``<think></think>``) are reasoning of nothing:
    they are removed, and the reasoning is ``None``.
    """
    first = _TAG_RE.search(text)
    if first is None:  # nearly every answer: one search is the whole cost
        return text, None
    tags = list(_TAG_RE.finditer(text, first.start()))
    answer: list[str] = []
    thoughts: list[str] = []
    position = 0
    inside = False
    if tags[0].group(1):  # the first tag closes a block: the text opened inside it
        thoughts.append(text[: tags[0].start()])
        position = tags[0].end()
        tags = tags[1:]
    for tag in tags:
        closing = bool(tag.group(1))
        if not inside and not closing:
            answer.append(text[position : tag.start()])
            position, inside = tag.end(), True
        elif inside and closing:
            thoughts.append(text[position : tag.start()])
            position, inside = tag.end(), False
        # an opening tag inside a block, or a closing one outside, is text of where it stands
    (thoughts if inside else answer).append(text[position:])
    return "".join(answer).strip(), join_reasoning(*thoughts)


def join_reasoning(*parts: str | None) -> str | None:
    """The non-blank ``parts``, stripped and separated by blank lines; ``None`` when there are none."""
    kept = [part.strip() for part in parts if part and part.strip()]
    return "\n\n".join(kept) or None
