"""Keeping secrets out of every file a run writes: the manifest, the model-call cache, the records.

Two kinds of secret reach PARE: the API key (from the environment variable a configuration names) and
values under secret-looking names in a model's ``extra`` request parameters (an ``api_key``, an
``Authorization`` header). Mappings are redacted by name; free text (a provider's error message, which
may echo what it was sent) has the known secret values cut out.
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from typing import Any

SECRET_NAME = re.compile(r"(api[_-]?key|token(?!s)|secret|password|authorization|credential)", re.IGNORECASE)
"""A name that suggests a secret; ``tokens`` is a count (``max_tokens``), not a secret."""
MASK = "***"
_SHORTEST_SECRET = 4
"""Values shorter than this are not cut out of text: they would mask ordinary words and numbers."""


def secret_name(key: object) -> bool:
    """Whether a field's name suggests it holds a secret (``*_env`` fields name a variable: not secret)."""
    return isinstance(key, str) and not key.endswith("_env") and SECRET_NAME.search(key) is not None


def redact_secrets(value: Any) -> Any:
    """``value`` with every mapping entry whose name suggests a secret replaced by ``"***"``."""
    if isinstance(value, dict):
        return {
            key: MASK if secret_name(key) and item else redact_secrets(item) for key, item in value.items()
        }
    if isinstance(value, list):
        return [redact_secrets(item) for item in value]
    return value


def secret_values(value: Any) -> Iterator[str]:
    """The text of every entry under a secret-looking name in ``value`` (nested mappings and lists)."""
    if isinstance(value, dict):
        for key, item in value.items():
            if secret_name(key) and isinstance(item, str | int) and not isinstance(item, bool):
                yield str(item)
            else:
                yield from secret_values(item)
    elif isinstance(value, list):
        for item in value:
            yield from secret_values(item)


def scrub(text: str, secrets: Iterable[str | None]) -> str:
    """``text`` with each secret value replaced by ``"***"`` (longest first, so none is left half shown)."""
    for secret in sorted({s.strip() for s in secrets if s and len(s.strip()) >= _SHORTEST_SECRET}, key=len)[
        ::-1
    ]:
        text = text.replace(secret, MASK)
    return text
