"""What a write that makes something returns: a sentence saying what it did, and the id of what it made.

A bare id (``email-712``) tells the model that called the tool nothing it can check: to whom the reply
went, which list the reminder joined. The sentence says it; the id is what the next tool takes.
"""

from __future__ import annotations

from collections.abc import Sequence

from pydantic import BaseModel, Field


class Done(BaseModel):
    """A write's result: what it did, and the id of what it made."""

    done: str = Field(description="what was done, e.g. \"Sent email-712 to bob@example.com: 'Re: Lunch'.\"")
    id: str = Field(description="the id of what was made, as the tools that act on it take it")


class SavedFiles(Done):
    """A write that saved several files (an email's attachments): ``id`` is the first one's path."""

    paths: list[str] = Field(description="the paths of every file saved, in order")


def listed(names: Sequence[str]) -> str:
    """Names joined as a sentence lists them: ``a``, ``a and b``, ``a, b and c``."""
    if len(names) <= 1:
        return "".join(names)
    return f"{', '.join(names[:-1])} and {names[-1]}"
