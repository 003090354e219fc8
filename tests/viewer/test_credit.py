"""Who the state diff says made each change: the world's events, the user's and the assistant's calls.

Issue 35: the reply a friend sent into the group chat the assistant had written in was shown as the
assistant's, because the page credited a change to the nearest place above it that the assistant had
changed (the conversation).
"""

from __future__ import annotations

import copy
import html
import re
from pathlib import Path
from typing import Any

from pare.agents.policy import SilentAssistant
from pare.bench.episode import EpisodeSettings, run_episode
from pare.bench.state_diff import state_changes
from pare.env.attribution import Attribution
from pare.results.trajectory import LogRecord, PlaceRecord, Trajectory, attribution_records
from pare.scenarios.library import get_scenario
from pare.scenarios.oracle import OracleAssistant, OracleUser
from pare.viewer import Catalog, Site, build_episode
from pare.viewer._credit import Credit, Credits
from pare.viewer._episode import Change, EpisodeView
from pare.viewer._evidence import library_scenario, state_entries
from tests.viewer.runs import WORLD_SCENARIO

_ROW = re.compile(r"<tr class=\"op-\w+\">(.*?)</tr>", re.S)
_CELL = re.compile(r"<td[^>]*>(.*?)</td>", re.S)
_TAG = re.compile(r"<[^>]+>")


def _trajectory(folder: Path) -> Trajectory:
    configuration = Catalog.open([folder]).configurations[0]
    data = configuration.trajectory(configuration.records[(WORLD_SCENARIO, 1)])
    assert data is not None
    return data


def _entry(data: Trajectory, **wanted: Any) -> int:
    (index,) = [e.index for e in data.log if all(getattr(e, k) == v for k, v in wanted.items())]
    return int(index)


def _path_of(data: Trajectory, key: str, value: str) -> str:
    """The state diff's path (without the app) of the item added with ``key: value``."""
    (path,) = [
        op["path"].split("/", 2)[2]
        for op in data.state_diff or []
        if isinstance(op.get("value"), dict) and op["value"].get(key) == value
    ]
    return str(path)


def _by(episode: EpisodeView, path: str) -> list[tuple[str, int | None, str | None]]:
    (change,) = [c for c in episode.changes or [] if c.path == path]
    return _credits(change)


def _credits(change: Change) -> list[tuple[str, int | None, str | None]]:
    return [(credit.who, credit.log_index, credit.event_id) for credit in change.credits]


def _diff_rows(page: str) -> dict[str, tuple[str, list[str]]]:
    """The page's state diff: for each path, the text of its "by" cell and the entries it links to."""
    section = page.split('id="changes"', 1)[1].split("</section>", 1)[0]
    rows = {}
    for row in _ROW.findall(section):
        cells = _CELL.findall(row)
        path = html.unescape(_TAG.sub("", cells[2]))
        by = cells[4]
        text = " ".join(html.unescape(_TAG.sub("", by)).split())
        rows[path] = (text, re.findall(r'href="#(log-\d+)"', by))
    return rows


def test_the_page_credits_the_friends_messages_to_their_events(world_run: Path) -> None:
    data = _trajectory(world_run)
    page = Site(Catalog.open([world_run])).page(f"c/oracle/e/{WORLD_SCENARIO}/run-1.html")
    assert page is not None
    rows = _diff_rows(page.body.decode())
    reply = _entry(data, actor="env", event_id="ana_tuesday")
    wrote = _entry(data, actor="assistant", tool="send_message_to_group_conversation")
    assert reply > wrote  # the reply came after the assistant wrote in the same conversation
    text, links = rows[_path_of(data, "message_id", "msg-ana-tue")]
    assert (text, links) == (f"event ana_tuesday #{reply}", [f"log-{reply}"])
    first = _entry(data, actor="env", event_id="ana_wednesday")
    assert rows[_path_of(data, "message_id", "msg-ana-wed")] == (
        f"event ana_wednesday #{first}",
        [f"log-{first}"],
    )
    own = [path for path, (text, _) in rows.items() if text == f"assistant #{wrote}"]
    assert [p for p in own if "/messages/" in p] == [_path_of(data, "message_id", "msg-1")]
    assert f'id="log-{reply}"' in page.body.decode()  # the link lands on the event's row of the log


def test_fields_the_world_changed_and_proposals_name_who_changed_them(world_run: Path) -> None:
    data = _trajectory(world_run)
    episode = build_episode(data, [])
    reply = _entry(data, actor="env", event_id="ana_tuesday")
    # the friend's reply left the conversation unread; the assistant never touched that field
    assert _by(episode, "conversations/conv-wallrats/unread") == [("event", reply, "ana_tuesday")]
    proposed = _entry(data, actor="assistant", tool="send_message_to_user", mode="observe", turn=1)
    accepted = _entry(data, actor="user", tool="accept_proposal", turn=2)
    assert _by(episode, "proposals/0") == [("assistant", proposed, None), ("user", accepted, None)]
    made = _entry(data, actor="assistant", tool="add_calendar_event")
    assert _by(episode, "events/" + _path_of(data, "event_id", "event-1").rsplit("/", 1)[1]) == [
        ("assistant", made, None)
    ]


def test_what_the_user_made_by_hand_is_credited_to_the_users_calls() -> None:
    scenario = get_scenario(WORLD_SCENARIO)
    steps = len(scenario.by_hand().user)
    settings = EpisodeSettings(max_turns=EpisodeSettings().max_turns + steps)
    result = run_episode(scenario, OracleUser(scenario, scenario.by_hand()), SilentAssistant(), settings)
    data = result.trajectory()
    episode = build_episode(data, [])
    sent = _entry(data, actor="user", tool="send_message")
    saved = _entry(data, actor="user", tool="save")
    created = [c for c in episode.changes or [] if c.op == "add"]
    by_user = {c.path.split("/")[0]: _credits(c) for c in created if c.credits[0].who == "user"}
    assert by_user == {"conversations": [("user", sent, None)], "events": [("user", saved, None)]}
    assert not [c for c in created if c.credits[0].who == "assistant"]


def test_a_removed_item_is_credited_to_the_call_that_removed_it() -> None:
    scenario = get_scenario("five_a_side_kickoff_moved")
    solution = scenario.solution("delete_and_readd")
    result = run_episode(scenario, OracleUser(scenario, solution), OracleAssistant(scenario, solution))
    data = result.trajectory()
    episode = build_episode(data, [])
    deleted = _entry(data, actor="assistant", tool="delete_calendar_event")
    (removed,) = [c for c in episode.changes or [] if c.op == "remove"]
    assert removed.path == "events/ev-match-lions"
    assert _credits(removed) == [("assistant", deleted, None)]


def test_a_judge_check_links_the_texts_it_read(world_run: Path) -> None:
    data = _trajectory(world_run)
    wrote = _entry(data, actor="assistant", tool="send_message_to_group_conversation")
    # without the scenario at hand (changed since, or given by path) the check's sentence names them
    episode = build_episode(data, [])
    # the judge check on the group's message (others may read other texts)
    (judged,) = [c for g in episode.goals for c in g.checks if c.form == "judge" and wrote in c.evidence]
    assert judged.passed and f"(#{wrote})" in judged.detail
    assert judged.evidence == [wrote]
    page = Site(Catalog.open([world_run])).page(f"c/oracle/e/{WORLD_SCENARIO}/run-1.html")
    assert page is not None
    text = page.body.decode()
    checks = [part.split("</li>", 1)[0] for part in text.split('<span class="form">judge</span>')[1:]]
    links = [re.findall(r'href="#(log-\d+)"', check) for check in checks]
    assert [f"log-{wrote}"] in links


def _log(*calls: tuple[str, str, str, dict[str, Any]]) -> list[LogRecord]:
    kinds = {"env": "env", "open_event": "ui"}
    return [
        LogRecord.model_validate(
            {"index": i, "turn": 1, "time": "2025-03-03T09:00:00", "actor": actor, "app": app, "tool": tool,
             "args": args, "ok": True, "kind": kinds.get(actor, kinds.get(tool, "write")),
             "event_id": "party" if actor == "env" else None}
        )
        for i, (actor, app, tool, args) in enumerate(calls)
    ]  # fmt: skip


def _marks(attribution: Attribution) -> dict[str, PlaceRecord]:
    places, _ = attribution_records(attribution)
    return {record.dotted: record for record in places}


def test_list_items_known_only_by_position_are_credited_to_who_changed_them() -> None:
    # an order's items are a list: the assistant changes the second one's quantity, then the world
    # ships the order; the quantity is the assistant's, not the world's
    before = {"orders": {"o1": {"order_id": "o1", "status": "placed", "items": [
        {"item_id": "i1", "quantity": 1}, {"item_id": "i2", "quantity": 1}]}}}  # fmt: skip
    changed = copy.deepcopy(before)
    changed["orders"]["o1"]["items"][1]["quantity"] = 3
    shipped = copy.deepcopy(changed)
    shipped["orders"]["o1"]["status"] = "shipped"
    attribution = Attribution()
    attribution.record("assistant", 1, "shopping", before, changed)
    log = _log(
        ("user", "shopping", "open_order", {"order_id": "o1"}),
        ("assistant", "shopping", "update_item_quantity", {"order_id": "o1", "item_id": "i2"}),
        ("env", "shopping", "update_order_status", {"order_id": "o1", "status": "shipped"}),
    )
    credits = Credits(log, _marks(attribution))
    ops = {op["path"]: op for op in state_changes({"shopping": before}, {"shopping": shipped})}
    assert credits.of(ops["/shopping/orders/o1/items/1/quantity"]) == [Credit("assistant", 1)]
    assert credits.of(ops["/shopping/orders/o1/status"]) == [Credit("event", 2, "party")]


def test_a_list_shortened_by_a_removal_is_credited_to_the_write_not_to_a_later_read() -> None:
    before = {"events": {"ev1": {"event_id": "ev1", "attendees": ["Ann", "Bo", "Cy"]}}}
    after = copy.deepcopy(before)
    after["events"]["ev1"]["attendees"].remove("Bo")
    attribution = Attribution()
    attribution.record("assistant", 0, "calendar", before, after)
    assert not attribution.to_dict()  # a removal leaves no mark
    log = _log(
        ("assistant", "calendar", "edit_calendar_event", {"event_id": "ev1", "updates": {"attendees": []}}),
        ("user", "calendar", "open_event", {"event_id": "ev1"}),
    )
    credits = Credits(log, _marks(attribution))
    ops = state_changes({"calendar": before}, {"calendar": after})
    assert [op["op"] for op in ops] == ["replace", "remove"]
    assert [credits.of(op) for op in ops] == [[Credit("assistant", 0)]] * 2


def test_a_state_check_links_the_calls_that_made_the_items_it_found(world_run: Path) -> None:
    configuration = Catalog.open([world_run]).configurations[0]
    record = configuration.records[(WORLD_SCENARIO, 1)]
    data = _trajectory(world_run)
    scenario = library_scenario(record.scenario_id, record.scenario_hash)
    assert scenario is not None
    found = state_entries(scenario, data)
    added = _entry(data, actor="assistant", tool="add_calendar_event")
    assert found[("session_in_calendar", 0)] == [added]  # the session the assistant added
    # the physio appointment it found was in the calendar from the start: the assistant's new event
    # beside it in the same calendar did not make it
    assert found[("wednesday_plans_kept", 0)] == []
    page = Site(Catalog.open([world_run])).page(f"c/oracle/e/{WORLD_SCENARIO}/run-1.html")
    assert page is not None
    goal = page.body.decode().split("<b>wednesday_plans_kept</b>", 1)[1].split('<div class="goal', 1)[0]
    first = goal.split('<li class="check', 2)[1]
    assert "physio" in first and "log-ref" not in first
    assert data.state_diff is not None
    data.state_diff.insert(0, {"op": "remove", "path": "/calendar/events/no-such-event"})
    assert state_entries(scenario, data) == {}  # not this scenario's start: the page falls back
