"""Days and clock times read from free text: the informal forms, ordinals, ranges, the part of the day, and
what the date library adds (and is kept from adding)."""

from __future__ import annotations

import copy
import subprocess
import sys
from datetime import UTC, date, datetime, time, timedelta
from typing import Any

import pytest
import yaml

from pare.bench.selftest import check_scenario
from pare.scenarios import Scenario, parse_scenario
from pare.scenarios.library import BENCH_DIR
from pare.scenarios.matchers import compile_matcher, written_at
from pare.scenarios.meaning import clauses, is_negated, mentions_clock, mentions_day, mentions_moment
from pare.scenarios.model import ActionPattern
from pare.scenarios.patterns import CompiledPattern
from pare.scenarios.timewords import mentions
from pare.sim.log import LogEntry

JUNE_1 = datetime(2025, 6, 1, 9, 0, tzinfo=UTC)  # a Sunday
JUNE_5 = datetime(2025, 6, 5, 9, 0, tzinfo=UTC)  # a Thursday


def _times(text: str, anchor: datetime = JUNE_1) -> list[set[str]]:
    return [{moment.strftime("%H:%M") for moment in m.times} for m in mentions(text, anchor) if m.times]


def _days(text: str, anchor: datetime = JUNE_1) -> list[set[date]]:
    return [set(m.days) for m in mentions(text, anchor) if m.days]


@pytest.mark.parametrize(
    ("text", "readings"),
    [
        ("half nine", [{"09:30", "21:30"}]),
        ("see you at half 9", [{"09:30", "21:30"}]),
        ("half past nine", [{"09:30", "21:30"}]),
        ("quarter past 3", [{"03:15", "15:15"}]),
        ("a quarter to four", [{"03:45", "15:45"}]),
        ("ten to four", [{"03:50", "15:50"}]),
        ("20 past 3", [{"03:20", "15:20"}]),
        ("25 minutes to 4", [{"03:35", "15:35"}]),
        ("nine o'clock", [{"09:00", "21:00"}]),
        ("at nine", [{"09:00", "21:00"}]),
        ("at nine thirty", [{"09:30", "21:30"}]),
        ("noon", [{"12:00"}]),
        ("8 in the evening for you", [{"20:00"}]),
        ("9 in the morning", [{"09:00"}]),
        ("half nine in the evening", [{"21:30"}]),
        ("at 11 at night", [{"23:00"}]),
        # the part of the day said just before the time picks it too
        ("tomorrow evening, about half six", [{"18:30"}]),
        ("Friday morning at 9", [{"09:00"}]),
        ("tonight at 8", [{"20:00"}]),
        ("five to midnight", [{"23:55"}]),
        ("at five to midnight", [{"23:55"}]),
        ("quarter past noon", [{"12:15"}]),
        ("cab at half seven from the lobby", [{"07:30", "19:30"}]),
        ("tickets for the half seven show", [{"07:30", "19:30"}]),
        ("twenty to two outside the office", [{"01:40", "13:40"}]),
    ],
)
def test_informal_clock_times_are_read(text: str, readings: list[set[str]]) -> None:
    assert _times(text) == readings


@pytest.mark.parametrize(
    "text",
    [
        "at one point we met",  # a word hour counting something
        "half an hour",
        "2 to 4",  # neither "2 minutes to 4" nor a range without a time on either end
        "the score was 2-4",
        "between 2 and 4 guests",
        "it costs $18.15",
        "half one of the boxes",
        "five to ten people",
        "meet at 5 Market Row",  # "Mar" in a street name is no month
    ],
)
def test_numbers_that_are_not_times_are_not_read_as_times(text: str) -> None:
    assert _times(text) == []


@pytest.mark.parametrize(
    ("text", "readings"),
    [
        ("2-4pm", [{"14:00"}, {"16:00"}]),
        ("2pm - 4pm", [{"14:00"}, {"16:00"}]),
        ("11-1pm", [{"11:00"}, {"13:00"}]),
        ("10am-2", [{"10:00"}, {"14:00"}]),
        ("14:00\u201316:00", [{"14:00"}, {"16:00"}]),
        ("9:30 to 11", [{"09:30", "21:30"}, {"11:00", "23:00"}]),
        ("between 2 and 4", [{"02:00", "14:00"}, {"04:00", "16:00"}]),
        ("between 2 and 4 works", [{"02:00", "14:00"}, {"04:00", "16:00"}]),
        ("from 2 to 4 in the afternoon", [{"14:00"}, {"16:00"}]),
    ],
)
def test_a_range_names_both_its_ends(text: str, readings: list[set[str]]) -> None:
    assert _times(text) == readings


def test_the_nth_is_the_next_one_from_when_it_is_read() -> None:
    assert _days("the 2nd", JUNE_1) == [{date(2025, 6, 2)}]  # said on 1 June: tomorrow
    assert _days("the 2nd", JUNE_5) == [{date(2025, 7, 2)}]  # said on 5 June: next month's
    assert _days("the 5th", JUNE_5) == [{date(2025, 6, 5)}]  # today counts
    assert _days("the 31st", datetime(2025, 6, 5, tzinfo=UTC)) == [{date(2025, 7, 31)}]  # June has no 31st


def test_the_nth_after_a_date_in_the_same_sentence_is_also_read_in_its_month() -> None:
    june_16 = datetime(2025, 6, 16, 9, 0, tzinfo=UTC)
    days = _days("I checked in on 2 June and out on the 5th.", june_16)
    assert date(2025, 6, 5) in days[-1]  # the sentence set the month
    assert date(2025, 7, 5) in days[-1]  # and the next 5th is still a reading
    assert _days("I checked in on 2 June. Out on the 5th.", june_16)[-1] == {
        date(2025, 7, 5)
    }  # another sentence


def test_half_nine_on_the_2nd_names_the_same_moment_as_0930_on_2_june() -> None:
    moment = datetime(2025, 6, 2, 9, 30, tzinfo=UTC)
    for text in (
        "09:30 on 2 June",
        "half nine on the 2nd",
        "the 2nd at half past nine",
        "9.30 in the morning on the 2nd",
    ):
        assert mentions_moment(text, moment, JUNE_1), text
    assert not mentions_moment("half nine on the 3rd", moment, JUNE_1)
    assert not mentions_moment("half nine in the evening on the 2nd", moment, JUNE_1)


def test_relative_phrases_are_read_by_the_date_library() -> None:
    assert _days("Could we do it in two days?") == [{date(2025, 6, 3)}]
    assert mentions_moment("in 3 days at 5pm", datetime(2025, 6, 4, 17, 0, tzinfo=UTC), JUNE_1)
    assert _days("2 days from now works") == [{date(2025, 6, 3)}]


@pytest.mark.parametrize(
    "text",
    [
        "we will see",  # "we" is not Wednesday
        "I may come",  # "may" is not May
        "She sat down",
        "8 in the evening",  # a time of day names no day
    ],
)
def test_the_date_library_does_not_add_false_days(text: str) -> None:
    assert _days(text) == []


def test_a_price_before_a_relative_phrase_does_not_shift_it() -> None:
    assert _days("Flat 22, 1,200 a month, free 2 days from now") == [{date(2025, 6, 3)}]


def test_weekdays_stay_on_or_after_the_reference_day() -> None:
    assert mentions_day("Thursday works", date(2025, 6, 5), JUNE_5)  # the library would say next week's
    assert mentions_day("next Thursday", date(2025, 6, 12), JUNE_5)


def test_a_dash_or_a_colon_ends_a_clause_but_not_a_range_or_a_clock_time() -> None:
    assert clauses("Not Friday - Thursday works") == ["Not Friday", "Thursday works"]
    assert clauses("Not Friday\u2014Thursday works") == ["Not Friday", "Thursday works"]
    assert clauses("Update: Thursday works") == ["Update", "Thursday works"]
    assert clauses("2 - 4pm at 18:30 works") == ["2 - 4pm at 18:30 works"]
    thursday = date(2025, 6, 5)
    assert mentions_day("Not Friday - Thursday works", thursday, JUNE_1)
    assert not mentions_day("Not Friday - Thursday works", date(2025, 6, 6), JUNE_1)


def test_someone_else_being_away_is_not_a_negation() -> None:
    second = date(2025, 6, 2)
    assert mentions_day("Mum is away on the 2nd so we need the sitter that day", second, JUNE_1)
    assert mentions_day("Jo's away the 2nd, can you cover?", second, JUNE_1)
    assert mentions_day("They are away the 2nd", second, JUNE_1)
    assert not mentions_day("I'm away on the 2nd", second, JUNE_1)
    assert not mentions_day("We'll be away on the 2nd", second, JUNE_1)


@pytest.mark.parametrize(
    "clause",
    ["no later than 5pm on Friday", "never mind, Friday", "no rush, Friday is fine", "no more than two"],
)
def test_bounds_and_friendly_phrases_are_not_negations(clause: str) -> None:
    assert not is_negated(clause)


def test_a_count_after_a_dash_is_no_end_of_a_range() -> None:
    assert _times("HL presale 10:00 - 2x standing") == [{"10:00", "22:00"}]


def test_a_zero_padded_hour_is_the_morning_and_thousands_are_no_hours() -> None:
    assert _times("by 09:30") == [{"09:30"}]
    assert _times("by 9:30") == [{"09:30", "21:30"}]
    assert _times("the rent goes from 2,950 to 2,900") == []


def test_the_nth_after_a_past_act_may_be_the_last_one() -> None:
    june_20 = datetime(2025, 6, 20, 9, 0, tzinfo=UTC)
    assert _days("I paid it on the 11th", june_20) == [{date(2025, 6, 11), date(2025, 7, 11)}]
    assert _days("due on the 11th", june_20) == [{date(2025, 7, 11)}]


def test_a_weekday_after_a_past_act_may_be_the_one_gone_by() -> None:
    saturday = datetime(2025, 6, 14, 10, 0, tzinfo=UTC)
    assert _days("the one I ordered on Thursday", saturday) == [{date(2025, 6, 12), date(2025, 6, 19)}]
    assert _days("it arrived Thu, broken", saturday) == [{date(2025, 6, 12), date(2025, 6, 19)}]
    assert _days("see you on Thursday", saturday) == [{date(2025, 6, 19)}]


def test_a_day_span_gives_its_month_to_both_ends() -> None:
    wednesday = datetime(2025, 9, 3, 10, 0, tzinfo=UTC)
    assert _days("Friday 12 to Sunday 14 September", wednesday) == [{date(2025, 9, 12)}, {date(2025, 9, 14)}]
    assert _days("Sat 13 and Sun 14 September", wednesday)[0] == {date(2025, 9, 13)}
    assert _days("open 9 to 5 on 4 June", wednesday) == [{date(2025, 6, 4), date(2026, 6, 4)}]


def test_the_day_after_follows_the_day_just_named() -> None:
    wednesday = datetime(2025, 9, 3, 10, 0, tzinfo=UTC)
    assert _days("closed tomorrow and the day after", wednesday) == [{date(2025, 9, 4)}, {date(2025, 9, 5)}]
    assert _days("the day after the party", wednesday) == []


def test_a_weekday_said_with_next_week_is_in_next_week() -> None:
    monday = datetime(2025, 9, 15, 10, 0, tzinfo=UTC)
    assert _days("can you cover my Tuesday run next week?", monday) == [{date(2025, 9, 23)}]
    assert _days("next week on Friday", monday) == [{date(2025, 9, 26)}]
    assert _days("see you Tuesday", monday) == [{date(2025, 9, 16)}]


def test_the_end_of_a_month_is_its_last_week() -> None:
    wednesday = datetime(2025, 9, 3, 10, 0, tzinfo=UTC)
    assert _days("pay it by the end of the month", wednesday) == [
        {date(2025, 9, day) for day in range(24, 31)}
    ]
    assert max(_days("by the end of next month", wednesday)[0]) == date(2025, 10, 31)
    (june,) = _days("until the end of June", wednesday)
    assert {date(2025, 6, 28), date(2026, 6, 30)} <= june and date(2025, 6, 23) not in june


def test_the_first_is_a_day_only_with_a_month_or_a_preposition() -> None:
    wednesday = datetime(2025, 9, 3, 10, 0, tzinfo=UTC)
    assert _days("I keep the first.", wednesday) == []
    assert _days("the rent goes out on the first.", wednesday) == [{date(2025, 10, 1)}]


def test_midnight_is_also_the_last_minute_of_the_day() -> None:
    assert _times("submit it by midnight") == [{"00:00", "23:59"}]


def test_a_dotted_date_with_its_year_ends_a_sentence() -> None:
    may = datetime(2025, 5, 1, 9, 0, tzinfo=UTC)
    assert _days("The warranty ends on 21.05.2026.", may) == [{date(2026, 5, 21)}]
    assert _times("The warranty ends on 21.05.2026.", may) == []
    assert _days("firmware v1.2.3.4", may) == []


def test_an_h_between_clock_digits_needs_no_space_around_it() -> None:
    assert _times("26x26x5 H13 filter") == []
    assert _times("18h15") == [{"18:15"}]


def test_chat_shorthand_for_tomorrow_and_the_evening_is_read() -> None:
    may = datetime(2025, 5, 1, 9, 0, tzinfo=UTC)
    assert _days("Tmrw eve, usual 6:30", may) == [{date(2025, 5, 2)}]
    assert _times("Tmrw eve, usual 6:30", may) == [{"18:30"}]
    assert _days("see you tmw", may) == [{date(2025, 5, 2)}]


def test_in_a_minute_is_soon_and_a_time_before_a_ride_is_a_time() -> None:
    assert _times("my bio will follow in a minute", datetime(2025, 5, 1, 9, 12, tzinfo=UTC)) == []
    assert _times("it was the five past ten cab") == [{"10:05", "22:05"}]
    assert _times("five to ten people came") == []


def test_half_an_hour_ago_is_not_an_hour_ago() -> None:
    assert _times("she ate it half an hour ago", datetime(2025, 6, 2, 8, 50, tzinfo=UTC)) == []


@pytest.mark.parametrize(
    "text", ["the flat on the 4th floor", "her 30th birthday", "the 2nd time she asked", "5 Market Row, 9am"]
)
def test_an_ordinal_that_counts_something_or_a_street_is_no_day(text: str) -> None:
    assert _days(text) == []


def test_the_part_of_the_day_picks_the_reading_a_check_wants() -> None:
    assert mentions_clock("8 in the evening for you", time(20, 0), JUNE_1)
    assert not mentions_clock("8 in the evening for you", time(8, 0), JUNE_1)
    matcher = compile_matcher({"mentions_time": "day+1 09:30"})
    assert matcher.test("Half nine tomorrow?", JUNE_1)
    assert not matcher.test("Half nine tomorrow evening?", JUNE_1)


def test_the_date_library_is_imported_only_when_a_text_needs_it() -> None:
    probe = (
        "import sys\n"
        "from datetime import UTC, datetime, time\n"
        "import pare.cli, pare.scenarios.matchers\n"
        "from pare.scenarios.meaning import mentions_clock\n"
        "mentions_clock('Thursday at 6.15pm', datetime(2025, 6, 1, 9, 0, tzinfo=UTC).time(), "
        "datetime(2025, 6, 1, tzinfo=UTC))\n"
        "print('dateparser' in sys.modules)\n"
        "mentions_clock('in two days', time(9, 0), datetime(2025, 6, 1, tzinfo=UTC))\n"
        "print('dateparser' in sys.modules)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "True"]


def _library_with_reply(content: str, expect: str) -> Scenario:
    """The library's clash scenario (1:1 moved to Thursday 12 June at 09:30) with one variant: the oracle's
    work, and the message to Hannah worded as ``content``."""
    path = BENCH_DIR / "accepted_invite_clashes_with_one_to_one.yaml"
    data = yaml.safe_load(path.read_text(encoding="utf-8"))
    intervention = copy.deepcopy(data["oracle"]["interventions"][0])
    (message,) = [action for action in intervention["actions"] if action["tool"] == "messaging__send_message"]
    message["args"]["content"] = content
    variant: dict[str, Any] = {
        "id": "reworded",
        "expect": expect,
        "why": "Other wording.",
        "interventions": [intervention],
    }
    if expect == "fail":
        variant["fails"] = ["hannah_told"]
    data["variants"].append(variant)
    return parse_scenario(yaml.safe_dump(data, sort_keys=False, allow_unicode=True), source=str(path))


@pytest.mark.parametrize(
    "content",
    [
        "I'm going to the all-hands, so I've moved this week's 1:1 to half nine on the 12th. Invite updated!",
        "All-hands clashes - moved our 1:1 to the 12th, 9.30 in the morning. Invite updated!",
        "Update: our 1:1 is now Thursday, half past nine to ten. Calendar updated!",
    ],
)
def test_a_library_scenario_accepts_informal_wording_of_the_right_slot(content: str) -> None:
    verdict = check_scenario(_library_with_reply(content, "pass"))
    assert "variant:reworded" in {run.run for run in verdict.runs}
    assert verdict.ok, verdict.breaches()


@pytest.mark.parametrize(
    "content",
    [
        "Moved our 1:1 to half nine on the 13th. Invite updated!",  # Friday
        "Moved our 1:1 to the 12th, 9.30 in the evening. Invite updated!",
        "Not Thursday - Friday at half nine works better. Invite updated!",
    ],
)
def test_a_library_scenario_rejects_informal_wording_of_a_wrong_slot(content: str) -> None:
    verdict = check_scenario(_library_with_reply(content, "fail"))
    assert verdict.ok, verdict.breaches()


def _sent(content: str, at: datetime) -> LogEntry:
    args = {"user_id": "user-jo", "content": content}
    return LogEntry(0, 1, at, "assistant", "messaging", "send_message", args, "write", True)


def test_a_message_is_read_as_of_when_it_was_sent() -> None:
    pattern = ActionPattern.model_validate(
        {"tool": "messaging__send_message", "args": {"content": {"mentions_day": "day+2"}}}
    )
    compiled = CompiledPattern.of(pattern, JUNE_1)
    assert not compiled.matches(_sent("See you tomorrow!", JUNE_1))  # sent on the 1st: the 2nd
    assert compiled.matches(
        _sent("See you tomorrow!", JUNE_1 + timedelta(days=1))
    )  # sent on the 2nd: the 3rd
    late = compile_matcher({"mentions_day": "2025-07-02"})
    with written_at(JUNE_5):
        assert late.test("on the 2nd", JUNE_1)  # said on 5 June, "the 2nd" is 2 July
    assert not late.test("on the 2nd", JUNE_1)  # said on 1 June, it is 2 June


def test_last_weekday_and_yesterday_are_read_back_from_when_the_text_was_sent() -> None:
    thursday_10_july = datetime(2025, 7, 10, 9, 0, tzinfo=UTC)
    assert _days("The photo was taken last Saturday", thursday_10_july) == [{date(2025, 7, 5)}]
    assert _days("this past Saturday", thursday_10_july) == [{date(2025, 7, 5)}]
    assert _days("last Thursday", thursday_10_july) == [{date(2025, 7, 3)}]  # a week ago, not today
    assert _days("Saturday", thursday_10_july) == [{date(2025, 7, 12)}]  # a bare weekday still looks ahead
    assert _days("I sent it yesterday", thursday_10_july) == [{date(2025, 7, 9)}]
    assert _days("the day before yesterday", thursday_10_july) == [{date(2025, 7, 8)}]


def test_the_nth_of_a_named_month_relative_to_now_is_that_months() -> None:
    thursday_10_july = datetime(2025, 7, 10, 9, 0, tzinfo=UTC)
    assert _days("taken on the 5th of this month", thursday_10_july) == [{date(2025, 7, 5)}]
    assert _days("due the 3rd of next month", thursday_10_july) == [{date(2025, 8, 3)}]
    assert _days("paid on the 28th of last month", thursday_10_july) == [{date(2025, 6, 28)}]
    assert _days("the 5th", thursday_10_july) == [{date(2025, 8, 5)}]  # alone: the next 5th, as before


def test_a_number_before_a_street_name_is_an_address_not_a_time() -> None:
    assert _times("Open house at 14 Larch Road") == []
    assert _times("meet at 3 Heron Way") == []
    assert _times("at 3 on the way home") == [{"03:00", "15:00"}]  # a lower-case word is no street


def test_a_weekday_written_with_a_day_of_the_month_picks_the_month_where_they_agree() -> None:
    june_14 = datetime(2025, 6, 14, 9, 0, tzinfo=UTC)  # a Saturday
    assert _days("Thursday the 12th", june_14) == [{date(2025, 6, 12)}]  # not 12 July, a Saturday
    assert _days("Monday the 7th", june_14) == [{date(2025, 7, 7)}]
    assert _days("the 12th", june_14) == [{date(2025, 7, 12)}]  # alone: the next 12th, as before


def test_a_dotted_date_needs_its_year_so_a_time_stays_a_time() -> None:
    assert _days("taken on 5.7.2025", JUNE_1) == [{date(2025, 7, 5)}]
    assert _days("at 5.30") == [] and _times("at 5.30") == [{"05:30", "17:30"}]


def test_a_word_time_before_an_adverb_is_still_a_time() -> None:
    assert _times("I'll be home by half seven anyway.") == [{"07:30", "19:30"}]
    assert _times("five to ten people") == []  # a number that counts is still no time


def test_an_hour_and_its_minutes_in_words_are_a_time() -> None:
    assert _times("see you at ten thirty") == [{"10:30", "22:30"}]
    assert _times("six fifteen tonight") == [{"18:15"}]
    assert _times("ten thirty-minute slots") == []  # a count of slots, not a time


def test_a_date_with_its_month_stands_whatever_weekday_is_written_with_it() -> None:
    june_14 = datetime(2025, 6, 14, 9, 0, tzinfo=UTC)
    assert _days("Friday 16 June", june_14) == [
        {date(2025, 6, 16), date(2026, 6, 16)}
    ]  # not moved to a Friday
    assert _days("Sunday 15th", june_14) == [{date(2025, 6, 15)}]  # an ordinal after a weekday is a date
    assert _days("Freddie's 7th birthday", june_14) == []  # an ordinal alone is not


def test_a_word_time_before_what_it_times_is_still_a_time() -> None:
    assert _times("the ten to six slot") == [{"05:50", "17:50"}]
    assert _times("the half seven train") == [{"07:30", "19:30"}]
    assert _times("at one point") == []  # "one" counts a point here


def test_a_count_later_counts_from_another_moment_and_names_no_day() -> None:
    at = datetime(2025, 5, 1, 9, tzinfo=UTC)
    assert mentions("the course kicks off a week later", at) == ()
    assert [sorted(m.days) for m in mentions("in a week", at)] == [[date(2025, 5, 8)]]


@pytest.mark.parametrize(
    ("text", "day"),
    [
        ("Saturday the tenth works", date(2025, 5, 10)),
        ("on the tenth of May", date(2025, 5, 10)),
        ("see you on the twenty-first.", date(2025, 5, 21)),
        ("the first time we met", None),
        ("the first of all", None),
    ],
)
def test_an_ordinal_day_in_words_is_a_day(text: str, day: date | None) -> None:
    found = [sorted(m.days)[0] for m in mentions(text, datetime(2025, 5, 1, 9, tzinfo=UTC)) if m.days]
    assert found == ([day] if day else [])
