"""Facts a goal looks for must be where the user can look: the gate warns about those no screen shows."""

from __future__ import annotations

import io
from typing import Any

from rich.console import Console

from pare.bench.selftest import check_scenario
from pare.cli.review_cmd import gate_table
from pare.scenarios.user_reach import reachable_texts, unseen_facts
from tests.scenarios.helpers import REPLY, parse, sound

CODE_IN_A_DOCUMENT = {"files": {"/Documents/keybox.txt": {"content": "Key box by the door, code 4471."}}}


def _code_wanted(data: dict[str, Any]) -> dict[str, Any]:
    """``sound()`` whose goal also wants the key box code 4471 in the reply, as the oracle sends it."""
    answer = {**REPLY, "args": {**REPLY["args"], "content": "Yes, Thursday works! The key box code is 4471."}}
    data["oracle"]["interventions"][0]["actions"] = [answer]
    data["goals"][0]["checks"][0]["state"]["where"]["content"] = {
        "mentions_day": "day+3",
        "contains": "4471",
    }
    for variant in data["variants"]:
        if variant["expect"] == "pass":
            variant["interventions"][0]["actions"][0]["args"]["content"] = "Thu is fine by me. Code 4471."
    return data


def _with_seed(data: dict[str, Any], app: str, seed: dict[str, Any]) -> dict[str, Any]:
    data["apps"] = [*data["apps"], app] if app != "files" else data["apps"]
    data["seed"][app] = seed
    return data


def test_a_fact_only_in_a_document_is_warned_about_and_the_gate_still_passes() -> None:
    scenario = parse(_with_seed(_code_wanted(sound()), "files", CODE_IN_A_DOCUMENT))
    (fact,) = unseen_facts(scenario)
    assert (fact.goal, fact.check, fact.field) == ("replied", 0, "content")
    assert "4471" in fact.matcher
    verdict = check_scenario(scenario)
    assert verdict.ok
    assert any("goal 'replied' check 1 looks for" in line and "4471" in line for line in verdict.warnings)


def test_the_review_shows_the_warning_beside_the_gates_runs() -> None:
    scenario = parse(_with_seed(_code_wanted(sound()), "files", CODE_IN_A_DOCUMENT))
    console = Console(width=400, record=True, file=io.StringIO())
    console.print(gate_table(scenario))
    (line,) = [line for line in console.export_text().splitlines() if "(warning)" in line]
    assert "4471" in line


def test_the_same_fact_in_a_message_the_user_can_open_is_not() -> None:
    data = _with_seed(_code_wanted(sound()), "files", CODE_IN_A_DOCUMENT)
    data["seed"]["email"]["emails"].append(
        {
            "email_id": "e2",
            "sender": "host@x.example",
            "subject": "Key box",
            "content": "The code is 4471.",
            "timestamp": "-2h",
        }
    )
    assert list(unseen_facts(parse(data))) == []


def test_a_listings_address_and_a_rides_fare_are_on_the_users_screens() -> None:
    data = _code_wanted(sound())
    data["goals"][0]["checks"][0]["state"]["where"]["content"] = {"contains_any": ["keeper*"]}
    data = _with_seed(
        data,
        "apartment",
        {
            "apartments": [
                {
                    "apartment_id": "apt-1",
                    "name": "Canal Basin 1BR",
                    "location": "Canal Basin",
                    "address": "4 Lock Keeper's Walk",
                    "price": 1450,
                    "bedrooms": 1,
                    "bathrooms": 1,
                }
            ],
            "saved": ["apt-1"],
        },
    )
    assert list(unseen_facts(parse(data))) == []
    data["seed"]["apartment"]["apartments"][0]["address"] = "19 Towpath Lane"
    (fact,) = unseen_facts(parse(data))
    assert "keeper*" in fact.matcher
    data["goals"][0]["checks"][0]["state"]["where"]["content"] = {"contains": "23.85"}
    data = _with_seed(
        data,
        "cab",
        {
            "rides": [
                {
                    "ride_id": "r1",
                    "start_location": "Home",
                    "end_location": "Fenwick Logistics",
                    "service_type": "Default",
                    "pickup_time": "day-2 10:12",
                    "booked_at": "day-2 10:00",
                    "distance_km": 9.0,
                    "duration_minutes": 20,
                    "price": 23.85,
                    "status": "completed",
                }
            ]
        },
    )
    assert list(unseen_facts(parse(data))) == []


def test_what_no_screen_lists_does_not_count() -> None:
    data = _code_wanted(sound())
    data["goals"][0]["checks"][0]["state"]["where"]["content"] = {"contains": "KEEPER"}
    data = _with_seed(
        data,
        "shopping",
        {"discount_codes": {"KEEPER": {"code": "KEEPER", "percent_off": 10}}},
    )
    (fact,) = unseen_facts(parse(data))
    assert "keeper" in fact.matcher.casefold()
    assert all("KEEPER" not in text for text in reachable_texts(parse(data)))


def test_the_phones_own_words_and_alternatives_with_a_visible_fact_are_not_flagged() -> None:
    data = _code_wanted(sound())
    where = data["goals"][0]["checks"][0]["state"]["where"]
    del where["content"]
    where["any_of"] = [{"content": {"contains": "4471"}}, {"subject": {"contains_any": ["thursday", "thu"]}}]
    assert list(unseen_facts(parse(data))) == []  # Ann's email says Thursday: one alternative is in view
    where["any_of"] = [{"content": {"contains_any": ["reply", "replied"]}}]
    assert list(unseen_facts(parse(data))) == []  # the email app's own screens say "reply"


def test_only_what_the_assistant_must_write_is_read() -> None:
    data = _code_wanted(sound())
    data["goals"][0]["checks"][0]["state"]["where"]["content"] = {"not": {"contains": "4471"}}
    data["goals"][0]["checks"][1]["state"]["where"]["content"] = {"contains": "9999"}  # a count of 0
    assert list(unseen_facts(parse(data))) == []


def test_what_the_user_typed_in_their_own_steps_is_theirs_to_know() -> None:
    data = _code_wanted(sound())
    assert [fact.field for fact in unseen_facts(parse(data))] == ["content"]
    # the user typed the code themselves (a search for it) before the assistant used it: nothing on trust
    data["oracle"]["user"].insert(1, {"tool": "search_emails", "args": {"query": "code 4471"}})
    assert list(unseen_facts(parse(data))) == []
