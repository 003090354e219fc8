"""The judge fallback reads the facts: a detail of a readable kind the facts do not give fails the text."""

from __future__ import annotations

import copy
from collections.abc import Sequence
from datetime import UTC, datetime
from typing import Any

import pytest

from pare.bench import run_episode
from pare.scenarios import OracleAssistant, OracleUser, evaluate
from pare.scenarios.fact_details import AllowedDetails, own_words
from pare.scenarios.loader import ScenarioError
from pare.scenarios.person_details import NameFinder, known_names, owner_names
from tests.scenarios.helpers import base, parse

START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)  # a Monday
"""When the facts are read and the texts sent."""


def _stray(facts: Sequence[str], text: str, more: Sequence[str] = ()) -> str | None:
    """What the facts rule rejects in ``text`` (the detail as the verdict names it), or ``None``."""
    found = AllowedDetails.of(facts, START, lambda: more).stray(text, START)
    return None if found is None else found[0].shown


DINNER = ["The dinner is on Thursday at 19:30."]


@pytest.mark.parametrize(
    "text", ["See you Thursday at 7:30pm", "half seven in the evening on Thursday", "19:30 it is", "at 7.30"]
)
def test_a_time_the_facts_give_is_allowed_in_any_form(text: str) -> None:
    assert _stray(DINNER, text) is None


@pytest.mark.parametrize(
    ("text", "shown"), [("Thursday at 8:30", "8:30"), ("half eight on Thursday", "8:30")]
)
def test_a_time_the_facts_do_not_give_fails(text: str, shown: str) -> None:
    assert _stray(DINNER, text) == shown


@pytest.mark.parametrize("text", ["half nine tonight", "9.30pm", "21:30", "at half past nine"])
def test_informal_forms_of_one_time_are_that_time(text: str) -> None:
    assert _stray(["The film starts at 21:30."], text) is None


def test_noon_and_a_time_on_the_quarter_are_read_too() -> None:
    assert _stray(["Lunch is at 12:00."], "see you at noon") is None
    assert _stray(["Lunch is at 12:00."], "see you at quarter past twelve") == "12:15"


def test_the_other_texts_are_read_only_when_a_detail_is_not_in_the_facts() -> None:
    asked: list[int] = []

    def more() -> Sequence[str]:
        asked.append(1)
        return ["I'll be home by 6."]

    allowed = AllowedDetails.of(DINNER, START, more)
    assert allowed.stray("Thursday at 19:30", START) is None and not asked
    assert allowed.stray("Thursday at 19:30; home by 6pm", START) is None and asked == [1]
    assert allowed.stray("home by 5pm", START) is not None and asked == [1]  # read once


def test_a_time_inside_a_range_of_the_facts_is_allowed_and_one_outside_is_not() -> None:
    facts = ["The van picks up between 9:00 and 10:00."]
    assert _stray(facts, "the van comes at quarter past nine") is None
    assert _stray(facts, "the van comes at 10:30") == "10:30"
    assert _stray(["Doors open 19:00-22:00."], "in from 7pm, out by 10pm") is None


def test_a_day_is_allowed_when_it_is_the_same_day() -> None:
    assert _stray(DINNER, "Dinner on 6 March at 19:30") is None  # 6 March 2025 is that Thursday
    assert _stray(DINNER, "Dinner on Friday at 19:30") == "Fri 7 Mar"
    assert _stray(["Her stay is 2 to 5 June 2025."], "from the 2nd of June") is None
    assert _stray(DINNER, "I'll book it today") is None  # the day the text is sent is no invented day


def test_money_is_read_by_currency_and_value() -> None:
    facts = ["The case costs £14.99."]
    assert _stray(facts, "ordered it for 14.99 pounds") is None
    assert _stray(facts, "ordered it for £14.99, ready at 2 p.m.") is None
    assert _stray(facts, "ordered it for £26.99") == "£26.99"
    assert _stray(["The fare is £15."], "it came to £15.00") is None
    assert _stray(["The fare is £15."], "it came to 1500p") is None
    assert _stray(["Half is $25.70."], "your half is €25,70") is None  # a sign the scenario never uses
    assert _stray(["Half is $25.70."], "your half is $25.07") == "$25.07"


def test_a_rough_time_may_be_five_minutes_off() -> None:
    facts = ["The cab arrives at 09:46."]
    assert _stray(facts, "it gets there around quarter to ten") is None
    assert _stray(facts, "it gets there at quarter to ten") == "9:45"
    assert _stray(facts, "it gets there around ten") == "10:00"


def test_a_figure_the_facts_give_without_a_currency_is_that_amount() -> None:
    facts = ["The offer is a salary of 41,500 a year.", "The invoice is 86.40."]
    assert _stray(facts, "a salary of £41,500") is None
    assert _stray(facts, "pay the $86.40 invoice") is None
    assert _stray(facts, "a salary of £42,500") == "£42,500"
    assert _stray(["Harbour's quote has an excess 350 and renews on 28 April."], "excess £350") is None


def test_a_share_is_read_where_the_facts_give_one_and_may_be_worked_out_from_their_amounts() -> None:
    facts = ["The HALDEN12 code takes 12% off the $67.20 order.", "Rent goes from $2,050 to $2,296."]
    assert _stray(facts, "with the twelve per cent code") is None
    assert _stray(facts, "with the 15% HALDEN12 discount") == "15%"
    assert _stray(facts, "the rent rises by about 12%") is None  # 246 of 2,050
    assert _stray(["The code takes £5 off."], "a 15% discount") is None  # no share given: not read


def test_a_trunk_zero_in_brackets_is_the_same_number() -> None:
    facts = ["Her new mobile is +31 6 4182 7390."]
    assert _stray(facts, "Call her on +31 (0)6 41 82 73 90") is None
    assert _stray(facts, "Call her on +31 (0)6 41 82 73 99") == "+31 (0)6 41 82 73 99"


def test_phone_numbers_are_their_digits() -> None:
    facts = ["Call the clinic on 07700 900742."]
    assert _stray(facts, "ring them on 0770-090-0742") is None
    assert _stray(facts, "ring them on +44 7700 900742") is None
    assert _stray(facts, "ring them on 07700 900743") == "07700 900743"


def test_links_and_addresses_must_be_the_facts_own() -> None:
    facts = ["The meeting link is https://zoom.us/j/8812?pwd=ab; questions to ana@firm.example."]
    assert _stray(facts, "Join at zoom: https://zoom.us/j/8812?pwd=ab.") is None
    assert _stray(facts, "Join at https://zoom.us/j/5555") == "https://zoom.us/j/5555"
    assert _stray(facts, "Write to ANA@firm.example") is None
    assert _stray(facts, "Write to ana@other.example") == "ana@other.example"


def test_only_kinds_the_facts_give_are_checked_and_other_texts_widen_them() -> None:
    assert _stray(["The dinner is at Luigi's."], "Luigi's at 8:30, £20 a head") is None
    assert _stray(DINNER, "Thursday 19:30, home by 23:00", more=["I'll be home by 11pm."]) is None


def test_a_forward_and_quoted_lines_carry_the_originals_details() -> None:
    text = "Passing this on.\n\n---------- Forwarded message ----------\nDinner Friday at 8:30"
    assert own_words(text) == "Passing this on.\n\n"
    assert _stray(DINNER, text) is None
    assert _stray(DINNER, "Thursday at 19:30 then.\n> Is it Friday at 8:30?") is None


def _probe(scenario_data: dict[str, Any], content: str) -> Any:
    """An episode of ``scenario_data`` whose assistant replies ``content`` instead of the oracle's text."""
    probe = copy.deepcopy(scenario_data)
    probe["oracle"]["interventions"][0]["actions"][0]["args"]["content"] = content
    scenario = parse(probe)
    return run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))


def _lunch() -> dict[str, Any]:
    """The tiny scenario whose one goal is a judge check with facts: lunch on Thursday at 12:30."""
    judged: dict[str, Any] = {
        "criterion": "says yes to lunch on Thursday at 12:30",
        "action": {"tool": "email__reply_to_email"},
        "fallback": {"contains": "thursday"},
        "facts": ["Lunch is on Thursday at 12:30."],
    }
    data = base()
    data["goals"] = [{"id": "g", "description": "goal", "checks": [{"judge": judged}]}]
    data["oracle"]["interventions"][0]["actions"][0]["args"]["content"] = "Thursday at 12:30 works!"
    return data


def test_a_probe_with_a_wrong_time_passes_without_the_facts_rule_and_fails_with_it() -> None:
    data = _lunch()
    result = _probe(data, "Thursday at 1:30 works!")
    log, state = result.env.log.entries, result.env.snapshot()

    opted_out = copy.deepcopy(data)
    opted_out["goals"][0]["checks"][0]["judge"]["other_details"] = "the reply may name any time"
    assert evaluate(parse(opted_out), log, state).success  # as before: the fallback alone decides

    outcome = evaluate(parse(data), log, state)
    (failure,) = outcome.failures()
    assert failure.detail == (
        'no judge model; "Thursday at 1:30 works!" states 1:30, which the facts do not give'
    )
    right = _probe(data, "Yes, Thursday 12.30 is great")
    assert evaluate(parse(data), right.env.log.entries, right.env.snapshot()).success


def test_the_opt_out_needs_a_reason() -> None:
    data = base()
    judged = {"criterion": "c", "action": {"tool": "email__reply_to_email"}, "fallback": {"contains": "x"}}
    data["goals"][0]["checks"].append({"judge": {**judged, "facts": ["A fact."], "other_details": ""}})
    with pytest.raises(ScenarioError, match="other_details: String should have at least 1 character"):
        parse(data)


def test_a_held_out_probe_teaches_the_rule_nothing() -> None:
    data = _lunch()
    probe = copy.deepcopy(data["oracle"]["interventions"])
    probe[0]["actions"][0]["args"]["content"] = "Thursday at 1:30 works!"
    result = _probe(data, "Thursday at 1:30 works!")
    log, state = result.env.log.entries, result.env.snapshot()

    # a passing variant is a right solution by definition: the details it states are allowed ...
    data["variants"] = [{"id": "later", "expect": "pass", "why": "w", "interventions": probe}]
    assert evaluate(parse(data), log, state).success
    # ... a reviewer's held-out probe is judged as a real assistant's text would be
    data["variants"][0]["held_out"] = True
    held_out = parse(data)
    assert held_out.right_solutions() == [None]
    assert not evaluate(held_out, log, state).success


def _why(facts: Sequence[str], text: str, more: Sequence[str] = ()) -> str | None:
    """Why the facts rule rejects ``text`` (the reason after the detail), or ``None``."""
    found = AllowedDetails.of(facts, START, lambda: more).stray(text, START)
    return None if found is None else found.why


WEDDING = ["The ceremony is at the chapel at 2pm.", "The reception starts at 3pm in the garden."]
COFFEE = ["The house blend costs £28 a kilo.", "The decaf costs £34 a kilo."]


def test_a_true_value_said_of_the_wrong_thing_fails_and_names_what_it_was_bound_to() -> None:
    assert _stray(WEDDING, "See you at the chapel at 3pm") == "15:00"
    assert _why(WEDDING, "See you at the chapel at 3pm") == (
        "which the facts give for another thing: for 'chapel' they give 14:00"
    )
    assert _stray(COFFEE, "Ordered 1 kg of the house blend for £34") == "£34"
    assert _stray(COFFEE, "Ordered 1 kg of the decaf for £34") is None
    assert _stray(WEDDING, "The garden reception is at 3pm") is None
    assert _stray(["The van comes on Friday.", "Bins go out on Tuesday."], "the van comes Tuesday") == (
        "Tue 4 Mar"
    )


def test_a_value_bound_to_nothing_or_to_something_it_is_given_for_is_left_alone() -> None:
    assert _stray(WEDDING, "See you at 3pm") is None  # no word of the clause binds it
    assert _stray(WEDDING, "Lovely day, 3pm it is") is None
    # a word the checked clause shares with a sentence giving this value clears it, however many others
    assert _stray([*WEDDING, "Photos at the chapel door at 3pm."], "See you at the chapel at 3pm") is None
    # the solutions' texts give what a value is for, too
    assert _stray(WEDDING, "See you at the chapel at 3pm", more=["Chapel steps, 3pm: photos."]) is None


def test_only_one_value_of_a_kind_binds_and_an_allowed_value_only_in_its_own_clause() -> None:
    # a checked sentence with two values of a kind binds neither; the sentence binds, not only the clause
    assert _stray(WEDDING, "Chapel at 2pm and 3pm") is None
    assert _stray(WEDDING, "The chapel, as you asked: 3pm") == "15:00"
    # an allowed clause listing several values binds none of them to its words
    facts = ["Harbour Dental offered Wednesday 08:30 or Friday 16:30.", "Board meeting on Wednesday."]
    assert _stray(facts, "I'd like the Harbour Dental slot on Friday at 16:30") is None
    # a value is bound to the words of its clause, not of the whole sentence
    facts = ["The ceremony is at the chapel, and the reception at 3pm.", "The chapel opens at 1pm."]
    assert _stray(facts, "the chapel at 3pm") is None


def test_rough_amounts_spoken_cents_and_bare_totals_are_money() -> None:
    assert _stray(["The quote is $58.40."], "it comes to about $59") is None  # within 2 %
    assert _stray(["The quote is $58.40."], "it comes to about $62") == "$62"
    assert _stray(["The quote is $58.40."], "it comes to $59") == "$59"
    assert _stray(["Half is $25.70."], "your half is 25 dollars and 70 cents") is None
    assert _stray(["Half is $25.70."], "your half is 25 dollars and 75 cents") == "25 dollars and 75 cents"
    assert _stray(["The order is £87.00."], "Total: 87.00") is None
    assert _stray(["The order is £87.00."], "Total: 88.00") == "88.00"
    # a bare figure is the given amount of its value for the binding too
    assert _stray(["The full price is $13.50.", "With MULTI3 the total is $11.20."], "Order total 13.50") == (
        "13.50"
    )


SEED = {
    "contacts": {
        "contacts": [
            {"contact_id": "c-me", "first_name": "Olivia", "last_name": "Grant", "is_user": True},
            {"contact_id": "c-ella", "first_name": "Ella", "last_name": "Moss"},
            {"contact_id": "c-maya", "first_name": "Maya", "last_name": "Reid"},
            {"contact_id": "c-sophie", "first_name": "Sophie", "last_name": "Hart"},
            {"contact_id": "c-may", "first_name": "May", "last_name": "Lund"},
            {"contact_id": "c-pub", "first_name": "The", "last_name": "Anchor"},
            {"contact_id": "c-gp", "first_name": "Dr", "last_name": "Okafor"},
        ]
    }
}


def _stray_person(facts: Sequence[str], text: str) -> str | None:
    allowed = AllowedDetails.of(facts, START, tuple)
    allowed.know_people(NameFinder.of(known_names(SEED)), owner_names(SEED))
    found = allowed.stray(text, START)
    return None if found is None else found.detail.shown


def test_a_person_of_the_world_the_facts_do_not_name_is_a_wrong_detail() -> None:
    facts = ["Olivia's photo is of Ella and Maya at the beach."]
    assert _stray_person(facts, "Lovely one of Ella and Sophie!") == "Sophie"
    assert _stray_person(facts, "Ella and Maya at the beach. Love, Olivia") is None
    assert _stray_person(facts, "ELLA and Maya, May 2025") is None  # capitals are a name; May is a month
    assert _stray_person(facts, "Ella, Maya and Tilly") is None  # Tilly is nobody of this world
    assert _stray_person(facts, "Ella and Maya, then the Anchor") is None  # a place kept as a contact
    assert _stray_person(facts, "Ella and Maya, Mrs Okafor said") == "Okafor"  # a title is no name
    # facts that name nobody leave people alone
    assert _stray_person(["The photo is from the beach."], "Lovely one of Sophie!") is None


@pytest.mark.parametrize(
    ("facts", "text", "stray"),
    [
        (["Sofia replies within 48 hours."], "She'll reply in two days", None),
        (["The course runs for 4 weeks."], "It runs for a month", None),
        (["The lease is for 12 months."], "It's a one-year lease", None),
        (["The film is 90 minutes long."], "It's 2 hours long", "2 hours"),
        (["Sofia replies within 48 hours."], "She'll reply in three days", "three days"),
    ],
)
def test_a_length_of_time_may_be_said_in_another_unit(facts: list[str], text: str, stray: str | None) -> None:
    assert _stray(facts, text) == stray


@pytest.mark.parametrize(
    ("text", "stray"),
    [
        ("City tax is 3.30 EUR a night", None),  # 9.90 for three nights
        ("that's $27 each", None),  # the $54 bill split in two
        ("your half is $27", None),
        ("that's $25 each", "$25"),  # no even split of a given amount
        ("the tax is 3.30 EUR", "3.30 EUR"),  # a share only where the words say so
        ("balance now $0.00", None),  # nothing left states no amount
    ],
)
def test_an_even_share_of_a_given_amount_is_given(text: str, stray: str | None) -> None:
    assert _stray(["City tax: 9.90 EUR for the 3 nights.", "Dinner came to $54."], text) == stray


def test_a_time_counted_from_now_is_rough() -> None:
    sent = START.replace(hour=10, minute=32)
    allowed = AllowedDetails.of(["The call is at 11:30."], START, tuple)
    assert allowed.stray("I'll phone Elm Park in an hour", sent) is None
    assert allowed.stray("I'll phone Elm Park in two hours", sent) is not None


def test_a_phone_number_is_bound_to_whose_it_is() -> None:
    facts = ["Marek's mobile is 07700 900111.", "Lina's mobile is 07700 900222."]
    assert _stray(facts, "Lina is on +44 7700 900111") == "+44 7700 900111"  # Marek's, said as Lina's
    assert _stray(facts, "Lina is on +44 7700 900222") is None  # hers, with the country code
    assert _stray(facts, "Lina 07700 900222, Marek 07700 900111") is None
