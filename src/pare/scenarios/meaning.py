"""Reading free text for meaning, deterministically: words, negation, and the days and times it names.

Checks on what an assistant wrote must accept every correct wording and reject the tempting wrong ones,
without a model. Three tools, all rule-based so a verdict never changes from one run to the next:

* **Words at their boundaries.** ``wed`` is found in "Wed 14:00" but not in "reviewed"; ``15`` in "6:15pm"
  but not in "150". A word is a run of letters or a run of digits; a piece matches where it is not glued
  to more of the same kind. A ``*`` at the end (or start) of a piece lets the word go on: ``view*``
  matches "viewing".
* **Clauses and negation.** Text is cut into clauses (sentences, commas, colons, dashes between words,
  "but", "instead of", "because", a "not" between two named things as in "Wednesday not Tuesday", ...); a
  clause with a negation cue ("not", "can't", "unfortunately", "instead of", "ruled out", "skipped", ...)
  does not affirm what it mentions, so "Thursday does not work" does not affirm Thursday while "Wednesday
  is out, Thursday works" does; nor does a clause that weighs an option the next clause turns from ("I
  thought about the 2-bed but it's over budget").
* **Days and clock times.** "Tue 14 May", "Thursday at 8", "half nine", "tomorrow", "6.15 pm", "2-4pm",
  "noon" are resolved against a reference moment (a weekday is the next such day on or after it; "next
  Thursday" also the one after) and compared as dates and times, not as text; read by
  :mod:`pare.scenarios.timewords`.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import date, datetime, time
from functools import lru_cache

from pare.scenarios.timewords import Mention, mentions

__all__ = ["Mention", "mentions"]  # read here by the explanations, as before the readers had a module

# -- words -------------------------------------------------------------------------------------------------
_LETTER_BEFORE = r"(?<![^\W\d_])"
_LETTER_AFTER = r"(?![^\W\d_])"
_DIGIT_BEFORE = r"(?<!\d)"


def _edge(char: str, *, before: bool) -> str:
    if char.isdigit():
        return _DIGIT_BEFORE if before else r"(?!\d)"
    if char.isalpha():
        return _LETTER_BEFORE if before else _LETTER_AFTER
    return ""


def _after_sign(parts: list[str], at: int) -> bool:
    """Whether the separator ``parts[at]`` (of a piece split at spaces and hyphens) follows a word that
    ends in a sign, not a letter or a digit, and is itself spaces only.
    """
    before = parts[at - 1] if at else ""
    return " " in parts[at] and "-" not in parts[at] and bool(before) and not before[-1].isalnum()


def _after_stop(parts: list[str], at: int) -> bool:
    """Whether the separator ``parts[at]`` is a space after a word of letters that ends in a stop ("no.")."""
    before = parts[at - 1] if at else ""
    return _after_sign(parts, at) and before.endswith(".") and before[:-1].isalpha()


def _before_space(parts: list[str], at: int) -> bool:
    return at + 1 < len(parts) and parts[at + 1] not in ("", "-") and " " in parts[at + 1]


@lru_cache(maxsize=4096)
def word_pattern(piece: str) -> re.Pattern[str]:
    """A case-insensitive pattern finding ``piece`` at word boundaries (see the module docstring)."""
    text = " ".join(piece.split())
    open_start, open_end = text.startswith("*"), text.endswith("*") and len(text) > 1
    core = text.strip("*")
    if not core:
        raise ValueError(f"{piece!r} has no text besides '*'")
    # A space in the piece also finds a hyphen, and a hyphen also a space or nothing: "dry clean*" and
    # "dry-clean*" both find "dry cleaning", "dry-cleaning" and (for the hyphen) "drycleaning".
    # A space after a stop or other sign may also be left out: "no. 14" finds "no.14" as well; and the stop
    # of an abbreviation may be left out, with the space: "no. 14" finds "no 14" (not "no14").
    parts = re.split(r"([ -])", core)
    body = "".join(
        (
            r"(?:\.[\s-]*|[\s-]+)"
            if part == " " and _after_stop(parts, at)
            else r"[\s-]*"
            if part == " " and _after_sign(parts, at)
            else r"[\s-]+"
        )
        if part == " "
        else r"[\s-]?"
        if part == "-"
        else re.escape(part[:-1])
        if _before_space(parts, at) and _after_stop(parts, at + 1)
        else re.escape(part).replace(r"\*", r"[\w']*")  # "drop* us", "didn*t": a word that goes on
        for at, part in enumerate(parts)
    )
    left = "" if open_start else _edge(core[0], before=True)
    right = "" if open_end else _edge(core[-1], before=False)
    return re.compile(left + body + right, re.IGNORECASE)


class WordFinder:
    r"""Finds one piece at word boundaries (:func:`word_pattern`) in text passed through
    :func:`normalise_quotes`.

    A process compiled a pattern for every piece its checks seek, about a thousand for the library, which
    cost more than the searches. A piece of ASCII text is now sought in ASCII text without a pattern:
    there, case-insensitive matching is ASCII case folding, a letter, a digit or a space is an ASCII one,
    and the separators a space or a hyphen of the piece stand for (``[\s-]+`` and ``[\s-]?``) are a run
    between two words of the piece, which must be all of that run since a word begins with neither. So
    the piece is where its first word is found in the lowercased text, each later word follows a run of
    separators as long as the piece allows, and the boundaries hold. Other pieces and texts use the
    pattern, compiled when first needed.
    """

    __slots__ = ("_digit_after", "_digit_before", "_letter_after", "_letter_before", "_pattern", "gaps",
                 "piece", "words")  # fmt: skip

    def __init__(self, piece: str) -> None:
        self.piece = normalise_quotes(piece)
        text = " ".join(self.piece.split())
        open_start, open_end = text.startswith("*"), text.endswith("*") and len(text) > 1
        core = text.strip("*")
        if not core:
            raise ValueError(f"{piece!r} has no text besides '*'")
        parts = re.split(r"([ -]+)", core.lower())
        # an abbreviation's stop that may be left out ("no. 14" finds "no 14") is for the pattern to find
        abbreviated = any(word.endswith(".") and word[:-1].isalpha() for word in parts[:-1:2])
        plain = core.isascii() and bool(parts[0]) and bool(parts[-1]) and not abbreviated and "*" not in core
        self.words: tuple[str, ...] | None = tuple(parts[::2]) if plain else None
        """The piece's words, lowercased, as sought in ASCII text; ``None`` when only the pattern finds it."""
        self.gaps = tuple(
            (0 if _after_sign(parts, 2 * at + 1) else run.count(" "), None if " " in run else len(run))
            for at, run in enumerate(parts[1::2])
        )
        """The fewest and most separators between two words (``None``: no most): a space in the piece
        stands for one or more (none after a sign such as a stop: "no. 14" finds "no.14"), a hyphen for
        one or none."""
        first, last = core[0], core[-1]
        self._letter_before = not open_start and first.isalpha()
        self._digit_before = not open_start and first.isdigit()
        self._letter_after = not open_end and last.isalpha()
        self._digit_after = not open_end and last.isdigit()
        self._pattern: re.Pattern[str] | None = None

    def found(self, text: str) -> bool:
        """Whether ``text`` (with straight apostrophes) holds the piece at word boundaries."""
        words = self.words
        if words is None or not text.isascii():
            if self._pattern is None:
                self._pattern = word_pattern(self.piece)
            return self._pattern.search(text) is not None
        lowered = text.lower()
        at = lowered.find(words[0])
        while at >= 0:
            if not (at and self._glued(text[at - 1], before=True)):
                end = self._end(lowered, words, at + len(words[0]))
                if end >= 0 and not (end < len(text) and self._glued(text[end], before=False)):
                    return True
            at = lowered.find(words[0], at + 1)
        return False

    def _end(self, lowered: str, words: tuple[str, ...], at: int) -> int:
        """Where the piece ends in ``lowered`` if its first word ends at ``at``; -1 if it is not there."""
        for word, (fewest, most) in zip(words[1:], self.gaps, strict=True):
            run = at
            while run < len(lowered) and (lowered[run] == "-" or lowered[run].isspace()):
                run += 1
            separators = run - at
            if separators < fewest or (most is not None and separators > most):
                return -1
            if not lowered.startswith(word, run):
                return -1
            at = run + len(word)
        return at

    def _glued(self, char: str, *, before: bool) -> bool:
        """Whether ``char``, just before or after the piece, continues its first or last word."""
        if before:
            return (self._letter_before and char.isalpha()) or (self._digit_before and char.isdigit())
        return (self._letter_after and char.isalpha()) or (self._digit_after and char.isdigit())


@lru_cache(maxsize=4096)
def word_finder(piece: str) -> WordFinder:
    """What :func:`has_word` seeks ``piece`` with, in text passed through :func:`normalise_quotes`."""
    return WordFinder(piece)


def has_word(text: str, piece: str) -> bool:
    """Whether ``text`` contains ``piece`` at word boundaries (curly and straight apostrophes alike)."""
    return word_finder(piece).found(normalise_quotes(text))


# -- clauses and negation -------------------------------------------------------------------------------
_PICTOGRAPH = (
    "\u203c\u2049\u231a\u231b\u2328\u23cf\u23e9-\u23f3\u23f8-\u23fa\u2600-\u26ff\u2700-\u275a\u2761-\u2767"
    "\u27b0\u27bf\u2b1b\u2b1c\u2b50\u2b55\U0001f000-\U0001faff"
)
"""Emoji and the other pictographs that people end a sentence with ("not Fri 🙈 could we move it?"):
Unicode's Extended_Pictographic characters (with the flags' regional indicators), less those written
inside a sentence: (c), (R), TM, arrows, geometric shapes used as bullets, ornamental quotes and brackets.
The Miscellaneous Symbols and Dingbats blocks are taken whole but for those (a check mark or a star ends
a phrase as well)."""
_PICTOGRAPH_RUN = f"[{_PICTOGRAPH}](?:[{_PICTOGRAPH}\ufe0e\ufe0f\u200d\u20e3\U000e0020-\U000e007f])*"
"""A run of pictographs with what joins and styles them (variation selectors, zero-width joiners, keycaps,
tag characters): one sentence break, so no joiner is left behind as a clause of its own."""

_CLAUSE_BREAK = re.compile(
    # a comma breaks a clause, except inside a number written with thousands separators (44,200) or a
    # decimal comma (€25,70); a full stop breaks one too, except in "no. 22" (a number, not a refusal)
    r"[;!?\n]|,(?!(?<=\d,)\d{2,3}(?!\d))|(?<![Nn]o)\.(?=\s|$)|(?<=[Nn]o)\.(?=\s|$)(?!\s*\d)|"
    # a colon before a space ("Update: Thursday works", not 18:15) and a dash between words ("Not Friday -
    # Thursday works", "Friday—Thursday"), but not between two numbers (the range 2 - 4pm)
    r":(?=\s|$)|(?<=[^\d\s])\s+[-\u2013\u2014]+\s+|\s+[-\u2013\u2014]+\s+(?=[^\d\s])|(?<!\d)[\u2013\u2014](?!\d)|"
    # "but" after "any day", "anything", "everyone"... means "except": the clause goes on ("any day but
    # Wednesday works" turns Wednesday down, see _NEGATION_PATTERNS)
    r"(?<!any day)(?<!anything)(?<!any time)(?<!anytime)(?<!anyone)(?<!every day)(?<!everything)"
    r"(?<!everyone)(?<!\ball)\s(?=but\b)|"
    r"\s(?=(?:however|although|though|whereas|except|instead of|rather than|if|unless|"
    r"apart from|other than|unlike)\b)|"
    # an aside that negates, negates only itself: "Hillcrest (not the main surgery)"
    r"\s(?=\((?:not|no|never|rather than|instead of|moved from)\b)|" + _PICTOGRAPH_RUN,
    re.IGNORECASE,
)
_SENTENCE_BREAK = re.compile(r"[!?\n]|\.(?=\s|$)(?!(?<=\b[Nn]o\.)\s*\d)(?<!\bapprox\.)|" + _PICTOGRAPH_RUN)
"""Where a sentence ends: not at "no. 9" (a number) or "approx."."""
"""Where a sentence ends: the days and times of one sentence are read together."""
NEGATION_CUES: tuple[str, ...] = (
    "not",
    "no",
    "never",
    "cannot",
    "can't",
    "won't",
    "*n't",
    "unable",
    "unfortunately",
    "sadly",
    "neither",
    "nor",
    "nothing",
    "none",
    "decline",
    "unavailable",
    "instead of",
    "rather than",
    "except",
    "apart from",
    "other than",
    "unlike",
    "is out",
    "'s out",
    "are out",
    "'m out",
    "am out",
    "'re out",
    # being away negates only in the first person: "I'm away Thursday" turns Thursday down, while "Mum is
    # away on the 2nd, so book the sitter for the 2nd" asks for it (someone else's absence is a reason)
    "'m away",
    "am away",
    "we're away",
    "we are away",
    "i'll be away",
    "i will be away",
    "we'll be away",
    "we will be away",
    # both of us, all of us: "We're both out on Thursday" turns Thursday down as "we're out" does
    "both out",
    "we're all out",
    "we are all out",
    "we're both away",
    "we are both away",
    "we're all away",
    "we are all away",
    "we'll both be away",
    "we will both be away",
    "i'll be out",
    "i will be out",
    "we'll be out",
    "we will be out",
    "we'll both be out",
    "we will both be out",
    # passing an option over is not choosing it: "I left out Rowan Street", "ruled out the Harbour flat",
    # "skipped Harbour Walk", "it's over budget"
    "left out",
    "leave out",
    "leaving out",
    "leaves out",
    "ruled out",
    "rule out",
    "rules out",
    "ruling out",
    "skip",
    "skipped",
    "skipping",
    "skips",
    "decided against",
    "over budget",
    "over our budget",
    "over your budget",
    "over the budget",
    "too expensive",
    "too pricey",
    "is taken",
    "'s taken",
    "clash*",
    "no good",
    "impossible",
    "busy",
    "booked up",
    "fully booked",
    # set aside, not chosen: "the GreenLoop ones can stay on the shelf"
    "stay on the shelf",
    "stays on the shelf",
)
"""Words that keep a clause from affirming what it mentions."""

_NEGATION_PATTERNS = re.compile(
    r"(?<![^\W\d_])(?:(?:went|gone|goes|going|shot|jumped)\s+up|(?:rose|risen|increased|jumped)\s+)"
    r"(?:\s*(?:in price\s+)?to\s+)?(?:[$\u00a3\u20ac]\s?\d|\d[\d.,]*\s*(?:pounds|quid|dollars|euros)\b)|"
    # where something was, not where it is: "Talk moved from Thursday 14:00" (but "moved from Thursday to
    # Friday" names where it is too, so it stays affirmed)
    r"(?<![^\W\d_])moved\s+from\b(?![^.,;:!?\n]*\bto\b)|"
    # "any day but Wednesday", "anything but the 2kg bag": but as except
    r"(?<![^\W\d_])(?:any\s+day|anything|any\s*time|anyone|every\s+day|everything|everyone|all)\s+but\b",
    re.IGNORECASE,
)
"""Negations that need more than a phrase: where something moved from, with no "to" after it; a price
that went up ("the moon lamp went up to £42, so I went for the globe" passes the lamp over), told by the
money amount after it ("I went up to the office" is no price)."""

_DELIBERATION_CUES: tuple[str, ...] = (
    "thought about",
    "thinking about",
    "thought of",
    "considered",
    "considering",
    "was tempted by",
    "were tempted by",
    "toyed with",
    "was going to",
    "were going to",
)
"""What someone weighed before turning it down: a clause with one of these, followed by a clause that
begins "but" ("I thought about the 2-bed but it's over budget"), affirms nothing it mentions."""

_CONTRARY_START = re.compile(r"(?:but|however|though|although)\b", re.IGNORECASE)

DECLINE_CUES: tuple[str, ...] = (
    "can't make",
    "cannot make",
    "can't do",
    "cannot do",
    "can't come",
    "cannot come",
    "won't be able",
    "not be able",
    "unable",
    "doesn't work",
    "does not work",
    "won't work",
    "will not work",
    "don't think",
    "no longer",
    "not available",
    "unavailable",
    "unfortunately",
    "regret*",
    "declin*",
    "have to cancel",
    "need to cancel",
    "must cancel",
    # a plan that is off, said without "cancel": the meeting is "called off", "not going ahead", "scrapped"
    "called off",
    "call it off",
    "not going ahead",
    "won't go ahead",
    "will not go ahead",
    "not happening",
    "scrapped",
    "off the table",
    "won't make it",
    "not going to make",
    "can't take",
    "cannot take",
    "can't share",
    "cannot share",
    "no room",
    "no thanks",
    "no thank you",
    "i'll pass",
    "i will pass",
    "pass this time",
    "give it a miss",
    "sit this one out",
    "not for me",
    "can't attend",
    "cannot attend",
    "won't attend",
    "won't be coming",
    "not coming",
    "not interested",
    "count me out",
    "rather not",
    "another time",
    "next time",
    "rain check",
)
"""Phrases that make a whole message a refusal or a cancellation."""

_BARE_REFUSAL = re.compile(
    r"\W*(?:no|nope|nah|can't|cannot|sadly,?\s+(?:no|not)|(?:i'm\s+)?afraid\s+not|sorry,?\s+no)\W*", re.I
)
"""A clause that is only a refusal ("Can't, sorry"; "No, I'm fine"; "Sadly not")."""

_REFUSAL_PATTERNS = (
    re.compile(r"(?<![^\W\d_])no\s+need(?!\s+(?:to|for)\b)", re.I),
    re.compile(
        r"(?<![^\W\d_])(?:i|we)(?:'ll)?\s+(?:can't|cannot|won't|will\s+not)\s+(?:be\s+able\s+to\s+)?"
        r"(?:get\s+(?!over\b)|return|bring|give|send|lend|drop|attend|join|manage|be\s+there|be\s+back|pick)",
        re.I,
    ),
)
"""Refusals that need more than a phrase: "no need" (but not "no need to worry"); "I can't get it back to
you", "we won't be able to attend" (an act of one's own turned down; not "I can't get over it")."""

COUNTER_OFFER_CUES: tuple[str, ...] = (
    "instead",
    "how about",
    "what about",
    "works",
    "work for",
    "would work",
    "suits",
    "would suit",
    "is fine",
    "is better",
    "i can do",
    "i could do",
    "i'll take",
    "i will take",
    "could i have",
    "could i get",
    "can i have",
    "can i get",
    "could we do",
    "can we do",
    "could we move",
    "can we move",
    "happy to",
    "would love",
)
"""Phrases by which a later clause takes up another option ("Thursday won't work, but Friday is fine"):
the message then turns one option down and is not a refusal as a whole."""


_FRIENDLY_IDIOMS = re.compile(
    r"(?<![^\W\d_])(no problem|no worries|not a problem|no trouble|no rush|no hurry|never mind|"
    # eagerness, not a refusal ("can't wait to see you", "Ella can't wait for the trip"); but "it can't
    # wait till Friday" and "this can't wait for Monday" refuse the wait
    r"(?<!\bit\s)(?<!\bthis\s)(?<!\bthat\s)(?:can't|cannot)\s+wait(?!\s+(?:till|until|til|any))|"
    r"don't hesitate|no later than|not later than|no more than|no matter|not only|nothing but|"
    # reminders that affirm what they remind of: "don't forget games night Thursday at 19:00"
    r"(?:don't|do not|dont)\s+(?:forget|be late)|"
    # thanks, not a hedge: "not sure what I'd have done otherwise", "don't know what we would do without you"
    r"(?:not sure|don't know|do not know|dunno)\s+what\s+(?:i|we)(?:'d|\s+would)\s+(?:have\s+)?do(?:ne)?|"
    r"no\.?\s*(?=\d))(?![^\W\d_])",
    re.IGNORECASE,
)
"""Phrases that look negative but are not: friendly ones ("no problem, Thursday works", "no rush", "don't
forget Thursday at 7"), bounds
that set a limit rather than deny ("by Friday, no later than 5pm"), and "no. 22": removed before cues are
sought."""


def normalise_quotes(text: str) -> str:
    """``text`` with curly apostrophes made straight, as the words sought are written."""
    if text.isascii():  # most text: no curly apostrophe, known without a search (isascii reads a flag)
        return text
    return text.replace("\u2019", "'").replace("\u2018", "'")


_CONTRAST_BREAK = re.compile(
    # "Collection Wednesday not Tuesday", "the 3rd not the 4th", "6pm not 7pm": one named thing set against
    # another, each a capitalised word or a number; "Thursday does not work", "Thursday not OK" stay whole
    r"(?<![\w'])(?:[A-Z][\w']*|\d[\w:.]*)(\s+)not\s+(?:(?:on|at|the|for)\s+)*"
    r"(?!OK\b|I\b|A\b)(?:[A-Z]|\d+(?![\d.]*\s*%))"
)
"""Where "not" sets one named thing against another inside a clause."""
_REASON_BREAK = re.compile(
    # "as soon as you can", "as long as it is" compare, they give no reason
    r"(?<!soon)(?<!long)(?<!much)(?<!far)(?<!well)(?<!often)(?<!quickly)(?<!early)"
    r"\s(?=(?:because\s(?!of\b)|(?:as|so)\s+(?:i|we)(?:'|\s)|so\s+(?:that\s+)?(?:he|she|they|it|you|there)(?:'|\s)"
    r"|(?:as|since)\s+(?:he|she|they|it|you|the\s+\w+|\w+)\s+(?:can't|cannot|won't|doesn't|don't|isn't|"
    r"aren't|wasn't|weren't|needs?|has|have|is|are|was|were|will|would|could|should|did|does|can)\b))",
    re.IGNORECASE,
)
"""Where a reason or a consequence of one's own begins ("you won't have to wait for me as I'll be there at
14:45", "no need to keep the old bed because I've ordered a frame", "leave the key in the glovebox, as
Dockside can't test the brakes without it"): a negation in the one does not reach what the other names."""


def _split_contrast(part: str) -> list[str]:
    """``part`` cut before each "not" that sets one named thing against another."""
    cuts = [found.start(1) for found in _CONTRAST_BREAK.finditer(part)]
    return [part[begin:end] for begin, end in zip([0, *cuts], [*cuts, len(part)], strict=True)]


def clauses(text: str) -> list[str]:
    """``text`` cut into clauses."""
    return list(_clauses(normalise_quotes(text)))


@lru_cache(maxsize=4096)
def _clauses(text: str) -> tuple[str, ...]:
    found: list[str] = []
    for part in _CLAUSE_BREAK.split(text):
        contrasts = _split_contrast(part) if "not" in part else [part]
        pieces = [piece for contrast in contrasts for piece in _REASON_BREAK.split(contrast)]
        found.extend(stripped for piece in pieces if (stripped := piece.strip()))
    return tuple(found)


@lru_cache(maxsize=64)
def _any_cue(cues: tuple[str, ...]) -> re.Pattern[str]:
    """One pattern finding any of ``cues`` at word boundaries: one search instead of one per cue.

    The cues that begin a word share one test of the word's start, so inside a word the search tries that
    test once rather than once per cue (the cue lists are long, and every clause of every message is read).
    """
    by_edge: dict[str, list[str]] = {}
    for cue in cues:
        pattern = word_pattern(normalise_quotes(cue)).pattern
        edge = next((e for e in (_LETTER_BEFORE, _DIGIT_BEFORE) if pattern.startswith(e)), "")
        by_edge.setdefault(edge, []).append(f"(?:{pattern[len(edge) :]})")
    return re.compile("|".join(f"{edge}(?:{'|'.join(bodies)})" for edge, bodies in by_edge.items()), re.I)


def has_any(text: str, cues: tuple[str, ...]) -> bool:
    """Whether ``text`` contains one of ``cues`` at word boundaries (what ``has_word`` finds for each)."""
    return _any_cue(cues).search(normalise_quotes(text)) is not None


def is_negated(clause: str) -> bool:
    """Whether ``clause`` carries a negation cue."""
    plain = _FRIENDLY_IDIOMS.sub(" ", clause)
    return has_any(plain, NEGATION_CUES) or _NEGATION_PATTERNS.search(plain) is not None


def _passed_over(clause: str, following: str | None) -> bool:
    """Whether ``clause`` weighs an option that the ``following`` clause turns from ("I thought about the
    2-bed" before "but it's over budget").
    """
    return (
        following is not None and _CONTRARY_START.match(following) is not None
        and has_any(clause, _DELIBERATION_CUES)
    )  # fmt: skip


@lru_cache(maxsize=4096)
def _affirmed(text: str) -> tuple[str, ...]:
    parts = clauses(text)
    following: list[str | None] = [*parts[1:], None]
    return tuple(
        clause
        for clause, after in zip(parts, following, strict=False)  # one more following: the last has none
        if not is_negated(clause) and not _passed_over(clause, after)
    )


@dataclass(frozen=True, slots=True)
class ClauseSpan:
    """Where one clause of a text lies, and whether it affirms what it mentions (:func:`clause_spans`)."""

    start: int
    """Where the clause begins in the text (its surrounding spaces left out)."""
    end: int
    """Where it ends."""
    affirmed: bool
    """Whether :func:`affirmed_clauses` keeps it: no negation cue, and no option weighed then turned from."""
    cues: tuple[tuple[int, int], ...]
    """Where, in the text, what keeps it from affirming is written: its negation cues, or for a clause
    passed over the words that weigh the option ("thought about"); empty for an affirmed clause."""

    def holds(self, begin: int, end: int) -> bool:
        """Whether the span ``begin``-``end`` of the text begins in this clause."""
        return self.start <= begin < self.end

    def covers_cue(self, begin: int, end: int) -> bool:
        """Whether the span ``begin``-``end`` of the text overlaps one of the clause's cues."""
        return any(begin < cue_end and cue_start < end for cue_start, cue_end in self.cues)


def clause_spans(text: str) -> tuple[ClauseSpan, ...]:
    """The clauses of ``text`` as :func:`clauses` cuts them, with where each lies in ``text`` and whether it
    affirms, so a match found in the whole text can be judged by the clause it lies in.
    """
    return _clause_spans(normalise_quotes(text))


@lru_cache(maxsize=4096)
def _clause_spans(text: str) -> tuple[ClauseSpan, ...]:
    parts = _clauses(text)
    following: list[str | None] = [*parts[1:], None]
    spans: list[ClauseSpan] = []
    at = 0
    for clause, after in zip(parts, following, strict=False):
        start = text.find(clause, at)  # clauses are stripped pieces of the text, in order, quotes unchanged
        at = start + len(clause)
        cues = _cue_spans(clause, start)
        passed = not cues and _passed_over(clause, after)
        if passed:
            cues = tuple(
                (start + found.start(), start + found.end())
                for found in _any_cue(_DELIBERATION_CUES).finditer(clause)
            )
        spans.append(ClauseSpan(start, at, not cues and not passed, cues))
    return tuple(spans)


def _cue_spans(clause: str, offset: int) -> tuple[tuple[int, int], ...]:
    """Where ``clause``'s negation cues are (shifted by ``offset``); empty when it is not negated."""
    # friendly idioms ("no problem") blanked out letter for letter, so positions stay those of the clause
    plain = _FRIENDLY_IDIOMS.sub(lambda found: " " * len(found.group(0)), clause)
    found = [*_any_cue(NEGATION_CUES).finditer(plain), *_NEGATION_PATTERNS.finditer(plain)]
    return tuple(sorted((offset + one.start(), offset + one.end()) for one in found))


def affirmed_clauses(text: str) -> list[str]:
    """The clauses of ``text`` without a negation cue."""
    return list(_affirmed(text))


def affirms(text: str, piece: str) -> bool:
    """Whether some clause of ``text`` without negation mentions ``piece``."""
    return any(has_word(clause, piece) for clause in _affirmed(text))


@lru_cache(maxsize=4096)
def declines(text: str) -> bool:
    """Whether ``text`` reads as a refusal, a cancellation or a "does not work" as a whole.

    A message that turns one option down and then takes up another in a later clause of its own ("12:00
    won't work, so could I have until 14:00?") is a counter-offer, not a refusal.
    """
    parts = [_FRIENDLY_IDIOMS.sub(" ", part) for part in clauses(text)]
    refusing = [
        index
        for index, part in enumerate(parts)
        if has_any(part, DECLINE_CUES)
        or any(pattern.search(part) for pattern in _REFUSAL_PATTERNS)
        or (index == 0 and _BARE_REFUSAL.fullmatch(part))
    ]
    if not refusing:
        return False
    return not any(
        not _denies(part) and has_any(part, COUNTER_OFFER_CUES) for part in parts[refusing[0] + 1 :]
    )


_HEDGE = re.compile(
    r"(?<![^\W\d_])(?:probably|maybe|perhaps|possibly|hopefully|tentative(?:ly)?|"
    r"not (?:sure|certain)(?: yet)?|"
    r"(?:i'll|i will|will|let me) (?:confirm|double-check|get back to you)(?! (?:that|the|your|my)\b)|"
    r"let you know(?! (?:if|when|whether|once|as soon|how|what|where|who)\b)|"
    r"i think (?:i|it|that|we|this)(?:'ll| will| should| might| could| can)|"
    r"(?:i|we) (?:might|may) be able|should be able to|(?:i'll|i will|we'll|we will|will) try (?:and|to)|"
    r"if (?:i|we) can(?! help)|fingers crossed|all being well|with any luck|(?:i|we) might|"
    r"if i'm not mistaken|if i remember (?:right|rightly|correctly)|unless i'm wrong|i believe|"
    r"(?:still )?(?:awaiting|pending|waiting (?:on|for)) (?:\w+(?:'s)? ){0,2}"
    r"(?:sign-?off|approval|confirmation)|"
    r"(?:subject|still subject) to (?:change|confirmation|approval)|"
    r"(?:treat|take) (?:it|them|these|those|the \w+) with (?:care|caution|a pinch of salt)|"
    r"(?:final|updated|full) version (?:to follow|later|once)|"
    r"(?:send|share) (?:you )?(?:the|an) (?:final|updated|full) version (?:later|once|when|after))"
    r"(?![^\W\d_])",
    re.IGNORECASE,
)
"""What keeps an answer from being one: "probably", "I'll confirm later", "can I let you know in the
morning?", "I think it should be clear", "I'll try and get there", "if I can", "if I'm not mistaken",
"still awaiting Oliver's sign-off", "I'll send the final version later" (but not "I'll let you know when I'm
on my way")."""
_FIRM = re.compile(
    r"(?<![^\W\d_])(?:yes|yeah|yep|definitely|certainly|absolutely|count (?:me|us) in|i'm in|i am in|"
    r"confirmed|see you|works|sounds (?:good|great|perfect)|(?:that's|is) (?:fine|perfect|great)|perfect|"
    r"great|happy to|(?:i'll|i will|we'll) be there|i can make|can do|will do|booked|coming|attending|"
    r"accept(?:ed)?|(?:love|delighted|glad) to|make it|on my way|done|agreed)(?![^\W\d_])",
    re.IGNORECASE,
)
"""Words that make an answer firm: a clause with one and no hedge outweighs a hedge elsewhere ("Yes, I'm
in! Maybe we can share a cab")."""


@lru_cache(maxsize=4096)
def hedge(text: str) -> str | None:
    """The hedge that keeps ``text`` from being a firm answer, as written, or ``None``: some clause hedges
    and no clause without a hedge answers firmly.
    """
    parts = [normalise_quotes(part) for part in clauses(text)]
    found = next((match.group(0) for part in parts if (match := _HEDGE.search(part))), None)
    if found is None:
        return None
    firm = any(
        _FIRM.search(part) and not _HEDGE.search(part) and not _hedged_condition(parts[index + 1 :])
        for index, part in enumerate(parts)
    )
    return None if firm else found


def _hedged_condition(following: list[str]) -> bool:
    """Whether the clause after a firm one makes it conditional on a hedge: "I'll be there" and "if I can
    get away" is no firm answer.
    """
    return (
        bool(following) and _CONDITION.match(following[0]) is not None and bool(_HEDGE.search(following[0]))
    )


_CONDITION = re.compile(r"\s*(?:if|unless|as long as|provided)\b", re.IGNORECASE)


@dataclass(frozen=True, slots=True)
class Refusal:
    """Why a text reads as a refusal, for explanations (:func:`refusal`)."""

    clause: str
    """The first clause that refuses."""
    cue: str
    """What in it refuses, as written."""
    taken_up: tuple[str, str] | None
    """A later clause that takes up another option and the phrase by which it does (then the text is a
    counter-offer, not a refusal), or ``None``."""


def refusal(text: str) -> Refusal | None:
    """The first refusing clause of ``text`` with its cue, and what takes up another option after it; what
    :func:`declines` decides on, spelt out (called only to explain a verdict).
    """
    parts = [_FRIENDLY_IDIOMS.sub(" ", part) for part in clauses(text)]
    for index, part in enumerate(parts):
        found = _any_cue(DECLINE_CUES).search(normalise_quotes(part))
        found = found or next((m for p in _REFUSAL_PATTERNS if (m := p.search(part))), None)
        cue = found.group(0) if found else None
        if cue is None and index == 0 and _BARE_REFUSAL.fullmatch(part):
            cue = part.strip()
        if cue is None:
            continue
        for later in parts[index + 1 :]:
            offer = _any_cue(COUNTER_OFFER_CUES).search(normalise_quotes(later))
            if offer is not None and not _denies(later):
                return Refusal(part.strip(), cue, (later.strip(), offer.group(0)))
        return Refusal(part.strip(), cue, None)
    return None


def negation_cue(clause: str) -> str | None:
    """The negation cue that keeps ``clause`` from affirming, as written, or ``None`` (for explanations)."""
    plain = normalise_quotes(_FRIENDLY_IDIOMS.sub(" ", clause))
    found = _any_cue(NEGATION_CUES).search(plain) or _NEGATION_PATTERNS.search(plain)
    return found.group(0) if found else None


def found_word(text: str, piece: str) -> str | None:
    """What in ``text`` :func:`has_word` finds for ``piece``, as written, or ``None`` (for explanations)."""
    text = normalise_quotes(text)
    found = word_pattern(normalise_quotes(piece)).search(text)
    if found is None:
        return None
    begin, end = found.span()  # the whole word a piece with '*' found the start or end of
    while begin and text[begin - 1].isalnum():
        begin -= 1
    while end < len(text) and text[end].isalnum():
        end += 1
    return text[begin:end]


def _denies(clause: str) -> bool:
    """Whether ``clause`` is negated, "nothing works" and "neither suits" included."""
    return is_negated(clause) or any(
        has_word(clause, cue) for cue in ("nothing", "neither", "none", "nobody")
    )


# -- days and clock times (read by pare.scenarios.timewords) ---------------------------------------------
_BOUND_CLAUSE = re.compile(
    r"(?<![^\W\d_])(?:before|until|till|by the time|ahead of when)\s+(?:you|she|he|they|we|i|it)"
    r"(?:'(?:re|s|ll|m|ve|d))?\s+\S.*",
    re.IGNORECASE | re.DOTALL,
)
"""A subordinate clause of someone's own act that bounds the plan: "I'll pop round before you head off on
Thursday" plans a visit before Thursday, not on it."""


def without_bound(clause: str) -> str:
    """``clause`` without a bounding clause ("before you fly on Thursday"): the day such a clause names is
    when the plan must be done by, not a day the clause affirms.
    """
    return _BOUND_CLAUSE.sub("", clause) if has_any(clause, _BOUND_WORDS) else clause


_BOUND_WORDS = ("before", "until", "till", "by the time", "ahead of when")


@lru_cache(maxsize=4096)
def _affirmed_mentions(text: str, anchor: datetime) -> tuple[tuple[Mention, ...], ...]:
    """The mentions of each affirmed clause, grouped by sentence (clauses of one sentence together).

    Remembered: the same messages are read again by every check on them and every evaluation.
    """
    groups: list[tuple[Mention, ...]] = []
    for sentence in _SENTENCE_BREAK.split(normalise_quotes(text)):
        group: list[Mention] = []
        for clause in affirmed_clauses(sentence):
            group.extend(mentions(without_bound(clause), anchor))
        if group:
            groups.append(tuple(group))
    return tuple(groups)


def sentences(text: str) -> list[str]:
    """``text``'s sentences, as the day and time operators group them (empty ones left out)."""
    parts = _SENTENCE_BREAK.split(normalise_quotes(text))
    return [sentence.strip() for sentence in parts if sentence.strip()]


def sentence_clauses(text: str) -> list[list[str]]:
    """``text``'s clauses grouped by sentence, as the day and time operators read them."""
    sentences = _SENTENCE_BREAK.split(normalise_quotes(text))
    return [found for sentence in sentences if (found := clauses(sentence))]


def mentions_day(text: str, day: date, anchor: datetime) -> bool:
    """Whether ``text`` affirmatively names ``day``."""
    return any(day in m.days for group in _affirmed_mentions(text, anchor) for m in group)


def mentions_clock(text: str, clock: time, anchor: datetime) -> bool:
    """Whether ``text`` affirmatively names the clock time ``clock``."""
    return any(clock in m.times for group in _affirmed_mentions(text, anchor) for m in group)


def stray_clocks(text: str, allowed: Sequence[tuple[time, time]], anchor: datetime) -> list[Mention]:
    """The clock times ``text`` affirmatively names that fall in none of the ``allowed`` spans (first and
    last minute included; a single time is a span of one minute). A mention counts as allowed when one of
    its readings does: "at 6" is 06:00 or 18:00.
    """

    def fits(clock: time) -> bool:
        return any(first <= clock <= last for first, last in allowed)

    groups = _affirmed_mentions(text, anchor)
    return [m for group in groups for m in group if m.times and not any(fits(clock) for clock in m.times)]


def stray_days(text: str, allowed: frozenset[date], anchor: datetime) -> list[Mention]:
    """The days ``text`` affirmatively names that are none of ``allowed`` (read as of ``anchor``)."""
    groups = _affirmed_mentions(text, anchor)
    return [m for group in groups for m in group if m.days and not m.days & allowed]


def mentions_moment(text: str, moment: datetime, anchor: datetime) -> bool:
    """Whether ``text`` affirmatively names ``moment``'s day together with its clock time: both in one
    sentence, or the text names just one day and one clock time.
    """
    day, clock = moment.date(), moment.time().replace(second=0, microsecond=0)
    groups = _affirmed_mentions(text, anchor)
    for group in groups:
        if any(day in m.days for m in group) and any(clock in m.times for m in group):
            return True
    every = [m for group in groups for m in group]
    days = {frozenset(m.days) for m in every if m.days}
    times = {frozenset(m.times) for m in every if m.times}
    return len(days) == 1 and len(times) == 1 and day in next(iter(days)) and clock in next(iter(times))
