"""Free text read for meaning: words at their boundaries, negated clauses, days and clock times."""

from __future__ import annotations

from datetime import UTC, date, datetime, time, timedelta

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from pare.scenarios.matchers import compile_matcher
from pare.scenarios.meaning import (
    DECLINE_CUES,
    NEGATION_CUES,
    affirms,
    clauses,
    declines,
    has_any,
    has_word,
    is_negated,
    mentions_clock,
    mentions_day,
    mentions_moment,
    normalise_quotes,
    word_finder,
    word_pattern,
)

START = datetime(2025, 3, 18, 9, 10, tzinfo=UTC)  # a Tuesday
THURSDAY_1815 = datetime(2025, 3, 20, 18, 15, tzinfo=UTC)


@pytest.mark.parametrize(
    ("text", "piece", "found"),
    [
        ("I reviewed it", "wed", False),
        ("Wed 14:00 then", "wed", True),
        ("the viewing", "view", False),
        ("the viewing", "view*", True),
        ("rewrite it", "*write", True),
        ("at 6:15pm", "15", True),
        ("costs 150", "15", False),
        ("room 3", "3", True),
        ("room 13", "3", False),
        ("viewings@greenwaylets.example", "greenwaylets", True),
        ("t.nowak@lindenlets.example", "t.nowak@lindenlets.example", True),
        ("see   the\nflat", "see the flat", True),
        ("Thursday", "THURSDAY", True),
        ("I can\u2019t share the cab", "can't share", True),
        ("I can't share the cab", "can\u2019t share", True),
    ],
)
def test_words_are_found_at_their_boundaries(text: str, piece: str, found: bool) -> None:
    assert has_word(text, piece) is found


@pytest.mark.parametrize(
    ("text", "affirmed"),
    [
        ("Thursday works for us", True),
        ("Thursday does not work for us", False),
        ("Thursday doesn't work", False),
        ("Thursday won\u2019t work", False),
        ("Wednesday is out, Thursday works", True),
        ("Wednesday works but not Thursday", False),
        ("Let's do Wednesday instead of Thursday", False),
        ("No problem, Thursday it is", True),
        ("Unfortunately Thursday is impossible", False),
        ("Any day except Thursday", False),
        ("Thursday's out for Hannah", False),
        ("Thursday is taken by the budget review", False),
        ("Thursday clashes with the review", False),
        ("Thursday\u2019s out, so Friday", False),
    ],
)
def test_negated_clauses_affirm_nothing(text: str, affirmed: bool) -> None:
    assert affirms(text, "thursday") is affirmed


@pytest.mark.parametrize(
    ("text", "declined"),
    [
        ("Sorry, I can't make Thursday", True),
        ("Unfortunately we have to cancel", True),
        ("Thursday doesn't work for me", True),
        ("No worries, Thursday works", False),
        ("Thursday works, see you then", False),
        ("Sorry, the cab's full, can't take you", True),
        ("There's no room in the car", True),
        ("I can\u2019t share the cab tonight", True),
        ("No thanks, I'm fine", True),
        ("Thanks but I've already got a cab booked, no need", True),
        ("That's sweet but no need, I have a taxi", True),
        ("Thanks Jess, I'll pass this time", True),
        ("Can't, sorry", True),
        ("No, I'm fine thanks", True),
        ("Sorry, I can't make it, but thanks for asking!", True),
        ("Unfortunately Thursday won't work for us either", True),
        ("No problem, see you at 8", False),
        ("12:00 won't work as I'm on site until 12:30, so could I have check-out until 14:00 please?", False),
        ("Anya can't make Saturday, but Sunday works for her", False),
        ("Thursday doesn't work, how about Friday at 17:30?", False),
        ("Thursday doesn't work, and Friday doesn't work either", True),
        ("Nothing to add, Thursday it is", False),
        ("Unfortunately that doesn't work, nothing works for me this week", True),
        ("Sadly no, I'm away. Maybe another time?", True),
        ("No, Friday is fine", False),
        ("Good news, Zoe said yes for Friday night! No need to worry.", False),
        ("No bus needed, a taxi will meet you at Central at midnight", False),
        ("Afraid the audit review is not going ahead this afternoon", True),
        ("They've called off Friday's session", True),
        ("Sorry, I can't get it back to you, I'm away", True),
        ("I can't get over how good it was, see you Friday", False),
        ("The offsite is scrapped, sorry", True),
        ("Friday's session is not happening, but Monday works", False),
    ],
)
def test_declines(text: str, declined: bool) -> None:
    assert declines(text) is declined


@pytest.mark.parametrize(
    ("text", "answers"),
    [
        ("Probably in, I'll confirm later!", False),
        ("Thanks Jess! Can I let you know in the morning?", False),
        ("I think the drive should be clear on Monday, but I'll confirm over the weekend", False),
        ("Not sure yet, Thursday might work", False),
        ("Yes, I'm in! Maybe we can share a cab", True),
        ("Thursday at 7 works. I'll let you know when I'm on my way", True),
        ("We're both coming - hopefully the sun shines for you!", True),
        ("Hopefully see you soon! Thursday works", True),
        ("I'll try and get there for six", False),
        ("I'll be there if I can get away from work", False),
        ("I might make Thursday, fingers crossed", False),
        ("Yes, I'll be there. I'll try to bring the chairs", True),
        ("It's Thursday at 19:30 if I'm not mistaken", False),
        ("Figures attached, still awaiting Oliver's sign-off", False),
        ("Here is the form; I'll send the final version later", False),
    ],
)
def test_a_hedge_is_no_answer_for_declines_false(text: str, answers: bool) -> None:
    # a hedge neither refuses nor agrees: `declines: false` wants an answer, `declines: true` a refusal
    assert compile_matcher({"declines": False}).test(text, START) is answers
    assert not compile_matcher({"declines": True}).test(text, START)


@pytest.mark.parametrize(
    ("text", "named"),
    [
        ("Thursday at 18:15 works for us.", True),
        ("Thu 6:15pm is great", True),
        ("Thursday works. See you at 6.15 pm", True),
        ("Could we do 20 March at 18:15?", True),
        ("March 20th, 18h15", True),
        ("See you on 20/03 at 18:15", True),
        ("2025-03-20 18:15", True),
        ("No problem, Thursday at 6:15 p.m. then", True),
        ("Wednesday at 18:30 doesn't suit; Thursday 18:15 is perfect", True),
        ("Thursday does not work, 18:15 on Wednesday is fine", False),
        ("Unfortunately Thursday at 18:15 won't work", False),
        ("Wednesday at 18:15 works", False),
        ("Thursday at 19:15 works", False),
        ("It costs $18.15 on Thursday", False),
    ],
)
def test_a_moment_is_read_as_a_day_with_a_clock_time(text: str, named: bool) -> None:
    assert mentions_moment(text, THURSDAY_1815, START) is named


@pytest.mark.parametrize(
    ("text", "day"),
    [
        ("tomorrow then", date(2025, 3, 19)),
        ("today at noon", date(2025, 3, 18)),
        ("the day after tomorrow", date(2025, 3, 20)),
        ("next Thursday", date(2025, 3, 27)),
        ("next Thursday", date(2025, 3, 20)),
        ("on the 22nd", date(2025, 3, 22)),
        ("Sat 22 March", date(2025, 3, 22)),
        ("Friday", date(2025, 3, 21)),
    ],
)
def test_days_resolve_against_the_start(text: str, day: date) -> None:
    assert mentions_day(text, day, START)


def test_a_weekday_is_the_next_one_on_or_after_the_start() -> None:
    assert mentions_day("Tuesday", date(2025, 3, 18), START)
    assert not mentions_day("Tuesday", date(2025, 3, 25), START)
    assert not mentions_day("We sat on the sofa", date(2025, 3, 22), START)  # lower-case 'sat' is a verb


@pytest.mark.parametrize(
    ("text", "clock", "named"),
    [
        ("at 8 then", time(20, 0), True),
        ("at 8 then", time(8, 0), True),
        ("8am sharp", time(20, 0), False),
        ("around 6.30pm", time(18, 30), True),
        ("midday", time(12, 0), True),
        ("7 o'clock", time(19, 0), True),
        ("flat 8, 27 Linden Street", time(20, 0), False),
    ],
)
def test_clock_times(text: str, clock: time, named: bool) -> None:
    assert mentions_clock(text, clock, START) is named


def test_the_matchers_read_for_meaning() -> None:
    assert compile_matcher({"mentions_time": "day+2 18:15"}).test("Thursday at 6:15pm suits", START)
    assert compile_matcher({"mentions_day": "day+2"}).test(["Thu works"], START)
    assert compile_matcher({"mentions_clock": "18:15"}).test({"content": "at 18.15"}, START)
    assert compile_matcher({"affirms": ["thursday", "lea"]}).test("Lea and I can do Thursday", START)
    assert not compile_matcher({"declines": False}).test("Sorry, we cannot make it", START)
    assert not compile_matcher({"contains": "wed"}).test("reviewed", START)
    described = compile_matcher({"mentions_clock": "18:15", "affirms": "x"}).describe()
    assert described == "mentions_clock 18:15 and affirms ['x']"


def test_a_thousands_comma_does_not_cut_a_number_in_two() -> None:
    assert clauses("My salary is 44,200 pounds, as agreed.") == ["My salary is 44,200 pounds", "as agreed"]
    assert compile_matcher({"affirms": "44,200"}).test("My salary is now 44,200 a year", START)
    assert not compile_matcher({"affirms": "44,200"}).test("It is not 44,200 any more", START)


def test_an_unquoted_yaml_date_names_a_day() -> None:
    import yaml

    matcher = compile_matcher(yaml.safe_load("{mentions_day: 2025-03-20}"))
    assert matcher.test("Thursday 20 March is fine", START)


def test_being_out_or_away_negates_the_day_it_names() -> None:
    thursday = START.date() + timedelta(days=2)
    assert mentions_day("Thursday works for me.", thursday, START)
    away = ("I'm away on Thursday.", "I'm out on Thursday.", "We'll be away Thursday", "I am out Thursday")
    for text in away:
        assert not mentions_day(text, thursday, START), text
    assert mentions_day("Thursday works, I'm back from being away by then.", thursday, START)


def test_an_unquoted_yaml_time_compares_as_a_time_with_the_state() -> None:
    import yaml

    listed = compile_matcher(yaml.safe_load("{one_of: [2025-03-20T14:00:00Z]}"))
    assert listed.test("2025-03-20T14:00:00+00:00", START)
    assert not listed.test("2025-03-20T15:00:00+00:00", START)
    assert compile_matcher(yaml.safe_load("{equals: 2025-03-20 14:00:00}")).test("2025-03-20 14:00", START)


def test_a_weekday_written_with_its_date_names_that_date_only() -> None:
    monday = datetime(2025, 5, 12, 8, 30, tzinfo=UTC)
    text = "Baton practice is on Thursday 22 May at 19:30."
    assert mentions_day(text, date(2025, 5, 22), monday)
    assert not mentions_day(text, date(2025, 5, 15), monday)  # not this week's Thursday as well
    assert mentions_day("Thursday works", date(2025, 5, 15), monday)
    assert mentions_day("Tue the 20th suits", date(2025, 5, 20), monday)


def test_a_date_earlier_in_the_text_does_not_swallow_a_later_weekday() -> None:
    saturday = datetime(2025, 5, 17, 9, 20, tzinfo=UTC)
    assert mentions_day(
        "Since 12 May we have had no water. Tue and Thu mornings are free", date(2025, 5, 20), saturday
    )


@pytest.mark.parametrize(
    ("text", "piece", "found"),
    [
        ("Collect dry-cleaning", "dry clean*", True),
        ("Collect dry cleaning", "dry-clean*", True),
        ("Collect drycleaning", "dry-clean*", True),
        ("Collect dry   cleaning", "dry clean*", True),
        ("a dry day, cleaning later", "dry clean*", False),
        # an abbreviation's stop may be left out with its space kept, or the space with its stop kept
        ("Pick up Mum's gift from no 14", "no. 14", True),
        ("Pick up Mum's gift from No.14", "no. 14", True),
        ("Pick up Mum's gift from no14", "no. 14", False),
        ("Pick up Mum's gift from no 145", "no. 14", False),
    ],
)
def test_spaces_and_hyphens_in_a_piece_find_each_other(text: str, piece: str, found: bool) -> None:
    assert has_word(text, piece) is found


@pytest.mark.parametrize(
    "text",
    ["Cedar Rd (no. 22) please, the garden one.", "Please hold No 22 Cedar Road", "Flat no.3 on Cedar Road"],
)
def test_a_house_number_written_no_is_not_a_negation(text: str) -> None:
    assert affirms(text, "cedar")
    assert not declines(text)


def test_a_bare_no_still_ends_its_clause() -> None:
    assert not affirms("No. Thursday doesn't suit", "thursday")
    assert affirms("I said no. Thursday works", "thursday")


def test_the_days_a_text_names_are_read_against_each_start() -> None:
    """What a text names is remembered by text and start: 'tomorrow' is another day from another start."""
    from pare.scenarios import meaning

    later = START + timedelta(days=7)
    for _ in range(2):
        assert meaning.mentions_day("See you tomorrow", (START + timedelta(days=1)).date(), START)
        assert not meaning.mentions_day("See you tomorrow", (START + timedelta(days=1)).date(), later)
        assert meaning.mentions_day("See you tomorrow", (later + timedelta(days=1)).date(), later)


# Letters and digits of both kinds, separators (runs of them too), apostrophes (straight and curly), '*' and
# characters whose case-insensitive matching is not ASCII's (Kelvin sign, long s, dotted and dotless i, sharp
# s, superscript two)
_BITS = [*"aAbBkKsSiI09_ -'*.,\t\n\x1c", " - ", "--", "  ", "a-b", "a b"]
_BITS += ["\u2019", "\u2018", "é", "ß", "\u212a", "\u017f", "\u0130", "\u0131", "²"]
_PIECES = (
    st.lists(st.sampled_from(_BITS), min_size=1, max_size=4)
    .map("".join)
    .filter(lambda piece: bool(" ".join(normalise_quotes(piece).split()).strip("*")))
)


@st.composite
def _piece_and_text(draw: st.DrawFn) -> tuple[str, str]:
    piece = draw(_PIECES)
    noise = st.lists(st.sampled_from(_BITS), max_size=3).map("".join)
    written = draw(st.sampled_from([piece, piece.upper(), piece.lower(), piece.strip("*"), piece.swapcase()]))
    inside = draw(st.booleans())
    text = draw(noise) + (written if inside else "") + draw(noise) + draw(st.sampled_from(["", written]))
    return piece, text


@settings(max_examples=3000, deadline=None)
@given(_piece_and_text())
def test_a_word_is_found_where_its_pattern_finds_it(case: tuple[str, str]) -> None:
    piece, text = case
    expected = word_pattern(normalise_quotes(piece)).search(normalise_quotes(text)) is not None
    assert word_finder(piece).found(normalise_quotes(text)) is expected
    assert has_word(text, piece) is expected


@settings(max_examples=500, deadline=None)
@given(st.text(max_size=6), st.text(max_size=12))
def test_a_word_is_found_where_its_pattern_finds_it_in_any_text(piece: str, text: str) -> None:
    if not " ".join(normalise_quotes(piece).split()).strip("*"):
        with pytest.raises(ValueError, match="no text"):
            word_finder(piece)
        return
    expected = word_pattern(normalise_quotes(piece)).search(normalise_quotes(text)) is not None
    assert has_word(text, piece) is expected


@pytest.mark.parametrize(
    "text",
    [
        "not Fri 🙈 Any chance we could move it?",
        "not Fri 🙈🙈 Any chance we could move it?",
        "not Fri 👍🏽 Any chance we could move it?",  # a skin tone: one pictograph
        "not Fri ❤️ Any chance we could move it?",  # a variation selector
        "not Fri 👨‍👩‍👧 Any chance we could move it?",  # a family joined by zero-width joiners
        "not Fri 🇫🇷 Any chance we could move it?",  # a flag
        "not Fri ✅ Any chance we could move it?",
        "not Fri ⏰ Any chance we could move it?",
        "not Fri‼ Any chance we could move it?",
    ],
)
def test_an_emoji_ends_a_sentence(text: str) -> None:
    assert clauses(text) == ["not Fri", "Any chance we could move it"]
    assert affirms(text, "move*")
    assert not affirms(text, "fri")


def test_symbols_written_inside_a_sentence_do_not_end_it() -> None:
    for text in ("Acme™ works © 2025", "Mon → Tue works", "he said ❝yes❞ to Thursday", "Bob ↔ Ann"):
        assert clauses(text) == [text]


def test_a_star_inside_a_piece_lets_that_word_go_on() -> None:
    from pare.scenarios.meaning import has_word

    assert has_word("Could you drop us at the door?", "drop* us")
    assert has_word("dropping us off at six", "drop* us")
    assert has_word("It didn't work", "didn*t work")
    assert not has_word("a preview of it", "view*")
    assert not has_word("drop them off", "drop* us")


def test_a_comma_inside_a_figure_with_a_unit_is_no_clause_break() -> None:
    assert clauses("rent is $2,150pcm, bills extra") == ["rent is $2,150pcm", "bills extra"]


def test_a_number_after_no_or_a_rough_figure_does_not_end_a_sentence() -> None:
    from pare.scenarios.meaning import sentences

    assert sentences("We'll pass on no. 9 Poplar. Thanks!") == ["We'll pass on no. 9 Poplar", "Thanks"]
    assert sentences("It is approx. 5 minutes away. See you.") == ["It is approx. 5 minutes away", "See you"]
    assert sentences("There are no. Really none.") == ["There are no", "Really none"]


def test_the_days_of_one_sentence_end_at_an_emoji() -> None:
    # two sentences, each with one day or one time: only as the text's only day and only time together
    assert mentions_moment("Thursday 🙂 18:15 then", THURSDAY_1815, START)
    assert not mentions_moment("Thursday 🙂 18:15 then, or Friday 🙂 08:00", THURSDAY_1815, START)
    assert mentions_moment("Thursday 18:15 🙂 or Friday 08:00", THURSDAY_1815, START)


def test_every_emoji_pictograph_ends_a_sentence() -> None:
    regex = pytest.importorskip("regex")  # its Unicode tables say which characters are pictographs
    pictographs = [
        chr(code)
        for code in [*range(0x2600, 0x2760), *range(0x1F000, 0x1FB00)]
        if regex.fullmatch(r"\p{Extended_Pictographic}", chr(code))
    ]
    assert len(pictographs) > 1000
    for char in pictographs:
        assert clauses(f"not Fri {char} move it") == ["not Fri", "move it"], hex(ord(char))


@pytest.mark.parametrize(
    ("text", "piece", "affirmed"),
    [
        # passing an option over is not choosing it; the option chosen beside it still is
        ("I left out Rowan Street", "rowan street", False),
        ("I left Rowan Street's keys out for you", "rowan street", True),
        ("I ruled out the Harbour flat", "harbour", False),
        ("The Harbour flat is the one I chose", "harbour", True),
        ("I skipped Harbour Walk", "harbour walk", False),
        ("We walked Harbour Walk", "harbour walk", True),
        ("I decided against the Harbour flat", "harbour", False),
        ("I thought about the 2-bed but it's over budget", "2-bed", False),
        ("I considered Friday but went for Saturday", "saturday", True),
        ("I considered Friday but went for Saturday", "friday", False),
        ("I thought about Thursday and booked it", "thursday", True),
        ("The moon lamp went up to \u00a342, so I went for the globe", "moon lamp", False),
        ("The moon lamp went up to \u00a342, so I went for the globe", "globe", True),
        ("I went up to the moon lamp stall", "moon lamp", True),
        ("I ordered the L rather than the XL", "XL", False),
        ("I ordered the L rather than the XL", "L", True),
        ("Booked Saturday instead of Friday", "friday", False),
        ("Booked Saturday instead of Friday", "saturday", True),
        # a negation about someone else's act or a side remark stays in its own clause
        ("You won't have to wait for me as I'll be there at 14:45", "14:45", True),
        ("You won't have to wait for me as I'll be there at 14:45", "wait", False),
        ("There's no need to keep the old bed because I've ordered a frame for Saturday", "saturday", True),
        ("There's no need to keep the old bed because I've ordered a frame for Saturday", "keep", False),
        ("I can't make it because of Thursday", "thursday", False),
        ("Booked the Thursday shift not sure what I'd have done otherwise", "thursday", True),
        ("Booked the Thursday shift but not sure it's confirmed", "confirmed", False),
        ("I'm not sure Thursday works", "thursday", False),
        # "X not Y": X affirmed, Y negated; "Thursday does not work" and "Thursday not OK" stay whole
        ("Collection Wednesday not Tuesday", "wednesday", True),
        ("Collection Wednesday not Tuesday", "tuesday", False),
        ("the 3rd not the 4th", "3rd", True),
        ("the 3rd not the 4th", "4th", False),
        ("Thursday does not work", "thursday", False),
        ("Thursday not OK for me", "thursday", False),
        ("Thursday not ideal", "thursday", False),
        ("Thursday not 100% sure", "thursday", False),
    ],
)
def test_what_is_passed_over_or_set_aside_is_not_affirmed(text: str, piece: str, affirmed: bool) -> None:
    assert affirms(text, piece) is affirmed


def test_both_of_us_being_out_turns_the_day_down() -> None:
    thursday = START.date() + timedelta(days=2)
    for text in ("We're both out on Thursday", "We are all away Thursday", "We'll both be out on Thursday"):
        assert not mentions_day(text, thursday, START), text
    assert mentions_day("We're all set for Thursday", thursday, START)
    assert mentions_day("Mum and Dad are both away on the 2nd, so book the sitter Thursday", thursday, START)


def test_a_side_remark_of_thanks_is_no_hedge_or_refusal() -> None:
    thanks = "Priya kindly agreed, not sure what I'd have done otherwise"
    assert not is_negated(clauses(thanks)[1])
    assert is_negated("not sure whether Priya agreed")
    assert not declines("You won't have to wait for me, I'll be there at 14:45")
    assert not declines("No need to keep the old bed, see you Saturday")
    assert declines("No need, thanks")


_CUE_TEXT = st.lists(
    st.sampled_from([*NEGATION_CUES, *DECLINE_CUES, "Thursday", "7", "x", "'", "-"]).map(
        lambda w: w.strip("*")
    )
    | st.text(alphabet="abnot'1 -.", max_size=4),
    max_size=6,
).map(" ".join)


@settings(max_examples=1500, deadline=None)
@given(_CUE_TEXT, st.sampled_from(["", "x", "1", " "]))
def test_a_cue_list_finds_what_its_cues_find_one_by_one(text: str, glue: str) -> None:
    for cues in (NEGATION_CUES, DECLINE_CUES):
        glued = glue + text + glue
        assert has_any(glued, cues) is any(has_word(glued, cue) for cue in cues)


def test_nothing_and_none_negate_their_clause() -> None:
    from pare.scenarios.meaning import affirms

    assert not affirms("Nothing critical in the results", "critical")
    assert not affirms("none of it is urgent", "urgent")
    assert affirms("Thursday works, nothing else planned", "thursday")  # only its own clause


def test_cant_wait_is_eager_but_cant_wait_till_refuses_the_wait() -> None:
    from pare.scenarios.meaning import affirms

    assert affirms("Can't wait to see you on Thursday", "thursday")
    assert not affirms("It can't wait till February", "february")
    assert affirms("Ella can't wait for the trip on Friday", "friday")
    assert not affirms("This can't wait for Monday", "monday")


def test_what_is_set_aside_or_moved_from_is_not_affirmed() -> None:
    assert not affirms("the GreenLoop ones can stay on the shelf", "greenloop")
    assert not affirms("Talk moved from Thursday 14:00", "thursday")
    assert affirms("Talk moved from Thursday to Friday", "friday")  # where it is now is named too
    assert affirms("Saffron House (moved from Osteria Bruno)", "saffron")
    assert not affirms("Saffron House (moved from Osteria Bruno)", "osteria")


def test_nothing_but_affirms_what_follows() -> None:
    assert affirms("he'll have nothing but the new kibble from now on", "kibble")
    assert not affirms("nothing arrived", "arrived")


def test_but_after_any_or_every_means_except() -> None:
    assert not affirms("Any day but Wednesday works for me", "wednesday")
    assert not affirms("anything but the 2kg bag", "2kg")
    assert affirms("I can do any day, but Wednesday is best", "wednesday")
    assert affirms("Wednesday is fine but Thursday is better", "thursday")


def test_an_aside_that_negates_negates_only_itself() -> None:
    assert affirms("Meadowbank Vets Hillcrest (not the main surgery)", "hillcrest")
    assert not affirms("Meadowbank Vets Hillcrest (not the main surgery)", "main surgery")


@pytest.mark.parametrize(
    "text",
    [
        "Not the regular oat drink, the barista one",
        "I thought about the 2-bed but it's over budget. Got the studio",
        "No problem, see you Friday - can't do Thursday",
        "Kept Beech Grove (3 bed) but removed Elm Court",
        "  the 3rd not the 4th;  ",
    ],
)
def test_clause_spans_place_the_clauses_and_say_which_affirm(text: str) -> None:
    from pare.scenarios.meaning import affirmed_clauses, clause_spans

    spans = clause_spans(text)
    assert [text[span.start : span.end] for span in spans] == clauses(text)
    assert [text[span.start : span.end] for span in spans if span.affirmed] == affirmed_clauses(text)
    for span in spans:  # what keeps a clause from affirming is written inside it
        assert span.affirmed is not bool(span.cues)
        assert all(span.start <= begin < end <= span.end for begin, end in span.cues)


def test_clause_spans_show_the_cue_a_match_may_cover() -> None:
    from pare.scenarios.meaning import clause_spans

    text = "Sorry, I can't make Friday"
    negated = clause_spans(text)[1]
    cue = text.index("can't")
    assert not negated.affirmed and negated.holds(cue, cue + 10)
    assert negated.covers_cue(cue, cue + 10)
    assert not negated.covers_cue(text.index("Friday"), len(text))


@pytest.mark.parametrize(
    ("text", "cut"),
    [
        ("Leave the key in the glovebox as Dockside can't test the brakes without it", True),
        ("Don't bring the car since the garage is closed", True),
        ("I went for the lighter spring version so it won't be too warm", True),
        ("The TN-25 is compatible as well if TN-23 is out of stock", True),
        ("Send it as soon as you can", False),
        ("Fine as long as it is before noon", False),
    ],
)
def test_a_reason_or_a_condition_with_its_own_subject_is_a_clause_of_its_own(text: str, cut: bool) -> None:
    assert (len(clauses(text)) > 1) is cut


def test_a_decimal_comma_does_not_cut_a_clause() -> None:
    assert clauses("It is €25,70 each, and 1,200 in all, 10, 20 or 30") == [
        "It is €25,70 each",
        "and 1,200 in all",
        "10",
        "20 or 30",
    ]
