from __future__ import annotations

from datetime import timedelta

import pytest

from pare.errors import SimulationBug, UserInputError
from pare.sim import AfterEvent, AfterStart, AtTime, EventAction, EventScheduler, ScheduledEvent, WhenLogged
from pare.sim.log import LogEntry
from tests.conftest import START, make_env, ok
from tests.fixture_app import NotebookApp


def arrive(text: str) -> EventAction:
    return EventAction("notebook", "arrive", {"text": text})


def fired(env) -> list[tuple[str, str]]:  # type: ignore[no-untyped-def]
    return [(e.event_id, e.time.strftime("%H:%M")) for e in env.log if e.actor == "env"]


def test_each_scheduling_form_fires_at_its_time() -> None:
    env = make_env([NotebookApp()])
    env.schedule(ScheduledEvent("absolute", AtTime(START + timedelta(minutes=30)), arrive("a")))
    env.schedule(ScheduledEvent("relative", AfterStart(timedelta(minutes=5)), arrive("b")))
    env.schedule(ScheduledEvent("chained", AfterEvent("relative", timedelta(minutes=10)), arrive("c")))
    env.schedule(ScheduledEvent("chained2", AfterEvent("chained"), arrive("d")))
    env.scheduler.validate()
    env.advance(timedelta(minutes=4))
    assert fired(env) == []
    env.advance(timedelta(hours=1))
    assert fired(env) == [
        ("relative", "09:05"),
        ("chained", "09:15"),
        ("chained2", "09:15"),
        ("absolute", "09:30"),
    ]
    assert env.clock.now == START + timedelta(minutes=64)
    assert env.scheduler.pending == 0


def test_condition_on_the_log_fires_once_after_its_delay_whoever_acts() -> None:
    env = make_env([NotebookApp()])
    condition = WhenLogged(
        lambda entry: entry.tool == "add_item" and entry.ok and entry.args.get("text") == "ping",
        delay=timedelta(minutes=10),
        description="someone adds 'ping'",
    )
    env.schedule(ScheduledEvent("pong", condition, arrive("pong")))
    env.schedule(ScheduledEvent("after-pong", AfterEvent("pong", timedelta(minutes=1)), arrive("pong2")))
    env.advance(timedelta(minutes=30))
    assert fired(env) == []
    assert env.scheduler.waiting_on_conditions == ["pong"]
    ok(env.call("assistant", "notebook__add_item", {"text": "ping"}, mode="execute"))
    ok(env.call("assistant", "notebook__add_item", {"text": "ping"}, mode="execute"))
    env.advance(timedelta(minutes=9))
    assert fired(env) == []
    assert env.scheduler.set_off == {"pong": len(env.log) - 2}  # the first ping, before it is due
    assert env.log[env.scheduler.set_off["pong"]].args == {"text": "ping"}
    env.advance(timedelta(minutes=5))
    assert fired(env) == [("pong", "09:40"), ("after-pong", "09:41")]


def test_an_event_withdrawn_by_another_is_not_delivered_once_that_one_is_set_off_first() -> None:
    env = make_env([NotebookApp()])

    def says(text: str) -> WhenLogged:
        return WhenLogged(lambda entry: entry.args.get("text") == text, delay=timedelta(minutes=10))

    env.schedule(ScheduledEvent("answer", says("right"), arrive("thanks")))
    env.schedule(ScheduledEvent("question", says("vague"), arrive("which?"), withdrawn_by="answer"))
    ok(env.call("assistant", "notebook__add_item", {"text": "vague"}, mode="execute"))
    env.advance(timedelta(minutes=5))
    ok(env.call("assistant", "notebook__add_item", {"text": "right"}, mode="execute"))
    env.advance(timedelta(minutes=30))
    assert fired(env) == [("answer", "09:15")]  # the question was due at 09:10, after the answer came
    assert env.scheduler.withdrawn == {"question": "answer"}
    assert env.scheduler.pending == 0


def test_an_event_already_delivered_is_not_withdrawn() -> None:
    env = make_env([NotebookApp()])
    env.schedule(ScheduledEvent("answer", WhenLogged(lambda e: e.args.get("text") == "right"), arrive("ok")))
    condition = WhenLogged(lambda e: e.args.get("text") == "vague", delay=timedelta(minutes=1))
    env.schedule(ScheduledEvent("question", condition, arrive("which?"), withdrawn_by="answer"))
    ok(env.call("assistant", "notebook__add_item", {"text": "vague"}, mode="execute"))
    env.advance(timedelta(minutes=5))
    ok(env.call("assistant", "notebook__add_item", {"text": "right"}, mode="execute"))
    env.advance(timedelta(minutes=5))
    assert [event for event, _ in fired(env)] == ["question", "answer"]
    assert not env.scheduler.withdrawn


def test_failed_call_can_still_satisfy_only_conditions_that_ask_for_it() -> None:
    env = make_env([NotebookApp()])
    env.schedule(ScheduledEvent("e", WhenLogged(lambda e: e.tool == "add_item" and e.ok), arrive("x")))
    env.call("assistant", "notebook__add_item", {"text": ""}, mode="execute")
    env.deliver_due_events()
    assert fired(env) == []


def test_same_time_events_fire_in_the_order_scheduled() -> None:
    env = make_env([NotebookApp()])
    for name in ("first", "second", "third"):
        env.schedule(ScheduledEvent(name, AfterStart(timedelta(minutes=1)), arrive(name)))
    env.advance(timedelta(minutes=1))
    assert [e for e, _ in fired(env)] == ["first", "second", "third"]


def test_events_due_at_start_are_delivered_without_moving_time() -> None:
    env = make_env([NotebookApp()])
    env.schedule(ScheduledEvent("now", AfterStart(), arrive("now")))
    env.deliver_due_events()
    assert fired(env) == [("now", "09:00")]
    assert env.clock.now == START


def test_next_event_time_allows_jumping_when_everyone_waits() -> None:
    env = make_env([NotebookApp()])
    env.schedule(ScheduledEvent("later", AtTime(START + timedelta(hours=3)), arrive("x")))
    upcoming = env.next_event_time()
    assert upcoming == START + timedelta(hours=3)
    env.advance_to(upcoming)
    assert fired(env) == [("later", "12:00")]
    assert env.next_event_time() is None


def test_validate_reports_unknown_dependencies_and_cycles() -> None:
    scheduler = EventScheduler(START)
    scheduler.add(ScheduledEvent("a", AfterEvent("b"), arrive("a")))
    scheduler.add(ScheduledEvent("b", AfterEvent("a"), arrive("b")))
    scheduler.add(ScheduledEvent("c", AfterEvent("ghost"), arrive("c")))
    with pytest.raises(UserInputError) as raised:
        scheduler.validate()
    assert "unknown event 'ghost'" in str(raised.value)
    assert "cycle" in str(raised.value)


def test_duplicate_event_ids_are_refused() -> None:
    scheduler = EventScheduler(START)
    scheduler.add(ScheduledEvent("a", AfterStart(), arrive("a")))
    with pytest.raises(UserInputError, match="share the id 'a'"):
        scheduler.add(ScheduledEvent("a", AfterStart(), arrive("b")))


def test_event_results_raise_notifications_to_both_actors() -> None:
    env = make_env([NotebookApp()])
    env.schedule(ScheduledEvent("a", AfterStart(timedelta(minutes=2)), arrive("buy milk and eggs")))
    env.advance(timedelta(minutes=2))
    assert env.user_view().notifications == [
        "[2025-03-03 09:02] Notebook: New item from Ada — Item: buy milk and eggs"
    ]
    assert "item_id=item-1" in env.assistant_observation().notifications[0]


def test_a_failing_event_is_recorded_and_reported_not_silent() -> None:
    env = make_env([NotebookApp()])
    env.schedule(ScheduledEvent("bad", AfterStart(), EventAction("notebook", "arrive", {"txt": "typo"})))
    env.schedule(ScheduledEvent("good", AfterStart(), arrive("fine")))
    env.deliver_due_events()
    assert [e.event_id for e in env.failed_events()] == ["bad"]
    assert "unexpected argument 'txt'" in (env.failed_events()[0].error or "")


def test_app_wakeups_fire_at_their_time_through_the_logged_door() -> None:
    from tests.fixture_app import AlarmApp

    env = make_env([AlarmApp()])
    ok(env.call("assistant", "alarm__set_alarm", {"at": "2025-03-03T10:30:00+00:00"}, mode="execute"))
    ok(env.call("assistant", "alarm__set_alarm", {"at": "2025-03-03T09:45:00+00:00"}, mode="execute"))
    assert env.next_event_time() == START + timedelta(minutes=45)
    env.advance(timedelta(hours=2))
    rings = [(e.event_id, e.time.strftime("%H:%M"), e.result) for e in env.log if e.actor == "env"]
    assert rings == [
        ("alarm:ring", "09:45", ["2025-03-03T09:45:00+00:00"]),
        ("alarm:ring", "10:30", ["2025-03-03T10:30:00+00:00"]),
    ]
    assert env.next_event_time() is None
    assert len(env.user_view().notifications) == 2


def test_delivering_reactions_fires_what_the_log_set_off_and_nothing_else() -> None:
    env = make_env([NotebookApp()])
    ping = WhenLogged(lambda entry: entry.tool == "add_item" and entry.args.get("text") == "ping")
    env.schedule(ScheduledEvent("story", AtTime(START + timedelta(minutes=5)), arrive("story")))
    env.schedule(ScheduledEvent("pong", WhenLogged(ping.condition, timedelta(minutes=20)), arrive("pong")))
    env.schedule(ScheduledEvent("after-pong", AfterEvent("pong", timedelta(minutes=1)), arrive("pong2")))
    env.schedule(ScheduledEvent("far", WhenLogged(ping.condition, timedelta(days=2)), arrive("far")))
    env.schedule(ScheduledEvent("unset", WhenLogged(lambda entry: False), arrive("never")))
    ok(env.call("assistant", "notebook__add_item", {"text": "ping"}, mode="execute"))
    assert env.scheduler.scheduled_reactions() == ["pong", "far"]
    assert not env.scheduler.is_reaction("story") and not env.scheduler.is_reaction("unset")

    delivered = env.deliver_reactions(START + timedelta(hours=1))
    assert delivered == ["pong", "after-pong"]  # in time order, a reaction's dependent too
    assert fired(env) == [("pong", "09:20"), ("after-pong", "09:21")]  # not the story event due at 09:05
    assert env.clock.now == START + timedelta(minutes=21)
    assert env.scheduler.scheduled_reactions() == ["far"]  # beyond the bound: still due
    assert env.scheduler.next_time() == START + timedelta(minutes=5)  # the story event stays scheduled


def test_a_condition_that_cannot_tell_yet_is_held_and_tested_again_in_order() -> None:
    """A condition waiting for an answer (a judge's reading) is tested again on the entry it could not
    tell, then on those logged since, and sets its event off as of the entry that met it.
    """
    env = make_env([NotebookApp()])
    answers: dict[str, bool] = {}

    def meant(entry: LogEntry) -> bool | None:
        text = entry.args.get("text")
        if entry.tool != "add_item" or not isinstance(text, str):
            return False
        return answers.get(text)  # None: not answered yet

    env.schedule(ScheduledEvent("reply", WhenLogged(meant, timedelta(minutes=10)), arrive("reply")))
    env.schedule(ScheduledEvent("plain", WhenLogged(lambda entry: entry.tool == "add_item"), arrive("p")))
    for text in ("maybe", "yes please"):
        ok(env.call("assistant", "notebook__add_item", {"text": text}, mode="execute"))
    first, second = len(env.log) - 2, len(env.log) - 1
    assert env.scheduler.undecided and env.scheduler.set_off == {"plain": first}  # the others go on
    with pytest.raises(SimulationBug, match="waited for an answer"):
        env.advance(timedelta(minutes=1))  # a reaction set off now would be due in the past

    answers["maybe"] = False
    env.scheduler.retest()  # 'maybe' does not meet it; 'yes please' is not answered yet
    assert env.scheduler.undecided and "reply" not in env.scheduler.set_off
    answers["yes please"] = True
    env.scheduler.retest()
    assert not env.scheduler.undecided and env.scheduler.set_off["reply"] == second
    env.advance(timedelta(minutes=10))
    assert fired(env) == [("plain", "09:00"), ("reply", "09:10")]
