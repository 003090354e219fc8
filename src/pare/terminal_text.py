r"""Text that did not come from PARE, made safe to print on a terminal.

Scenario files, generated candidates, model names, run labels, model answers and whatever is read back
from a run folder are written by someone else: a person, a model, or a file that was edited. Printed as
they are, their rich markup (``[/]``, ``[link=...]``) would be interpreted or crash the command, and their
control characters would be obeyed by the terminal (an escape sequence can hide the text after it, clear
the screen or set the window's title), so what a reviewer reads could differ from what the file says.

Every command prints such text through here:

* :func:`printable` writes each control character as a visible escape (``\x1b``), C0 and C1 alike
  (line breaks and tabs are kept), as well as the bidirectional overrides that reorder what is shown and
  lone surrogates no terminal can encode;
* :func:`printable_json` does the same to JSON text with JSON's own escapes, so it stays the same data;
* :func:`markup_safe` also escapes rich markup, for text placed inside a markup string or a table cell;
* :func:`plain_text` gives a rich :class:`~rich.text.Text` that is never read as markup;
* :func:`make_console` is a console that does not turn ``:name:`` codes into emoji either;
* :func:`show_warnings_as_text` prints PARE's logged warnings (a retry, a parameter a provider refused,
  both quoting the provider) through :func:`printable`.
"""

from __future__ import annotations

import logging
import re
import sys
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # rich is imported when something is printed: `pare --help` and errors stay fast
    from rich.console import Console
    from rich.text import Text

_UNSAFE = re.compile(
    "[\x00-\x08\x0b-\x1f\x7f-\x9f"  # C0 but tab and line feed, DEL, C1 (ESC and CSI begin sequences)
    "\u061c\u200e\u200f\u202a-\u202e\u2066-\u2069"  # bidirectional marks, embeddings, overrides, isolates
    "\ud800-\udfff]"  # lone surrogates (from a file name or argument that is not UTF-8)
)


def _visible(match: re.Match[str]) -> str:
    code = ord(match.group())
    if 0xD800 <= code <= 0xDFFF:
        return "\ufffd"
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}"


def printable(value: object) -> str:
    """``value`` as text whose control characters are shown, not obeyed (see the module docstring)."""
    text = value if isinstance(value, str) else str(value)
    return _UNSAFE.sub(_visible, text)


def printable_json(text: str) -> str:
    r"""JSON ``text`` with the characters :func:`printable` shows written as JSON escapes (``\u001b``):
    the same data, safe on a terminal (a JSON writer escapes C0 but leaves DEL, C1 and the rest).
    """
    return _UNSAFE.sub(lambda match: f"\\u{ord(match.group()):04x}", text)


def markup_safe(value: object) -> str:
    """``value`` as :func:`printable` text with rich markup escaped: shown as written inside markup."""
    from rich.markup import escape

    return escape(printable(value))


def plain_text(value: object, style: str = "") -> Text:
    """``value`` as :func:`printable` text in a rich :class:`~rich.text.Text` (never read as markup)."""
    from rich.text import Text

    return Text(printable(value), style=style)


def make_console(**options: Any) -> Console:
    """A rich console for PARE's commands: as :class:`~rich.console.Console`, without emoji codes."""
    from rich.console import Console

    return Console(emoji=False, **options)


class _PrintableWarnings(logging.Handler):
    """Writes each record's message to the standard error of the moment (as Python's last-resort
    handler would), made :func:`printable`.
    """

    def __init__(self) -> None:
        super().__init__(logging.WARNING)

    def emit(self, record: logging.LogRecord) -> None:
        try:
            sys.stderr.write(printable(self.format(record)) + "\n")
        except Exception:  # logging must never break the command: it reports the failure itself
            self.handleError(record)


def show_warnings_as_text() -> None:
    """Print the warnings PARE logs as text, where no logging is set up (as in ``pare`` at a terminal);
    an application or test that set up logging keeps its own handlers.
    """
    package = logging.getLogger("pare")
    if logging.getLogger().handlers or any(isinstance(h, _PrintableWarnings) for h in package.handlers):
        return
    package.addHandler(_PrintableWarnings())
