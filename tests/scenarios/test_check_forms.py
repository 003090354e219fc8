"""Check forms are records in one registry, keyed by their key in a scenario file."""

from __future__ import annotations

import re
import typing
from collections.abc import Sequence
from dataclasses import replace
from datetime import datetime
from typing import Any

import pytest

from pare.bench import run_episode
from pare.scenarios import OracleAssistant, OracleUser, evaluate
from pare.scenarios.checks import (
    CHECK_FORMS,
    CheckForm,
    Rule,
    check_sentences,
    linked_entries,
    register_check_form,
    state_check_places,
)
from pare.scenarios.model import CHECK_FORM_KEYS, ActionPattern, Check
from pare.scenarios.reading import CallReader
from pare.scenarios.validation import is_positive, needs_assistant
from pare.sim.log import LogEntry
from tests.scenarios.helpers import base, parse


def test_every_form_of_check_is_registered_with_the_model_of_its_field() -> None:
    assert tuple(CHECK_FORMS) == CHECK_FORM_KEYS == ("action", "no_action", "state", "judge", "any_of")
    for key, form in CHECK_FORMS.items():
        assert form.key == key
        assert typing.get_args(Check.model_fields[key].annotation) == (form.model, type(None))


def test_a_form_without_its_field_on_check_is_refused() -> None:
    form = replace(CHECK_FORMS["no_action"], key="never_action")
    wanted = re.escape("needs its field on Check: 'never_action: ActionPattern | None'")
    with pytest.raises(ValueError, match=wanted):
        register_check_form(form)
    with pytest.raises(ValueError, match="'action' is already registered"):
        register_check_form(CHECK_FORMS["action"])


class _FirstCall(Rule):
    """A rule of the test's own: holds when the pattern's tool was called, and names its first call."""

    def __init__(self, check: Check, pattern: ActionPattern, start: datetime) -> None:
        super().__init__(check)
        self.tools = pattern.tools or ()

    def wanted(self) -> str:
        return f"a first call of {' or '.join(self.tools)}"

    def verdict(self, context: Any, *, explain: bool = True) -> tuple[bool, str]:
        first = self.linked(context.log, None)
        return bool(first), f"first called at {first}"

    def linked(self, log: Sequence[LogEntry], reader: CallReader | None) -> list[int]:
        return [entry.index for entry in log if f"{entry.app}__{entry.tool}" in self.tools][:1]


def test_a_forms_rule_judges_its_checks_and_says_what_the_viewer_links(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    form = CheckForm("no_action", ActionPattern, _FirstCall, positive=lambda _: True, needs_assistant=bool)
    monkeypatch.setitem(CHECK_FORMS, "no_action", form)
    data = base()
    data["goals"][0]["checks"].append({"no_action": {"actor": "any", "tool": "system__open_app"}})
    scenario = parse(data)
    result = run_episode(scenario, OracleUser(scenario), OracleAssistant(scenario))

    outcome = evaluate(scenario, result.env.log.entries, result.env.snapshot())
    replied, first = outcome.goals[0].checks
    assert replied.passed
    opened = next(e.index for e in result.env.log.entries if e.tool == "open_app")
    assert first.form == "no_action" and first.passed and first.detail == f"first called at [{opened}]"
    assert check_sentences(scenario)["replied"][1] == "a first call of system__open_app"
    check = scenario.goals[0].checks[1]
    assert is_positive(check) and needs_assistant(check)  # what the loader asks of the form, from it
    links = linked_entries(scenario, result.env.log.entries, result.env.snapshot())
    assert links[("replied", 1)] == [opened]
    reply = next(e.index for e in result.env.log.entries if e.tool == "reply_to_email")
    assert links[("replied", 0)] == [reply]  # the built-in action rule links the matching call
    assert state_check_places(scenario, result.env.snapshot()) == {}  # no check reads the state
