"""Broken scenario files: each kind of mistake gets a message naming the file, the line and the place."""

from __future__ import annotations

import copy
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest

from pare.scenarios import ScenarioError, load_scenario, parse_scenario
from tests.scenarios.helpers import base, fair, parse, to_yaml

Edit = Callable[[dict[str, Any]], None]


def problems_of(data: dict[str, Any]) -> list[str]:
    with pytest.raises(ScenarioError) as caught:
        parse(data)
    return [str(problem) for problem in caught.value.problems]


def test_the_base_scenario_is_valid() -> None:
    assert parse(base()).id == "tiny_reply"


def _set(path: str, value: Any) -> Edit:
    def edit(data: dict[str, Any]) -> None:
        *parents, last = path.split("/")
        target: Any = data
        for part in parents:
            target = target[int(part)] if part.isdigit() else target[part]
        if value is _DELETE:
            del target[last]
        elif isinstance(target, list) and int(last) == len(target):
            target.append(value)
        elif isinstance(target, list):
            target[int(last)] = value
        else:
            target[last] = value

    return edit


_DELETE = object()


CASES: list[tuple[str, Edit, str, str]] = [
    ("unknown field", _set("colour", "red"), "colour", "unknown field 'colour'. Fields here: format"),
    ("misspelt field", _set("events/0/tol", "x"), "events[0].tol", "did you mean 'tool'"),
    (
        "field of the wrong level",
        _set("goals/0/checks/0/count", 1),
        "goals[0].checks[0].count",
        "Fields here: action",
    ),
    ("missing field", _set("story", _DELETE), "story", "required field missing"),
    ("bad tag", _set("tags", ["goal_infrence"]), "tags[0]", "goal_inference"),
    ("bad id", _set("id", "Tiny Reply"), "id", "pattern"),
    ("unknown app", _set("apps", ["email", "calender"]), "apps", "did you mean 'calendar'"),
    ("core app listed", _set("apps", ["email", "calendar", "agent_ui"]), "apps", "part of every phone"),
    (
        "unknown event tool",
        _set("events/0/tool", "email__recieve_email"),
        "events[0].tool",
        "did you mean 'email__receive_email'",
    ),
    (
        "tool of an absent app",
        _set("events/0/tool", "shopping__add_product"),
        "events[0].tool",
        "not in this scenario's apps",
    ),
    ("unqualified tool", _set("events/0/tool", "receive_email"), "events[0].tool", "write app__tool"),
    (
        "argument of wrong type",
        _set("events/0/args/subject", ["a", "list"]),
        "events[0].args",
        "argument 'subject'",
    ),
    (
        "unexpected argument",
        _set("events/0/args/colour", "red"),
        "events[0].args",
        "unexpected argument 'colour'",
    ),
    (
        "missing argument",
        _set("events/0/args/sender", _DELETE),
        "events[0].args",
        "missing required argument 'sender'",
    ),
    ("bad time", _set("events/0/at", "soonish"), "events[0].at", "not a time"),
    ("time before start", _set("events/0/at", "-5m"), "events[0].at", "before the scenario starts"),
    (
        "two triggers",
        _set("events/0/after", "ann_asks"),
        "events[0]",
        "exactly one of 'at', 'after' or 'when'",
    ),
    (
        "unknown id in oracle",
        _set("oracle/interventions/0/actions/0/args/email_id", "e_anne"),
        "oracle.interventions[0].actions[0].args.email_id",
        "not an id in the seed data",
    ),
    (
        "unknown id in user step",
        _set("oracle/user/1/args/email_id", "e9"),
        "oracle.user[1].args.email_id",
        "not an id",
    ),
    (
        "unknown user action",
        _set("oracle/user/1/tool", "open_mail"),
        "oracle.user[1].tool",
        "did you mean 'open_email'",
    ),
    (
        "user answers by itself",
        _set("oracle/user/1/tool", "accept_proposal"),
        "oracle.user[1].tool",
        "answers proposals by itself",
    ),
    (
        "oracle calls env tool",
        _set("oracle/interventions/0/actions/0/tool", "email__receive_email"),
        "oracle.interventions[0].actions[0].tool",
        "not a tool the assistant may call",
    ),
    (
        "condition on unknown event",
        _set("oracle/user/0/when/event", "ann_ask"),
        "oracle.user[0].when.event",
        "did you mean 'ann_asks'",
    ),
    (
        "unknown check tool",
        _set("goals/0/checks/0/action/tool", "email__reply"),
        "goals[0].checks[0].action.tool",
        "unknown tool",
    ),
    (
        "check argument the tool lacks",
        _set("goals/0/checks/0/action/args/body", "x"),
        "goals[0].checks[0].action.args.body",
        "has no argument 'body'",
    ),
    (
        "user tool under the assistant's name",
        _set("goals/0/checks/0/action", {"actor": "user", "tool": "email__reply_to_email"}),
        "goals[0].checks[0].action.tool",
        "screen actions",
    ),
    (
        "bad matcher",
        _set("goals/0/checks/0/action/args/content", {"contains": "x", "colour": "y"}),
        "goals[0].checks[0].action.args",
        "mixes operators",
    ),
    (
        "two forms in one check",
        _set("goals/0/checks/0/no_action", {"tool": "email__delete_email"}),
        "goals[0].checks[0]",
        "exactly one of action",
    ),
    (
        "state path of unknown field",
        _set("goals/0/checks/0", {"state": {"path": "calendar.event"}}),
        "goals[0].checks[0].state.path",
        "did you mean 'events'",
    ),
    (
        "state path of absent app",
        _set("goals/0/checks/0", {"state": {"path": "shopping.cart"}}),
        "goals[0].checks[0].state.path",
        "not an app of this scenario",
    ),
    (
        "where field items lack",
        _set("goals/0/checks/0", {"state": {"path": "calendar.events", "where": {"titel": "x"}}}),
        "goals[0].checks[0].state.where.titel",
        "did you mean 'title'",
    ),
    (
        "judge field not an argument",
        _set(
            "goals/0/checks/0",
            {
                "judge": {
                    "criterion": "polite",
                    "action": {"tool": "email__reply_to_email"},
                    "field": "body",
                    "fallback": {"contains": "x"},
                }
            },
        ),
        "goals[0].checks[0].judge.field",
        "not an argument",
    ),
    (
        "seed data error",
        _set("seed/email/emails/0/timestamp", "yesterday-ish"),
        "seed.email.emails[0].timestamp",
        "datetime",
    ),
    ("seed for an absent app", _set("seed/notes", {"notes": []}), "seed.notes", "not in apps"),
    (
        "reference to unknown step",
        _set("oracle/interventions/0/actions/0/args/email_id", "${nothing.email_id}"),
        "oracle.interventions[0].actions[0].args.email_id",
        "names no earlier oracle action",
    ),
    (
        "reference outside the oracle",
        _set("events/0/args/subject", "${ann_asks.email_id}"),
        "events[0].args.subject",
        "only be used in oracle steps",
    ),
    ("empty interventions", _set("oracle/interventions", []), "oracle.interventions", "kind: no_proposal"),
    ("no_proposal with a proposal", _set("kind", "no_proposal"), "oracle.interventions", "makes no proposal"),
    ("no_proposal without the check", _set("kind", "no_proposal"), "goals", "did not propose"),
    # silent authoring mistakes: each would otherwise quietly match nothing or prove nothing
    (
        "operator misspelt inside where",
        _set(
            "goals/0/checks/1",
            {"state": {"path": "email.emails", "where": {"content": {"contain_any": ["yes"]}}}},
        ),
        "goals[0].checks[1].state.where.content.contain_any",
        "'contain_any' is not an operator. Did you mean 'contains_any'",
    ),
    (
        "operator misspelt in arguments",
        _set("goals/0/checks/0/action/args/content", {"contain": "thursday"}),
        "goals[0].checks[0].action.args.content.contain",
        "is not an operator",
    ),
    (
        "text operator on a number",
        _set(
            "goals/0/checks/1",
            {"action": {"tool": "email__list_emails", "args": {"limit": {"contains": "1"}}}},
        ),
        "goals[0].checks[1].action.args.limit.contains",
        "'contains' cannot apply here: this field holds a number",
    ),
    (
        "number operator on a list",
        _set("goals/0/checks/1", {"state": {"path": "email.emails", "where": {"recipients": {"min": 1}}}}),
        "goals[0].checks[1].state.where.recipients.min",
        "holds a list",
    ),
    (
        "goal with no positive check",
        _set(
            "goals/1",
            {"id": "quiet", "description": "d", "checks": [{"no_action": {"tool": "email__delete_email"}}]},
        ),
        "goals[1].checks",
        "goal 'quiet' has no positive check",
    ),
    (
        "no goal needs the assistant",
        _set("goals/0/checks/0/action/actor", "any"),
        "goals",
        "no goal needs the assistant's own work",
    ),
    (
        "forbidding count is not positive",
        _set("goals/0/checks/0/action/count", 0),
        "goals[0].checks",
        "no positive check",
    ),
    (
        "if_args without when",
        _set("events/0/if_args", {"content": "x"}),
        "events[0]",
        "'if_args' goes with 'when'",
    ),
    (
        "otherwise without if_args",
        _set("events/0/otherwise", {"tool": "email__receive_email", "args": {}}),
        "events[0]",
        "'otherwise' goes with 'if_args'",
    ),
    (
        "variant that changes nothing",
        _set("variants", [{"id": "same", "expect": "pass", "why": "w"}]),
        "variants[0]",
        "gives 'interventions' or 'user'",
    ),
    (
        "variant fails an unknown goal",
        _set("variants", [{"id": "v", "expect": "fail", "why": "w", "user": [], "fails": ["replid"]}]),
        "variants[0].fails[0]",
        "unknown goal 'replid'. Did you mean 'replied'?",
    ),
    (
        "passing variant names goals to fail",
        _set("variants", [{"id": "v", "expect": "pass", "why": "w", "user": [], "fails": ["replied"]}]),
        "variants[0]",
        "this variant must pass",
    ),
    (
        "two variants share an id",
        _set("variants", [{"id": "v", "expect": "pass", "why": "w", "user": []}] * 2),
        "variants[1].id",
        "two variants share the id 'v'",
    ),
    (
        "variant with a broken action",
        _set(
            "variants",
            [
                {
                    "id": "v",
                    "expect": "fail",
                    "why": "w",
                    "interventions": [{"proposal": "p", "actions": [{"tool": "email__reply_email"}]}],
                }
            ],
        ),
        "variants[0].interventions[0].actions[0].tool",
        "did you mean 'email__reply_to_email'",
    ),
    (
        "by_hand step no screen offers",
        _set("oracle/by_hand", [{"tool": "reply_to_email", "args": {"content": "x"}}]),
        "oracle.by_hand[0].tool",
        "no screen of this scenario's apps offers 'reply_to_email'",
    ),
    (
        "state check by a stranger",
        _set("goals/0/checks/1", {"state": {"path": "email.emails", "by": "bob"}}),
        "goals[0].checks[1].state.by",
        "'assistant' or 'user'",
    ),
]


@pytest.mark.parametrize(("name", "edit", "place", "message"), CASES, ids=[case[0] for case in CASES])
def test_each_mistake_is_named_with_its_place(name: str, edit: Edit, place: str, message: str) -> None:
    data = base()
    edit(data)
    problems = problems_of(data)
    assert any(f": {place}: " in p and message.lower() in p.lower() for p in problems), problems
    assert all(p.startswith("tiny.yaml:") for p in problems)


def _reactive(**extra: Any) -> dict[str, Any]:
    data = base()
    data["events"].append(
        {
            "id": "ann_replies",
            "when": {"tool": "email__reply_to_email"},
            "tool": "email__receive_email",
            "args": {"sender": "ann@x.example", "subject": "Re", "content": "Great"},
            **extra,
        }
    )
    return data


def test_reactive_branches_are_checked_like_events() -> None:
    problems = "\n".join(
        problems_of(
            _reactive(
                if_args={"body": {"contains": "thursday"}, "content": {"contain": "x"}},
                otherwise={"id": "ann_asks", "tool": "email__recieve_email", "args": {}},
            )
        )
    )
    assert "events[1].if_args.body: email__reply_to_email has no argument 'body'" in problems
    assert "events[1].if_args.content.contain: 'contain' is not an operator" in problems
    assert "events[1].otherwise.id: the event id 'ann_asks' is taken" in problems
    assert "events[1].otherwise.tool: unknown tool 'email__recieve_email'" in problems


def test_an_otherwise_reaction_is_an_event_others_can_wait_for() -> None:
    data = _reactive(
        if_args={"content": {"contains": "thursday"}},
        otherwise={
            "tool": "email__receive_email",
            "args": {"sender": "ann@x.example", "subject": "?", "content": "Which day?"},
        },
    )
    data["oracle"]["user"].append({"tool": "go_back", "when": {"event": "ann_replies_otherwise"}})
    assert parse(data).events[1].otherwise_id == "ann_replies_otherwise"


def test_event_dependencies() -> None:
    data = base()
    data["events"].append(
        {
            "id": "a",
            "after": "b",
            "tool": "email__receive_email",
            "args": {"sender": "a@x.example", "subject": "a", "content": "a"},
        }
    )
    data["events"].append(
        {
            "id": "b",
            "after": "a",
            "delay": "5m",
            "tool": "email__receive_email",
            "args": {"sender": "b@x.example", "subject": "b", "content": "b"},
        }
    )
    data["events"].append(
        {
            "id": "c",
            "after": "zz",
            "tool": "email__receive_email",
            "args": {"sender": "c@x.example", "subject": "c", "content": "c"},
        }
    )
    data["events"].append(
        {
            "id": "a",
            "at": "+1m",
            "tool": "email__receive_email",
            "args": {"sender": "d@x.example", "subject": "d", "content": "d"},
        }
    )
    problems = "\n".join(problems_of(data))
    assert "cycle: a -> b -> a" in problems
    assert "waits for unknown event 'zz'" in problems
    assert "two events share the id 'a'" in problems


def test_every_problem_is_reported_at_once_with_lines() -> None:
    data = base()
    data["events"][0]["tool"] = "email__recieve_email"
    data["oracle"]["user"][1]["tool"] = "open_mail"
    data["goals"][0]["checks"][0]["action"]["args"]["body"] = "x"
    text = to_yaml(data)
    with pytest.raises(ScenarioError) as caught:
        parse_scenario(text, source="tiny.yaml")
    problems = caught.value.problems
    assert len(problems) == 3
    lines = text.splitlines()
    for problem, needle in zip(problems, ["email__recieve_email", "open_mail", "body:"], strict=True):
        assert problem.line is not None
        assert needle in lines[problem.line - 1], (problem, lines[problem.line - 1])
    assert str(caught.value).startswith("tiny.yaml: 3 problems:")


def test_structure_errors_point_at_their_line() -> None:
    text = to_yaml(base()).replace("difficulty: easy", "difficulty: trivial")
    with pytest.raises(ScenarioError) as caught:
        parse_scenario(text, source="tiny.yaml")
    (problem,) = caught.value.problems
    assert text.splitlines()[problem.line - 1].startswith("difficulty:")  # type: ignore[operator]


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("id: [unclosed\n", "not valid YAML"),
        ("id: a\ntitle: b\nid: c\n", "broken.yaml:3: id: 'id' is written twice"),
        ("", "this file is empty"),
        ("- a\n- b\n", "this file is a list"),
    ],
)
def test_not_a_scenario_at_all(text: str, message: str) -> None:
    with pytest.raises(ScenarioError, match=message):
        parse_scenario(text, source="broken.yaml")


def test_file_name_must_be_the_id(tmp_path: Path) -> None:
    path = tmp_path / "other_name.yaml"
    path.write_text(to_yaml(base()))
    with pytest.raises(ScenarioError, match="differs from the file name 'other_name'"):
        load_scenario(path)
    good = tmp_path / "tiny_reply.yaml"
    good.write_text(to_yaml(base()))
    assert load_scenario(good).id == "tiny_reply"


def test_missing_file_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(Exception, match="no such scenario file"):
        load_scenario(tmp_path / "nope.yaml")


def test_seed_lists_become_keyed_collections_and_ids_are_known() -> None:
    data = base()
    data["seed"]["email"]["emails"].append(dict(data["seed"]["email"]["emails"][0]))  # duplicate id
    problems = "\n".join(problems_of(data))
    assert "seed.email.emails[1].email_id: two items of 'emails' have the id 'e1'" in problems


def test_state_paths_step_through_id_keyed_collections() -> None:
    data = base()
    data["apps"].append("messaging")
    data["seed"]["messaging"] = {
        "current_user_id": "user-me",
        "users": {"user-me": "Me", "user-jo": "Jo Park"},
        "conversations": [
            {"conversation_id": "conv-jo", "participant_ids": ["user-me", "user-jo"], "messages": []},
        ],
    }
    path = "messaging.conversations.conv-jo.messages"
    data["goals"][0]["checks"].append(
        {"state": {"path": path, "where": {"sender_id": "user-me"}, "count": 0}}
    )
    parse(data)  # message fields are known through the conversation's id key
    data["goals"][0]["checks"][-1]["state"]["where"] = {"sender": "user-me"}
    problems = "\n".join(problems_of(data))
    assert (
        "state.where.sender: items of messaging.conversations.conv-jo.messages have no field 'sender'"
        in problems
    )
    assert "did you mean 'sender_id'" in problems.lower()


def test_an_intervention_longer_than_the_execute_budget_is_refused() -> None:
    """Actions past the budget would silently never run, and the gate would blame the checks instead."""
    data = base()
    actions = data["oracle"]["interventions"][0]["actions"]
    data["oracle"]["interventions"][0]["actions"] = (actions * 10)[:10]
    found = problems_of(data)
    assert any(
        "oracle.interventions[0].actions" in problem
        and "10 actions and the report make 11 steps, more than the 10" in problem
        for problem in found
    ), found
    data["oracle"]["interventions"][0]["actions"] = (actions * 9)[:9]
    assert not any("execute_steps" in problem for problem in _problems_or_none(data))


def _problems_or_none(data: dict[str, Any]) -> list[str]:
    try:
        parse(data)
    except ScenarioError as error:
        return [str(problem) for problem in error.problems]
    return []


@pytest.mark.parametrize(
    ("excused", "expect", "place", "message"),
    [
        (
            {"ann_confrims": "w"},
            "pass",
            "variants[0].otherwise_ok.ann_confrims",
            "did you mean 'ann_confirms'",
        ),
        ({"ann_asks": "w"}, "pass", "variants[0].otherwise_ok.ann_asks", "has no 'otherwise' branch"),
        ({"ann_confirms": ""}, "pass", "variants[0].otherwise_ok.ann_confirms", ""),  # a reason is required
        ({"ann_confirms": "w"}, "fail", "variants[0]", "a failing variant may get any reply"),
    ],
)
def test_a_variants_otherwise_ok_names_a_branch_it_excuses_with_a_reason(
    excused: dict[str, str], expect: str, place: str, message: str
) -> None:
    data = fair()
    data["variants"][0].update(otherwise_ok=excused, expect=expect)
    found = problems_of(data)
    matching = [
        p for p in found if p.startswith("tiny.yaml:") and f": {place}: " in p and message in p.lower()
    ]
    assert matching, found
    data["variants"][0].update(otherwise_ok={"ann_confirms": "Ann asks back, then gets her answer."})
    data["variants"][0]["expect"] = "pass"
    assert parse(data).variants[0].otherwise_ok == {"ann_confirms": "Ann asks back, then gets her answer."}


def test_one_mistake_seen_in_many_places_is_said_once_with_its_places() -> None:
    """A seed id misspelt: every action naming it is wrong in the same way, so the message says it once."""
    data = copy.deepcopy(fair())  # fair() shares its reply's arguments with the helpers
    data["seed"]["email"]["emails"][0]["email_id"] = "e_one"  # Bob's email, renamed in the seed only
    for variant in data["variants"][1:]:
        variant["interventions"][0]["actions"][0]["args"]["email_id"] = "e1"
    data["oracle"]["interventions"][0]["actions"][0]["args"]["email_id"] = "e1"
    with pytest.raises(ScenarioError) as caught:
        parse(data)
    error = caught.value
    assert len(error.problems) == 3
    first = min(problem.line for problem in error.problems if problem.line is not None)
    heading, line = str(error).splitlines()
    assert heading == "tiny.yaml: 1 problem in 3 places:"
    assert line.startswith(
        f"  tiny.yaml:{first}: oracle.interventions[0].actions[0].args.email_id, "
        "variants[1-2].interventions[0].actions[0].args.email_id: 'e1' is not an id in the seed data"
    ), line
    assert line.endswith("(3 places)")


@pytest.mark.parametrize(
    ("app", "edit", "place", "record"),
    [
        (
            "email",
            lambda seed: seed["emails"][0].update(timestamp="+1h"),
            "seed.email.emails[0].timestamp",
            "email 'e1' sent 2025-03-03 10:00",
        ),
        (
            "messaging",
            lambda seed: seed["conversations"][0]["messages"][1].update(timestamp="day+1 08:00"),
            "seed.messaging.conversations[0].messages[1].timestamp",
            "message 'm2' of conversation 'conv-jo' sent 2025-03-04 08:00",
        ),
    ],
)
def test_a_seed_record_dated_after_the_start_is_refused_at_load_with_its_line(
    app: str, edit: Callable[[dict[str, Any]], None], place: str, record: str
) -> None:
    data = base()
    data["apps"].append("messaging")
    data["seed"]["messaging"] = {
        "current_user_id": "user-me",
        "users": {"user-me": "Me", "user-jo": "Jo Park"},
        "conversations": [
            {
                "conversation_id": "conv-jo",
                "participant_ids": ["user-me", "user-jo"],
                "messages": [
                    {"message_id": "m1", "sender_id": "user-jo", "content": "Hi", "timestamp": "-2h"},
                    {"message_id": "m2", "sender_id": "user-me", "content": "Hello", "timestamp": "-1h"},
                ],
            },
        ],
    }
    parse(data)  # dated before the start: fine
    edit(data["seed"][app])
    text = to_yaml(data)
    with pytest.raises(ScenarioError) as caught:
        parse_scenario(text, source="tiny.yaml")
    (problem,) = caught.value.problems
    assert problem.path == place
    assert problem.message.startswith(f"{record} is after the scenario starts (2025-03-03 09:00)")
    assert problem.line is not None
    written = text.splitlines()[problem.line - 1]
    assert "timestamp:" in written and ("+1h" in written or "day+1 08:00" in written), written


def test_a_judge_may_read_a_field_inside_an_edits_updates() -> None:
    from pare.apps.registry import get_app_class
    from pare.scenarios.validation import _reads_field

    params = get_app_class("reminder").tools["update_reminder"].params
    assert _reads_field(params, "description")  # inside `updates`
    assert _reads_field(params, "reminder_id")
    assert not _reads_field(params, "body")
