"""Keeping secrets out of every file a run writes: the manifest, the model-call cache, the records.

Three kinds of secret reach PARE: the API key (from the environment variable a configuration names),
values under secret-looking names in a model's ``extra`` request parameters (an ``api_key``, a
``Cookie``, an ``X-Portkey-Virtual-Key``), and every value of a header mapping there (``extra_headers``:
a proxy's ``Helicone-Auth`` is a credential whatever its name). Mappings are redacted by name; free text
(a provider's error message, which may echo what it was sent) has the known secret values cut out, in
every form a server is known to echo them: as sent, in another case, base64-encoded (a ``Basic``
credential), or only their first characters (an error naming the key it refused by its prefix).
"""

from __future__ import annotations

import base64
import re
from collections.abc import Iterable, Iterator
from typing import Any

SECRET_NAME = re.compile(
    r"(api[_-]?key|token(?!s)|secret|password|passwd|auth(?!ors?(?:[^a-z]|$))|credential|cookie|session|"
    r"(^|[-_])key$|signature)",
    re.IGNORECASE,
)
"""A name that suggests a secret; ``tokens`` is a count (``max_tokens``), not a secret."""
HEADERS_NAME = re.compile(r"headers$", re.IGNORECASE)
"""A mapping of HTTP headers (``extra_headers``, ``default_headers``): every value in it is secret."""
MASK = "***"
_SHORTEST_SECRET = 4
"""Values shorter than this are not cut out of text: they would mask ordinary words and numbers."""
_SHORTEST_PREFIX = 8
"""The fewest leading characters of a secret that are cut out when a text shows only its start."""


def secret_name(key: object) -> bool:
    """Whether a field's name suggests it holds a secret (``*_env`` fields name a variable: not secret)."""
    return isinstance(key, str) and not key.endswith("_env") and SECRET_NAME.search(key) is not None


def _headers(key: object) -> bool:
    return isinstance(key, str) and HEADERS_NAME.search(key) is not None


def redact_secrets(value: Any) -> Any:
    """``value`` with every entry whose name suggests a secret, and every header value, replaced by
    ``"***"``.
    """
    if isinstance(value, dict):
        return {key: _redact_entry(key, item) for key, item in value.items()}
    if isinstance(value, list):
        return [redact_secrets(item) for item in value]
    return value


def _redact_entry(key: object, item: Any) -> Any:
    if secret_name(key) and item:
        return MASK
    if _headers(key) and isinstance(item, dict):
        return {name: MASK if header else header for name, header in item.items()}
    return redact_secrets(item)


def secret_values(value: Any) -> Iterator[str]:
    """The text of every entry under a secret-looking name, and of every header, in ``value`` (nested
    mappings and lists).
    """
    if isinstance(value, dict):
        for key, item in value.items():
            if (
                (secret_name(key) or _headers(key))
                and isinstance(item, str | int)
                and not isinstance(item, bool)
            ):
                yield str(item)
            elif _headers(key) and isinstance(item, dict):
                yield from (str(header) for header in item.values() if isinstance(header, str | int))
            else:
                yield from secret_values(item)
    elif isinstance(value, list):
        for item in value:
            yield from secret_values(item)


def secret_forms(secret: str) -> set[str]:
    """The texts that give ``secret`` away: itself, each word of it (``Bearer <token>`` is echoed as the
    token), and their base64 encodings, whole or inside a longer encoded text (``user:<secret>``).
    """
    secret = secret.strip()
    words = {secret, *(word for word in secret.split() if len(word) >= _SHORTEST_PREFIX)}
    forms = {word for word in words if len(word) >= _SHORTEST_SECRET}
    for word in list(forms):
        forms.update(_encoded(word.encode("utf-8")))
    return forms


def _encoded(data: bytes) -> Iterator[str]:
    """The base64 characters that ``data`` fixes wherever it sits in an encoded text: for each of the
    three alignments, the characters neither the bytes before nor the bytes after it can change.
    """
    for shift in range(3):
        bits = (shift + len(data)) * 8
        start, end = (shift * 8 + 5) // 6, bits // 6
        for encode in (base64.b64encode, base64.urlsafe_b64encode):
            stable = encode(b"\0" * shift + data).decode("ascii")[start:end]
            if len(stable) >= _SHORTEST_PREFIX:
                yield stable


def scrub(text: str, secrets: Iterable[str | None]) -> str:
    """``text`` with each secret replaced by ``"***"`` in every form :func:`secret_forms` lists, in any
    case, and wherever at least its first few characters are shown.
    """
    values = {s.strip() for s in secrets if s and len(s.strip()) >= _SHORTEST_SECRET}
    forms = {form for value in values for form in secret_forms(value)}
    for form in sorted(forms, key=len, reverse=True):  # longest first, so none is left half shown
        text = re.sub(re.escape(form), MASK, text, flags=re.IGNORECASE)
    for form in sorted(forms, key=len, reverse=True):
        if len(form) > _SHORTEST_PREFIX:
            text = _cut_prefixes(text, form)
    return text


def _cut_prefixes(text: str, secret: str) -> str:
    """``text`` with every run of ``secret``'s leading characters (at least :data:`_SHORTEST_PREFIX`) cut."""
    head = re.compile(re.escape(secret[:_SHORTEST_PREFIX]), re.IGNORECASE)
    lowered, wanted = text.lower(), secret.lower()
    pieces: list[str] = []
    position = 0
    for found in head.finditer(text):
        if found.start() < position:
            continue
        end = found.end()
        while (
            end < len(text)
            and end - found.start() < len(wanted)
            and lowered[end] == wanted[end - found.start()]
        ):
            end += 1
        pieces += [text[position : found.start()], MASK]
        position = end
    pieces.append(text[position:])
    return "".join(pieces)
