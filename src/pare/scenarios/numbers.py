"""Phone numbers and other digit strings in text, compared digit by digit whatever their grouping.

People group the same number in many ways: "07700 900742", "0770 090 0742", "07700-900-742",
"(0)7700 900742", "+44 7700 900742". A check that spells one grouping (or a regular expression that
allows a few) rejects the others, though every one dials the same number. Here a number is its digits:
a text names it when those digits appear in order with nothing but grouping signs between them (spaces,
dots, hyphens, brackets, slashes; at most two in a row) and no digit glued on at either end, so
"07700 900742" is not found in "07700 9007421".

The country code is the one part written differently: a number written with "+" and a code (the first
group after the "+": "+44 7700 900742", "+1 (415) 555-0178") is also named by its national form, with or
without a leading 0 ("07700 900742", "(415) 555-0178"); a number written with a leading 0 ("07700
900742") is also named with a "+" or "00" and a code of one to three digits in front of the rest
("+44 7700 900742", "0044 (0)7700 900742").
"""

from __future__ import annotations

import re
from functools import lru_cache

_SIGNS = r"[\s.\-()/]{0,2}"
"""What may stand between two digits of a number: its grouping."""
_CODE = r"(?:\+|00)\d{1,3}" + _SIGNS + r"(?:\(0\)" + _SIGNS + r")?"
"""A country code in front of a national number, with the "(0)" some write after it."""


class NumberError(ValueError):
    """A written number that has no digits to compare."""


def _spaced(digits: str) -> str:
    return _SIGNS.join(digits)


@lru_cache(maxsize=1024)
def number_pattern(written: str) -> re.Pattern[str]:
    """A pattern finding the number ``written`` (as a scenario spells it) in any grouping (module doc)."""
    text = written.strip()
    digits = re.sub(r"\D", "", text)
    if len(digits) < 3:
        raise NumberError(f"{written!r} is not a number of at least 3 digits")
    forms = [_spaced(digits)]
    if text.startswith(("+", "00")):
        code = re.match(r"(?:\+|00)\s*(\d+)", text)
        national = digits[len(code.group(1)) + (2 if text.startswith("00") else 0) :] if code else ""
        if code and len(national) >= 3:  # "+44 7700 900742" is also "07700 900742" and "7700 900742"
            forms.append(
                r"(?:\+|00)"
                + _spaced(code.group(1))
                + _SIGNS
                + r"(?:\(0\)"
                + _SIGNS
                + r")?"
                + _spaced(national)
            )
            forms.append(r"(?<![+\d])(?:0" + _SIGNS + r")?" + _spaced(national))
    elif digits.startswith("0") and len(digits) > 3:  # "07700 900742" is also "+44 7700 900742"
        forms.append(_CODE + _spaced(digits[1:]))
    return re.compile(r"(?<!\d)(?:" + "|".join(forms) + r")(?!\d)")


def names_number(text: str, written: str) -> bool:
    """Whether ``text`` names the number ``written``, whatever its grouping and country code form."""
    return number_pattern(written).search(text) is not None
