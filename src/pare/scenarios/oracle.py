"""Deterministic policies that play a scenario's oracle, and the one that proposes something unrelated.

The oracle user takes the scenario's scripted steps (each once its condition holds) and accepts every
proposal. The oracle assistant waits until an intervention's condition holds, proposes it, and once it
is accepted carries out its actions in execute mode and reports. Both act through the same environment
and turn order as model-backed actors, so the oracle proves the scenario can be solved as written. Both
play a :class:`~pare.scenarios.model.Solution`: the oracle's by default, or a declared variant's.

The slow user is the oracle user taking one harmless extra step (looking at the clock) before each
scripted step and before answering a proposal, as real users do: the gate demands the oracle still
succeeds with it, so every scenario leaves turns to spare. The busy user never waits: whenever the oracle
user would, it looks at the clock instead, as a user model that keeps using the phone does; the gate
demands the oracle still succeeds with it too, so no scenario's timeline depends on the user idling.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from pare.agents.policy import (
    ASSISTANT_WAIT,
    DEFAULT_BUDGET,
    SEND_MESSAGE,
    WAIT,
    Action,
    AssistantPolicy,
    Task,
    TurnBudget,
    UserPolicy,
)
from pare.env import AssistantObservation, Environment, ToolResult, UserView
from pare.errors import UserInputError
from pare.scenarios.checks import MISSING, lookup
from pare.scenarios.model import Condition, Intervention, OracleAction, Scenario, Solution, reference
from pare.scenarios.patterns import CompiledPattern, event_positions
from pare.scenarios.reading import live_reader
from pare.scenarios.times import resolve_relative_times

DEFAULT_ANSWER = "Yes, go ahead."
HARMLESS_STEP = "get_current_time"
"""What the slow user does before each of its steps: a look at the clock changes nothing."""


class OracleRunError(UserInputError):
    """The oracle could not be played as written (a reference to a value that never appeared)."""


class Conditions:
    """Checks the oracle's ``when`` conditions; their patterns are compiled once, not every step."""

    def __init__(self, scenario: Scenario, solution: Solution) -> None:
        conditions = [step.when for step in solution.user] + [
            intervention.when for intervention in solution.interventions
        ]
        self._patterns = {
            id(condition): CompiledPattern.of(condition.action, scenario.start)
            for condition in conditions
            if condition is not None and condition.action is not None
        }

    def hold(self, condition: Condition, env: Environment) -> bool:
        """Whether ``condition`` holds now: its event has fired and a matching action has been logged."""
        if condition.event is not None and condition.event not in env.scheduler.completed:
            return False
        pattern = self._patterns.get(id(condition))
        return pattern is None or bool(pattern.find(env.log.entries, live_reader(env)))


class _References:
    """Values produced while the scenario runs, for oracle arguments written ``${id.field}``."""

    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        self.results: dict[str, Any] = {}

    def resolve(self, args: dict[str, Any], env: Environment) -> dict[str, Any]:
        resolved = {name: self._resolved(value, env) for name, value in args.items()}
        return dict(resolve_relative_times(resolved, self.scenario.start))

    def _resolved(self, value: Any, env: Environment) -> Any:
        # An argument or an item of a list argument: files to attach are a list of paths, some made by
        # earlier actions (``attachments: ["${saved.id}", ...]``).
        if isinstance(value, list):
            return [self._resolved(item, env) for item in value]
        ref = reference(value)
        return value if ref is None else self._value(ref[0], ref[1], env)

    def _value(self, source: str, path: str, env: Environment) -> Any:
        written = "${" + source + (f".{path}" if path else "") + "}"
        if source in self.results:
            value = self.results[source]
        else:
            positions = event_positions(env.log.entries)
            if source not in positions:
                raise OracleRunError(
                    f"scenario '{self.scenario.id}': the oracle needs {written}, but '{source}' "
                    "has not produced a result yet (an oracle action id or an event that has fired)"
                )
            value = env.log.entries[positions[source]].result
        if not path:
            if isinstance(value, Mapping):  # a call wants one value: the object would fail it
                fields = ", ".join(str(key) for key in value)
                field = "id" if "id" in value else "<field>"
                raise OracleRunError(
                    f"scenario '{self.scenario.id}': {written} passes the whole result of '{source}', an "
                    f"object ({fields}), where one value is wanted: name its field, "
                    f"e.g. ${{{source}.{field}}}"
                )
            return value  # the whole result: a bare path or name
        found = lookup(value, path)
        if found is MISSING:
            whole = "" if isinstance(value, Mapping) else f"; ${{{source}}} names the whole result"
            raise OracleRunError(
                f"scenario '{self.scenario.id}': {written}: the result of '{source}' has no "
                f"'{path}' (it is {value!r}{whole})"
            )
        return found


class OracleUser(UserPolicy):
    """Takes a solution's scripted user steps in order and accepts every proposal."""

    name = "oracle_user"

    def __init__(self, scenario: Scenario, solution: Solution | None = None) -> None:
        self.scenario = scenario
        self.solution = solution or scenario.solution()
        self.steps = list(self.solution.user)
        self.position = 0
        self.references = _References(scenario)
        self.conditions = Conditions(scenario, self.solution)
        self.env: Environment | None = None
        self._named: str | None = None
        """The id of the last step taken, when it has one: its result is kept for later ``${id...}``."""

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Remember the environment (the oracle may look at the log to time its steps)."""
        self.env = env

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """Accept a pending proposal, else the next scripted step whose condition holds, else wait."""
        env = self._env()
        if self._named is not None and previous is not None:
            self.references.results[self._named] = previous.value
        self._named = None
        if view.pending_proposal is not None:
            return Action("accept_proposal", {"reason": self._answer(view.pending_proposal)})
        if self.position < len(self.steps):
            step = self.steps[self.position]
            if step.when is None or self.conditions.hold(step.when, env):
                self.position += 1
                self._named = step.id
                return Action(step.tool, self.references.resolve(step.args, env))
        return Action(WAIT)

    def _answer(self, proposal: str) -> str:
        for intervention in self.solution.interventions:
            if intervention.proposal == proposal:
                return intervention.answer
        return DEFAULT_ANSWER

    def _env(self) -> Environment:
        if self.env is None:
            raise RuntimeError("OracleUser.start() was not called")
        return self.env


class AcceptAllUser(OracleUser):
    """The oracle user under its own name: its scripted steps, and every proposal accepted at once without
    looking anything up. In a run it plays as the oracle user does; a calibration names it for what it
    measures, the user who accepts everything.
    """

    name = "accept_all_user"


class StrictOracleUser(OracleUser):
    """The oracle user who knows the right answer: it accepts a proposal only when one of the scenario's
    right solutions (the oracle, a passing variant) makes it word for word, and rejects any other. The
    reference a calibration measures a user model against; against a model assistant, whose words are its
    own, it rejects nearly everything.
    """

    name = "strict_oracle_user"

    def __init__(self, scenario: Scenario, solution: Solution | None = None) -> None:
        super().__init__(scenario, solution)
        passing = scenario.right_solutions()
        self.right = frozenset(i.proposal for name in passing for i in scenario.solution(name).interventions)

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """Reject a pending proposal no right solution makes; otherwise as the oracle user."""
        if view.pending_proposal is not None and view.pending_proposal not in self.right:
            return Action("reject_proposal", {"reason": "That is not what I need."})
        return await super().step(view, previous)


class SlowUser(OracleUser):
    """The oracle user with one harmless extra step before each scripted step and each answer."""

    name = "slow_user"

    def __init__(self, scenario: Scenario, solution: Solution | None = None) -> None:
        super().__init__(scenario, solution)
        self._dawdled = False

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """Look at the clock first whenever the oracle user would act; then act."""
        action = await super().step(view, previous)
        if action.tool == WAIT:
            return action
        if not self._dawdled:
            self._dawdled = True
            if action.tool not in ("accept_proposal", "reject_proposal"):
                self.position -= 1  # take this step again next time
            return Action(HARMLESS_STEP)
        self._dawdled = False
        return action


class BusyUser(OracleUser):
    """The oracle user who never waits: whenever the oracle user would wait (between its scripted steps
    and after the last one), it does something harmless on the phone instead (looks at the clock).
    """

    name = "busy_user"

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """The oracle user's action, with every wait replaced by a look at the clock."""
        action = await super().step(view, previous)
        return Action(HARMLESS_STEP) if action.tool == WAIT else action


def _transient_failure(result: ToolResult | None) -> bool:
    """Whether ``result`` is an injected tool failure: the same call may well succeed next time."""
    return result is not None and result.entry is not None and result.entry.injected_failure


class OracleAssistant(AssistantPolicy):
    """Proposes each intervention once its condition holds; once accepted, acts and reports."""

    name = "oracle_assistant"

    def __init__(self, scenario: Scenario, solution: Solution | None = None) -> None:
        self.scenario = scenario
        self.solution = solution or scenario.solution()
        self.next_intervention = 0
        self.references = _References(scenario)
        self.conditions = Conditions(scenario, self.solution)
        self.env: Environment | None = None
        self._queue: list[OracleAction] = []
        self._current: Intervention | None = None
        self._last: OracleAction | None = None

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Remember the environment (conditions are checked against its log)."""
        self.env = env

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """Propose the next intervention once its condition holds; otherwise wait."""
        env = self._env()
        interventions = self.solution.interventions
        if self.next_intervention < len(interventions):
            intervention = interventions[self.next_intervention]
            if intervention.when is None or self.conditions.hold(intervention.when, env):
                self.next_intervention += 1
                return Action(SEND_MESSAGE, {"content": intervention.proposal})
        return Action(ASSISTANT_WAIT)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """Carry out the accepted intervention's actions in order, then report. An action that failed
        with a transient error (an injected tool failure) is tried again, as a careful assistant would:
        the actions after it may need its result.
        """
        env = self._env()
        if task is None and self._last is not None and _transient_failure(previous):
            return Action(self._last.tool, self.references.resolve(self._last.args, env))
        if task is not None:
            self._current = next(
                (i for i in self.solution.interventions if i.proposal == task.proposal), None
            )
            self._queue = list(self._current.actions) if self._current is not None else []
            self._last = None
        elif self._last is not None and self._last.id is not None and previous is not None:
            self.references.results[self._last.id] = previous.value
        if self._queue:
            action = self._queue.pop(0)
            self._last = action
            return Action(action.tool, self.references.resolve(action.args, env))
        self._last = None
        report = self._current.report if self._current is not None else "I could not match that task."
        return Action(SEND_MESSAGE, {"content": report})

    def _env(self) -> Environment:
        if self.env is None:
            raise RuntimeError("OracleAssistant.start() was not called")
        return self.env


_UNRELATED: list[tuple[str, str, str, dict[str, Any]]] = [
    (
        "reminder",
        "Shall I set a reminder for you to water the plants tomorrow at 18:00?",
        "reminder__add_reminder",
        {
            "title": "Water the plants",
            "due_datetime": "day+1 18:00",
            "description": "The ferns on the balcony.",
        },
    ),
    (
        "notes",
        "Shall I start a note with a watering schedule for your plants?",
        "notes__create_note",
        {"title": "Plant watering schedule", "content": "Ferns: Fridays. Cactus: once a month."},
    ),
    (
        "calendar",
        "Shall I block 30 minutes tomorrow at 18:00 in your calendar to water the plants?",
        "calendar__add_calendar_event",
        {"title": "Water the plants", "start_datetime": "day+1 18:00", "end_datetime": "day+1 18:30"},
    ),
    (
        "contacts",
        "Shall I add the garden centre to your contacts?",
        "contacts__add_new_contact",
        {"first_name": "Greenleaf", "last_name": "Garden Centre", "phone": "+1 555 0199"},
    ),
    (
        "files",
        "Shall I save a text file with a watering schedule for your plants?",
        "files__create_file",
        {"path": "/Documents/plant_watering.txt", "content": "Ferns: Fridays. Cactus: once a month."},
    ),
]


class UnrelatedAssistant(AssistantPolicy):
    """Proposes, at once, a plausible task that has nothing to do with the scenario, and does it.

    A scenario whose checks this passes checks too little: the gate demands it fails.
    """

    name = "unrelated_assistant"

    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        apps = set(scenario.all_apps) | {"files"}
        self.app, self.proposal, self.tool, args = next(row for row in _UNRELATED if row[0] in apps)
        self.args = dict(resolve_relative_times(args, scenario.start))
        self.proposed = False
        self.done = False

    async def observe(self, observation: AssistantObservation | None, previous: ToolResult | None) -> Action:
        """Propose the unrelated task once; afterwards wait."""
        if not self.proposed:
            self.proposed = True
            return Action(SEND_MESSAGE, {"content": self.proposal})
        return Action(ASSISTANT_WAIT)

    async def execute(self, task: Task | None, previous: ToolResult | None) -> Action:
        """Do the unrelated task, then report."""
        if not self.done:
            self.done = True
            return Action(self.tool, dict(self.args))
        return Action(SEND_MESSAGE, {"content": "Done."})
