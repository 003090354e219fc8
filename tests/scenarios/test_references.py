"""Oracle arguments that name a result produced while the scenario runs: ``${id.field}`` and ``${id}``."""

from __future__ import annotations

from typing import Any

import pytest

from pare.bench import EpisodeSettings, run_episode
from pare.bench.selftest import check_scenario
from pare.env import EnvConfig
from pare.scenarios import OracleAssistant, OracleUser
from pare.scenarios.loader import ScenarioError
from pare.scenarios.oracle import OracleRunError
from tests.scenarios.helpers import base, parse


def _creates_then_edits(reference: str) -> dict[str, Any]:
    data = base()
    data["oracle"]["interventions"][0]["actions"] = [
        {
            "id": "made",
            "tool": "calendar__add_calendar_event",
            "args": {"title": "Call Ann", "start_datetime": "day+3 10:00", "end_datetime": "day+3 10:30"},
        },
        {
            "tool": "calendar__edit_calendar_event",
            "args": {"event_id": reference, "updates": {"location": "Zoom"}},
        },
        {"tool": "email__reply_to_email", "args": {"email_id": "e_ann", "content": "Thursday works!"}},
    ]
    return data


def test_the_id_a_write_made_is_named_by_its_field() -> None:
    scenario = parse(_creates_then_edits("${made.id}"))  # add_calendar_event returns {done, id}
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    assert result.success
    events = result.env.snapshot()["calendar"]["events"]
    assert [event["location"] for event in events.values() if event["title"] == "Call Ann"] == ["Zoom"]


def test_a_field_the_result_lacks_is_a_clear_error() -> None:
    scenario = parse(_creates_then_edits("${made.event_id}"))
    expected = r"has no 'event_id' \(it is \{'done': .*'id': 'event-1'\}\)"
    with pytest.raises(OracleRunError, match=expected):
        run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))


def test_a_whole_write_result_where_an_id_is_wanted_is_refused_at_load() -> None:
    # add_calendar_event returns {done, id}: passed whole, the edit would fail on an object for an id
    with pytest.raises(ScenarioError, match=r"event_id: '\$\{made\}' passes the whole result") as raised:
        parse(_creates_then_edits("${made}"))
    assert "'${made.id}'" in str(raised.value)


def _unchecked(data: dict[str, Any]) -> Any:
    """The scenario as its model reads it, without the loader's cross-checks (as a reference the loader
    cannot see through reaches the oracle)."""
    scenario = parse(base())
    return scenario.model_copy(update={"oracle": type(scenario.oracle).model_validate(data["oracle"])})


def test_a_whole_object_result_the_loader_let_through_breaches_the_gate_by_name() -> None:
    scenario = _unchecked(_creates_then_edits("${made}"))
    with pytest.raises(OracleRunError, match=r"\$\{made\} passes the whole result of 'made'.*\$\{made\.id\}"):
        run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    verdict = check_scenario(scenario, runs=("oracle",), variants=False)
    assert not verdict.ok
    assert any("${made.id}" in problem for problem in verdict.run("oracle").problems)


def test_the_oracle_tries_a_transiently_failed_action_again() -> None:
    """Under injected tool failures a referenced result still arrives: the oracle retries the call."""
    scenario = parse(_creates_then_edits("${made.id}"))
    retried = 0
    for seed in range(8):
        settings = EpisodeSettings(env=EnvConfig(seed=seed, tool_failure_probability=0.4))
        result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario), settings)
        injected = [entry for entry in result.env.log.entries if entry.injected_failure]
        retried += any(entry.tool == "add_calendar_event" for entry in injected)
        made = [entry for entry in result.env.log.entries if entry.tool == "add_calendar_event" and entry.ok]
        assert len(made) == 1  # retried until it worked, never made twice
    assert retried  # the seeds above do fail the referenced call at least once


def _writes_then_attaches(reference: str) -> dict[str, Any]:
    data = base()
    data["oracle"]["interventions"][0]["actions"] = [
        {
            "id": "saved",
            "tool": "files__write_file",
            "args": {"path": "/Documents/plan.txt", "content": "Thursday"},
        },
        {
            "tool": "email__reply_to_email",
            "args": {"email_id": "e_ann", "content": "Thursday works!", "attachments": [reference]},
        },
    ]
    return data


def test_a_reference_inside_a_list_names_the_file_an_earlier_action_wrote() -> None:
    scenario = parse(_writes_then_attaches("${saved.id}"))
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))
    assert result.success
    sent = [email for email in result.env.snapshot()["email"]["emails"].values() if email["folder"] == "SENT"]
    assert [email["attachments"] for email in sent] == [["/Documents/plan.txt"]]


def test_a_reference_inside_a_list_to_no_earlier_action_is_refused_at_load() -> None:
    refused = r"attachments: '\$\{saveed\.\.\.\}' names no earlier oracle action"
    with pytest.raises(ScenarioError, match=refused):
        parse(_writes_then_attaches("${saveed.id}"))


def test_a_user_step_names_what_it_made_for_the_users_later_steps() -> None:
    from pare.agents.policy import SilentAssistant
    from pare.scenarios.library import get_scenario

    scenario = get_scenario("childminder_new_business_account_confirm_then_pay")
    solution = scenario.by_hand()
    settings = EpisodeSettings(max_turns=EpisodeSettings().max_turns + len(solution.user))
    result = run_episode(scenario, OracleUser(scenario, solution), SilentAssistant(), settings)
    banking = result.env.snapshot()["banking"]
    (made,) = [payee for payee in banking["payees"].values() if payee["name"] == "Little Oaks Childminding"]
    paid = [t for t in banking["transactions"].values() if t.get("reference") == "LO-1025"]
    assert [t["payee_id"] for t in paid] == [made["payee_id"]]  # the pay screen got ${payee.id}
    assert result.outcome.user_did_work and not result.success


def _user_steps(reference: str, *, twice: bool = False) -> dict[str, Any]:
    data = base()
    data["oracle"]["user"] = [
        {"id": "found", "tool": "open_app", "args": {"app_name": "email"}},
        {"id": "found" if twice else "again", "tool": "search_emails", "args": {"query": reference}},
        *data["oracle"]["user"],
    ]
    return data


def test_a_user_step_reference_to_no_earlier_step_is_refused_at_load() -> None:
    with pytest.raises(ScenarioError, match=r"'\$\{fuond\.\.\.\}' names no earlier oracle action"):
        parse(_user_steps("${fuond.app}"))
    with pytest.raises(ScenarioError, match="share the id 'found'"):
        parse(_user_steps("thursday", twice=True))
    parse(_user_steps("thursday"))  # ids of its own, named once: fine
