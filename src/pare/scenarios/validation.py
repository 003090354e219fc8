"""Checking a scenario against the apps: every problem found, each with its place in the document.

Structure (fields, types, matcher syntax) is checked by the pydantic models; this module checks meaning:
apps and tools exist and take the given arguments, seed data fits each app, ids referred to exist,
events depend on known events without cycles and never fire before the start, state paths and fields
exist.
"""

from __future__ import annotations

from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass
from typing import Any, get_args

from pydantic import BaseModel, ValidationError

from pare.apps.base import App
from pare.apps.email import is_address
from pare.apps.registry import CORE_APPS, get_app_class
from pare.apps.tools import ToolSpec, describe_argument_errors
from pare.errors import did_you_mean
from pare.scenarios.annotations import item_type, model_fields
from pare.scenarios.checks import CHECK_FORMS
from pare.scenarios.item_text import TEXT_FIELDS, has_text_fields
from pare.scenarios.kinds import matcher_problems
from pare.scenarios.model import (
    VERDICT_PARTS,
    WHERE_ANY,
    WHERE_KEY,
    WHERE_TEXT,
    ActionPattern,
    Check,
    Condition,
    Intervention,
    Scenario,
    StateCheck,
    UserStep,
    reference,
)
from pare.scenarios.seed import Location, SeedError, original_location, prepare_seed
from pare.scenarios.times import parse_time, resolve_relative_times
from pare.scenarios.told import SENDING_TOOLS
from pare.sim.budget import DEFAULT_BUDGET
from pare.yaml_source import Path


@dataclass(frozen=True, slots=True)
class Problem:
    """One thing wrong with a scenario, at ``path`` in the document."""

    path: Path
    message: str


def format_path(path: Path) -> str:
    """``('events', 2, 'args')`` as ``events[2].args``."""
    text = ""
    for part in path:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else str(part))
    return text or "(top)"


class ToolCatalog:
    """The tools of a scenario's apps, by the names assistants, events and users call them."""

    def __init__(self, apps: Iterable[str]) -> None:
        self.apps = [*CORE_APPS, *[a for a in apps if a not in CORE_APPS]]
        self.flat: dict[str, ToolSpec] = {}
        self.user_actions: dict[str, list[ToolSpec]] = {}
        """User action name to the specs of every screen (or the shell) offering it."""
        self.user_qualified: dict[str, list[ToolSpec]] = {}
        """``app__action`` (as the action log records user actions) to specs."""
        for name in self.apps:
            cls = get_app_class(name)
            for spec in cls.tools.values():
                self.flat[spec.qualified_name] = spec
                if "user" in spec.actors:
                    self.user_actions.setdefault(spec.name, []).append(spec)
                    self.user_qualified.setdefault(spec.qualified_name, []).append(spec)
            for screen in cls.screens:
                for action_name, spec in screen.actions.items():
                    self.user_actions.setdefault(action_name, []).append(spec)
                    self.user_qualified.setdefault(f"{name}__{action_name}", []).append(spec)

    def unknown_tool(self, tool: str, choices: Iterable[str]) -> str:
        """The message for a tool name not among ``choices``."""
        app, _, rest = tool.partition("__")
        if not rest:
            return f"'{tool}' is not a tool name; write app__tool, e.g. email__send_email"
        if app not in self.apps:
            apps = ", ".join(self.apps)
            return f"'{tool}' belongs to app '{app}', which is not in this scenario's apps ({apps})"
        return f"unknown tool '{tool}'.{did_you_mean(tool, list(choices))}"


def validate_scenario(scenario: Scenario) -> list[Problem]:
    """Every problem with ``scenario`` beyond its structure; empty when it is sound."""
    return list(_Validator(scenario).run())


class _Validator:
    def __init__(self, scenario: Scenario) -> None:
        self.scenario = scenario
        self.start = scenario.start
        self.event_ids = [event.id for event in scenario.events] + [
            event.otherwise_id for event in scenario.events if event.otherwise_id is not None
        ]
        self.action_ids: list[str] = []
        self.action_tools: dict[str, ToolSpec] = {}
        """The tool of each oracle action with an id (what ``${id}`` passes is its result)."""
        self.catalog = ToolCatalog(scenario.all_apps)  # the model already refused unknown apps
        self.known_ids: set[str] = set()

    def run(self) -> Iterator[Problem]:
        yield from self._seed()
        yield from self._events()
        yield from self._oracle()
        yield from self._variants()
        yield from self._goals()
        yield from self._allowed_changes()

    # -- apps and seed data -----------------------------------------------------------------------------
    def _seed(self) -> Iterator[Problem]:
        for app, data in self.scenario.seed.items():
            if app not in self.scenario.all_apps:
                yield Problem(
                    ("seed", app), f"seed data for app '{app}', which is not in apps {self.scenario.apps}"
                )
                continue
            try:
                prepared, moved = prepare_seed(app, data, self.start)
            except SeedError as error:
                yield Problem(("seed", app, *error.location), str(error))
                continue
            cls = get_app_class(app)
            try:
                state = cls.State.model_validate(prepared)
            except ValidationError as error:
                for item in error.errors():
                    loc = tuple(part for part in item["loc"] if isinstance(part, str | int))
                    yield Problem(("seed", app, *original_location(loc, moved)), _pydantic_message(item))
            else:
                yield from self._dated_after_start(cls, state, app, moved)
            _collect_ids(prepared, self.known_ids)

    def _dated_after_start(
        self, cls: type[App], state: Any, app: str, moved: Mapping[Location, Location]
    ) -> Iterator[Problem]:
        """Seed records that say they happened after the start (the app refuses them when played)."""
        probe = cls()
        probe.adopt(state)
        for record in probe.records_dated_after(self.start):
            yield Problem(
                ("seed", app, *original_location(record.location, moved)),
                f"{record} is after the scenario starts ({self.start:%Y-%m-%d %H:%M}): seed data is the "
                "phone at the start, so a later edit would be stamped before the record existed; date it at "
                "or before the start, or make it an event that arrives during the episode",
            )

    # -- events ----------------------------------------------------------------------------------------
    def _events(self) -> Iterator[Problem]:
        seen: set[str] = set()
        for index, event in enumerate(self.scenario.events):
            where: Path = ("events", index)
            if event.id in seen:
                yield Problem((*where, "id"), f"two events share the id '{event.id}'")
            seen.add(event.id)
            if event.id.startswith("noise-"):
                yield Problem((*where, "id"), "ids starting with 'noise-' are reserved for noise events")
            for key, value in event.args.items():
                if key.endswith("_id") and isinstance(value, str):
                    self.known_ids.add(value)
            if event.at is not None and parse_time(event.at, self.start) < self.start:
                yield Problem(
                    (*where, "at"),
                    f"'{event.at}' is before the scenario starts ({self.start.isoformat()})",
                )
            if event.after is not None and event.after not in self.event_ids:
                hint = did_you_mean(event.after, self.event_ids)
                yield Problem((*where, "after"), f"waits for unknown event '{event.after}'.{hint}")
            if event.when is not None:
                yield from self._pattern(event.when, (*where, "when"))
                yield from self._if_args(event.when, event.if_args, (*where, "if_args"))
            yield from self._event_call(event.tool, event.args, where)
            otherwise_id = event.otherwise_id
            if event.otherwise is not None and otherwise_id is not None:
                place: Path = (*where, "otherwise")
                if otherwise_id in seen or otherwise_id in [e.id for e in self.scenario.events]:
                    yield Problem(
                        (*place, "id"), f"the event id '{otherwise_id}' is taken; give 'otherwise' an id"
                    )
                seen.add(otherwise_id)
                yield from self._event_call(event.otherwise.tool, event.otherwise.args, place)
        yield from self._cycles()

    def _event_call(self, tool: str, args: Mapping[str, Any], where: Path) -> Iterator[Problem]:
        catalog = self.catalog
        spec = catalog.flat.get(tool)
        if spec is None:
            yield Problem((*where, "tool"), catalog.unknown_tool(tool, catalog.flat))
            return
        for key, value in args.items():
            if key.endswith("_id") and isinstance(value, str):
                self.known_ids.add(value)
        yield from self._args(spec, args, (*where, "args"), refs_allowed=False)

    def _if_args(self, pattern: ActionPattern, if_args: Mapping[str, Any], where: Path) -> Iterator[Problem]:
        specs = self._pattern_specs(pattern) if pattern.tool is not None else []
        parameters = _parameters(specs)
        delivered = ("content", "attachments") if pattern.to is not None else ()
        for name, raw in if_args.items():
            if specs and name not in parameters and name not in delivered:
                hint = did_you_mean(name, parameters)
                yield Problem(
                    (*where, name),
                    f"{' or '.join(pattern.tools or ())} has no argument '{name}'.{hint} "
                    f"Arguments: {', '.join(sorted(parameters))}",
                )
            elif name in parameters:
                yield from self._fits(raw, parameters[name], (*where, name))

    def _cycles(self) -> Iterator[Problem]:
        parents = {event.id: event.after for event in self.scenario.events if event.after is not None}
        reported: set[frozenset[str]] = set()
        for index, event in enumerate(self.scenario.events):
            chain = [event.id]
            current = parents.get(event.id)
            while current is not None and current not in chain:
                chain.append(current)
                current = parents.get(current)
            if current is not None and current == event.id and frozenset(chain) not in reported:
                reported.add(frozenset(chain))
                cycle = " -> ".join([*chain, event.id])
                yield Problem(("events", index, "after"), f"events wait for each other in a cycle: {cycle}")

    # -- the oracle ------------------------------------------------------------------------------------
    def _oracle(self) -> Iterator[Problem]:
        oracle = self.scenario.oracle
        if self.scenario.kind == "proposal" and not oracle.interventions:
            yield Problem(
                ("oracle", "interventions"),
                "no intervention; a scenario where the right move is not to propose says kind: no_proposal",
            )
        if self.scenario.kind == "no_proposal" and oracle.interventions:
            yield Problem(
                ("oracle", "interventions"),
                "a no_proposal scenario's oracle makes no proposal: the right move is to watch and wait",
            )
        if self.scenario.kind == "no_proposal" and self.scenario.end_when_met:
            yield Problem(
                ("end_when_met",),
                "a no_proposal scenario's goals hold from the start, so end_when_met would end it before "
                "the moment that tempts the assistant; leave it out",
            )
        yield from self._user_steps(oracle.user, ("oracle", "user"))
        yield from self._user_steps(oracle.by_hand, ("oracle", "by_hand"))
        yield from self._interventions(oracle.interventions, ("oracle", "interventions"))

    def _variants(self) -> Iterator[Problem]:
        seen: set[str] = set()
        if self.scenario.kind == "no_proposal" and not any(
            check.no_action is not None and _forbids_proposing(check.no_action)
            for goal in self.scenario.goals
            for check in goal.checks
        ):
            yield Problem(
                ("goals",),
                "a no_proposal scenario needs a check that the assistant did not propose: "
                "no_action: {tool: agent_ui__send_message_to_user, mode: observe} (optionally with args)",
            )
        oracle_ids, oracle_tools = list(self.action_ids), dict(self.action_tools)
        for number, variant in enumerate(self.scenario.variants):
            where: Path = ("variants", number)
            if variant.id in seen:
                yield Problem((*where, "id"), f"two variants share the id '{variant.id}'")
            seen.add(variant.id)
            goals = [*(goal.id for goal in self.scenario.goals), *VERDICT_PARTS]
            for index, goal_id in enumerate(variant.fails):
                if goal_id not in goals:
                    hint = did_you_mean(goal_id, goals)
                    yield Problem((*where, "fails", index), f"unknown goal '{goal_id}'.{hint}")
            yield from self._otherwise_ok(variant.otherwise_ok, (*where, "otherwise_ok"))
            if variant.user is not None:
                yield from self._user_steps(variant.user, (*where, "user"))
            if variant.interventions is not None:
                self.action_ids, self.action_tools = [], {}  # a variant's ${id.field} name its own actions
                yield from self._interventions(variant.interventions, (*where, "interventions"))
                self.action_ids, self.action_tools = oracle_ids, oracle_tools

    def _otherwise_ok(self, excused: Mapping[str, str], where: Path) -> Iterator[Problem]:
        """A variant's ``otherwise_ok`` names reactive events that have an ``otherwise`` branch."""
        events = {event.id: event for event in self.scenario.events}
        branching = [event.id for event in self.scenario.events if event.otherwise is not None]
        for event_id in excused:
            event = events.get(event_id)
            if event is None:
                hint = did_you_mean(event_id, branching or list(events))
                yield Problem((*where, event_id), f"unknown event '{event_id}'.{hint}")
            elif event.otherwise is None:
                others = f" (events with one: {', '.join(branching)})" if branching else ""
                yield Problem(
                    (*where, event_id), f"event '{event_id}' has no 'otherwise' branch to excuse{others}"
                )

    def _user_steps(self, steps: Iterable[UserStep], at: Path) -> Iterator[Problem]:
        # a step's id names its result for the later steps of the same list only
        saved = list(self.action_ids), dict(self.action_tools)
        try:
            yield from self._user_step_list(steps, at)
        finally:
            self.action_ids, self.action_tools = saved

    def _user_step_list(self, steps: Iterable[UserStep], at: Path) -> Iterator[Problem]:
        catalog = self.catalog
        for index, step in enumerate(steps):
            where: Path = (*at, index)
            if step.when is not None:
                yield from self._condition(step.when, (*where, "when"))
            if step.tool in ("accept_proposal", "reject_proposal"):
                yield Problem(
                    (*where, "tool"),
                    "the oracle user answers proposals by itself; "
                    "give the answer as the intervention's 'answer'",
                )
                continue
            specs = catalog.user_actions.get(step.tool)
            if not specs:
                hint = did_you_mean(step.tool, catalog.user_actions)
                yield Problem(
                    (*where, "tool"), f"no screen of this scenario's apps offers '{step.tool}'.{hint}"
                )
                continue
            problems = [
                list(self._args(spec, step.args, (*where, "args"), refs_allowed=True)) for spec in specs
            ]
            if all(problems):
                yield from problems[0]
            if step.id is not None:
                if step.id in self.action_ids:
                    yield Problem((*where, "id"), f"two steps or oracle actions share the id '{step.id}'")
                self.action_ids.append(step.id)
                self.action_tools[step.id] = specs[0]

    def _interventions(self, interventions: Iterable[Intervention], at: Path) -> Iterator[Problem]:
        catalog = self.catalog
        for number, intervention in enumerate(interventions):
            where: Path = (*at, number)
            if intervention.when is not None:
                yield from self._condition(intervention.when, (*where, "when"))
            if len(intervention.actions) >= DEFAULT_BUDGET.execute_steps:
                yield Problem(
                    (*where, "actions"),
                    f"{len(intervention.actions)} actions and the report make "
                    f"{len(intervention.actions) + 1} steps, more than the {DEFAULT_BUDGET.execute_steps} an "
                    "accepted task gets (execute_steps): what comes after the limit would never run; do it "
                    "in fewer actions or split the work into two proposals",
                )
            for index, action in enumerate(intervention.actions):
                place: Path = (*where, "actions", index)
                spec = catalog.flat.get(action.tool)
                if spec is None:
                    yield Problem((*place, "tool"), catalog.unknown_tool(action.tool, catalog.flat))
                elif "assistant" not in spec.actors or spec.kind == "env":
                    yield Problem((*place, "tool"), f"'{action.tool}' is not a tool the assistant may call")
                else:
                    yield from self._args(spec, action.args, (*place, "args"), refs_allowed=True)
                if action.id is not None:
                    if action.id in self.action_ids:
                        yield Problem((*place, "id"), f"two oracle actions share the id '{action.id}'")
                    self.action_ids.append(action.id)
                    if spec is not None:
                        self.action_tools[action.id] = spec

    def _condition(self, condition: Condition, where: Path) -> Iterator[Problem]:
        if condition.event is not None and condition.event not in self.event_ids:
            hint = did_you_mean(condition.event, self.event_ids)
            yield Problem((*where, "event"), f"unknown event '{condition.event}'.{hint}")
        if condition.action is not None:
            yield from self._pattern(condition.action, (*where, "action"))

    # -- goals -----------------------------------------------------------------------------------------
    def _goals(self) -> Iterator[Problem]:
        seen: set[str] = set()
        proposing = self.scenario.kind == "proposal"
        if proposing and not any(
            needs_assistant(check) for goal in self.scenario.goals for check in goal.checks
        ):
            yield Problem(
                ("goals",),
                "no goal needs the assistant's own work, so a user who does the task by hand succeeds: "
                "give a state check 'by: assistant', or an action or judge check on the assistant's actions",
            )
        for number, goal in enumerate(self.scenario.goals):
            if goal.id in seen:
                yield Problem(("goals", number, "id"), f"two goals share the id '{goal.id}'")
            seen.add(goal.id)
            if proposing and not any(is_positive(check) for check in goal.checks):
                yield Problem(
                    ("goals", number, "checks"),
                    f"goal '{goal.id}' has no positive check (only things that must not happen), so doing "
                    "nothing meets it: add a check of what must be there",
                )
            for index, check in enumerate(goal.checks):
                yield from self._check(check, ("goals", number, "checks", index))

    def _check(self, check: Check, at: Path) -> Iterator[Problem]:
        """The problems of one check at ``at``; an ``any_of`` check's ways, each of their checks."""
        where: Path = (*at, check.form)
        if check.any_of is not None:
            for way_number, way in enumerate(check.any_of.root):
                for option_number, option in enumerate(way.all_of):
                    yield from self._check(option, (*where, way_number, "all_of", option_number))
            return
        if check.action is not None:
            yield from self._pattern(check.action, where)
        elif check.no_action is not None:
            yield from self._pattern(check.no_action, where)
        elif check.judge is not None:
            yield from self._pattern(check.judge.action, (*where, "action"))
            told = check.judge.action.to is not None and check.judge.field in (
                "content",
                "attachments",
            )
            for spec in [] if told else self._pattern_specs(check.judge.action):
                if not _reads_field(spec.params, check.judge.field):
                    yield Problem(
                        (*where, "field"),
                        f"'{check.judge.field}' is not an argument of {spec.qualified_name} "
                        f"({', '.join(spec.params.model_fields)})",
                    )
        elif check.state is not None:
            yield from self._state(check.state, where)

    def _allowed_changes(self) -> Iterator[Problem]:
        apps = self.scenario.all_apps
        for index, allowed in enumerate(self.scenario.allowed_changes):
            where: Path = ("allowed_changes", index)
            if allowed.app not in apps:
                yield Problem(
                    (*where, "app"),
                    f"'{allowed.app}' is not an app of this scenario.{did_you_mean(allowed.app, apps)}",
                )
                continue
            fields = model_fields(get_app_class(allowed.app).State) or {}
            if allowed.collection is not None and allowed.collection not in fields:
                yield Problem(
                    (*where, "collection"),
                    f"'{allowed.collection}' is not a field of {allowed.app}'s data."
                    f"{did_you_mean(allowed.collection, fields)} Fields: {', '.join(fields)}",
                )

    def _state(self, check: StateCheck, where: Path) -> Iterator[Problem]:
        parts = check.path.split(".")
        app = parts[0]
        apps = [*self.scenario.all_apps, "files", "agent_ui"]
        if app not in apps:
            hint = did_you_mean(app, apps)
            yield Problem(
                (*where, "path"), f"'{check.path}' starts with '{app}', not an app of this scenario.{hint}"
            )
            return
        model: Any = get_app_class(app).State
        for depth, part in enumerate(parts[1:], start=1):
            fields = model_fields(model)
            if fields is None:
                # a key of a dict keyed by ids, or an index of a list: step into the item type
                model = item_type(model)
                if model is None:
                    break  # free data: cannot check further statically
                continue
            if part not in fields:
                shown = ".".join(parts[:depth])
                yield Problem(
                    (*where, "path"),
                    f"'{part}' is not a field of {shown}.{did_you_mean(part, fields)} "
                    f"Fields: {', '.join(fields)}",
                )
                return
            model = fields[part]
        if "value" in check.model_fields_set and model is not None:
            yield from self._fits(check.value, model, (*where, "value"))
        if check.where and model is not None:
            item_fields = model_fields(item_type(model))
            if item_fields is not None:
                yield from self._where_fields(check.path, check.where, item_fields, (*where, "where"))
            for place, raw in _where_conditions(check.where, (*where, "where")):
                yield from self._id_reference(str(place[-1]), raw, place)

    # -- shared pieces ---------------------------------------------------------------------------------
    def _pattern(self, pattern: ActionPattern, where: Path) -> Iterator[Problem]:
        catalog = self.catalog
        if pattern.screen is not None and pattern.actor not in ("user", "any"):
            yield Problem(
                (*where, "screen"),
                f"'screen' is where the user was when acting; this pattern is about the {pattern.actor}",
            )
        for key in ("after_event", "before_event"):
            event = getattr(pattern, key)
            if event is not None and event not in self.event_ids:
                yield Problem((*where, key), f"unknown event '{event}'.{did_you_mean(event, self.event_ids)}")
        if pattern.app is not None and pattern.app not in catalog.apps:
            yield Problem(
                (*where, "app"), f"'{pattern.app}' is not an app of this scenario ({', '.join(catalog.apps)})"
            )
        if pattern.to is not None:
            yield from self._people(pattern, where)
        if pattern.tool is None:
            # any tool (of the app, if given) taking these arguments: e.g. any email write to Bob
            specs = [
                spec
                for spec in [
                    *catalog.flat.values(),
                    *(s for group in catalog.user_qualified.values() for s in group),
                ]
                if pattern.app is None or spec.app == pattern.app
            ]
            names = {name for spec in specs for name in spec.params.model_fields}
            for name in pattern.args:
                if name not in names:
                    owner = f"tool of {pattern.app}" if pattern.app else "tool"
                    yield Problem((*where, "args", name), f"no {owner} has an argument '{name}'")
            return
        tools = pattern.tools or ()
        for position, tool in enumerate(tools):
            if self._tool_specs(tool, pattern.actor):
                continue
            choices: list[str] = {
                "user": list(catalog.user_qualified),
                "assistant": list(catalog.flat),
                "env": list(catalog.flat),
                "any": [*catalog.flat, *catalog.user_qualified],
            }[pattern.actor]
            message = catalog.unknown_tool(tool, choices)
            if pattern.actor == "user" and tool in catalog.flat:
                message += (
                    " (the user acts through screen actions, logged as app__action, e.g. email__open_email)"
                )
            yield Problem(
                (*where, "tool", position) if isinstance(pattern.tool, list) else (*where, "tool"), message
            )
        specs = self._pattern_specs(pattern)
        if not specs or any(not self._tool_specs(tool, pattern.actor) for tool in tools):
            return
        parameters = _parameters(specs)
        for name, raw in pattern.args.items():
            if name not in parameters:
                hint = did_you_mean(name, parameters)
                yield Problem(
                    (*where, "args", name),
                    f"{' or '.join(pattern.tools or ())} has no argument '{name}'.{hint} "
                    f"Arguments: {', '.join(sorted(parameters)) or 'none'}",
                )
            else:
                yield from self._fits(raw, parameters[name], (*where, "args", name))
                yield from self._id_reference(name, raw, (*where, "args", name))

    def _people(self, pattern: ActionPattern, where: Path) -> Iterator[Problem]:
        """A pattern's ``to``: people the scenario knows, reachable by the calls it names."""
        people = [pattern.to] if isinstance(pattern.to, str) else pattern.to or []
        for position, person in enumerate(people):
            place: Path = (*where, "to") if isinstance(pattern.to, str) else (*where, "to", position)
            if "@" in person:
                if not is_address(person.strip()):
                    yield Problem(place, f"'{person}' is not an email address (name@domain)")
            elif person not in self.known_ids:
                yield Problem(
                    place,
                    f"'{person}' is neither an email address nor a messaging user id of this scenario."
                    f"{did_you_mean(person, self.known_ids)}",
                )
        silent = [tool for tool in pattern.tools or () if tool not in SENDING_TOOLS]
        if silent:
            yield Problem(
                (*where, "tool"),
                f"{', '.join(silent)} tells no one anything, so 'to' never matches it; leave 'tool' out "
                f"(any email or message) or name sending tools: {', '.join(sorted(SENDING_TOOLS))}",
            )
        if pattern.app is not None and pattern.app not in ("email", "messaging"):
            yield Problem(
                (*where, "app"), f"'to' means an email or a message; app '{pattern.app}' sends neither"
            )

    def _fits(self, raw: Any, annotation: Any, where: Path) -> Iterator[Problem]:
        for place, message in matcher_problems(raw, annotation):
            yield Problem((*where, *place), message)

    def _pattern_specs(self, pattern: ActionPattern) -> list[ToolSpec]:
        return [spec for tool in pattern.tools or () for spec in self._tool_specs(tool, pattern.actor)]

    def _tool_specs(self, tool: str, actor: str) -> list[ToolSpec]:
        catalog = self.catalog
        specs: list[ToolSpec] = []
        if actor in ("user", "any"):
            specs.extend(catalog.user_qualified.get(tool, []))
        if actor in ("assistant", "env", "any") and tool in catalog.flat:
            specs.append(catalog.flat[tool])
        return specs

    def _args(
        self, spec: ToolSpec, args: Mapping[str, Any], where: Path, *, refs_allowed: bool
    ) -> Iterator[Problem]:
        refs = {name for name, value in args.items() if _references_in(value)}
        for name in sorted(refs):
            if not refs_allowed:
                yield Problem((*where, name), "values written ${...} can only be used in oracle steps")
                continue
            for step, field in _references_in(args[name]):
                if step not in self.action_ids and step not in self.event_ids:
                    hint = did_you_mean(step, [*self.action_ids, *self.event_ids])
                    yield Problem(
                        (*where, name),
                        f"'${{{step}...}}' names no earlier oracle action id or event id.{hint}",
                    )
                elif not field and step in self.action_tools:
                    yield from self._whole_record(step, self.action_tools[step], (*where, name))
        concrete = {name: value for name, value in args.items() if name not in refs}
        try:
            spec.params.model_validate(resolve_relative_times(concrete, self.start))
        except ValidationError as error:
            kept = [
                item for item in error.errors() if not (item["type"] == "missing" and item["loc"][0] in refs)
            ]
            if kept:
                yield Problem(where, describe_argument_errors(spec, kept))
        for name, value in concrete.items():
            yield from self._id_reference(name, value, (*where, name))

    def _whole_record(self, step: str, made: ToolSpec, where: Path) -> Iterator[Problem]:
        """``${step}`` where ``step``'s tool returns an object (a write's ``Done``): the call would get the
        whole object where it wants one value, and fail.
        """
        record = made.returned_record
        if record is not None:
            fields = ", ".join(record.model_fields)
            hint = f"'${{{step}.id}}' for the id of what it made" if "id" in record.model_fields else ""
            yield Problem(
                where,
                f"'${{{step}}}' passes the whole result of {made.qualified_name}, an object ({fields}), "
                f"where one value is wanted: name its field, e.g. {hint or f'${{{step}.<field>}}'}",
            )

    def _where_fields(
        self, path: str, conditions: Mapping[str, Any], item_fields: Mapping[str, Any], where: Path
    ) -> Iterator[Problem]:
        for name, raw in conditions.items():
            if name == WHERE_ANY:
                for number, alternative in enumerate(raw):
                    yield from self._where_fields(path, alternative, item_fields, (*where, name, number))
            elif name == WHERE_KEY:
                continue  # the item's key: text, matched as such
            elif name == WHERE_TEXT:
                if not has_text_fields(item_fields):
                    yield Problem(
                        (*where, name),
                        f"items of {path} have no text fields for '{WHERE_TEXT}' to read "
                        f"({', '.join(TEXT_FIELDS)}); name a field",
                    )
                yield from self._fits(raw, str, (*where, name))
            elif name not in item_fields:
                hint = did_you_mean(name, item_fields)
                yield Problem(
                    (*where, name),
                    f"items of {path} have no field '{name}'.{hint} Fields: {', '.join(item_fields)}",
                )
            else:
                yield from self._fits(raw, item_fields[name], (*where, name))

    def _id_reference(self, name: str, raw: Any, where: Path) -> Iterator[Problem]:
        """An argument or field named ``*_id`` / ``*_ids`` must name ids that exist in the seed data or
        are created by events.
        """
        if not (name.endswith("_id") or name.endswith("_ids")):
            return
        values = raw if isinstance(raw, list) else [raw]
        for value in values:
            if isinstance(value, str) and reference(value) is None and value not in self.known_ids:
                hint = did_you_mean(value, self.known_ids)
                yield Problem(where, f"'{value}' is not an id in the seed data or created by an event.{hint}")


def _forbids_proposing(pattern: ActionPattern) -> bool:
    """Whether a no_action pattern forbids the assistant's proposals."""
    return pattern.actor in ("assistant", "any") and (
        "agent_ui__send_message_to_user" in (pattern.tools or ())
        or (pattern.tool is None and pattern.app == "agent_ui")
    )


def _parameters(specs: Iterable[ToolSpec]) -> dict[str, Any]:
    """Argument name to type annotation, over ``specs``."""
    return {name: info.annotation for spec in specs for name, info in spec.params.model_fields.items()}


def is_positive(check: Check) -> bool:
    """Whether ``check`` demands that something be there (not only that something be absent)."""
    return CHECK_FORMS[check.form].positive(check.body)


def needs_assistant(check: Check) -> bool:
    """Whether ``check`` can only hold through the assistant's own work."""
    form = CHECK_FORMS[check.form]
    return form.positive(check.body) and form.needs_assistant(check.body)


def _collect_ids(data: Any, into: set[str]) -> None:
    """Every id in seed data: keys of mappings, values of ``*_id`` fields, members of ``*_ids`` lists."""
    if isinstance(data, Mapping):
        for key, value in data.items():
            into.add(str(key))
            if isinstance(value, str) and str(key).endswith("_id"):
                into.add(value)
            elif isinstance(value, list) and str(key).endswith("_ids"):
                into.update(v for v in value if isinstance(v, str))
            _collect_ids(value, into)
    elif isinstance(data, list):
        for value in data:
            _collect_ids(value, into)


def _pydantic_message(item: Any) -> str:
    if item["type"] == "missing":
        return "required field missing"
    if item["type"] == "extra_forbidden":
        return "unknown field"
    return str(item["msg"])


def _where_conditions(conditions: Mapping[str, Any], where: Path) -> Iterator[tuple[Path, Any]]:
    """Every field condition of a ``where``, those inside ``any_of`` included, with where it is."""
    for name, raw in conditions.items():
        if name == WHERE_ANY:
            for number, alternative in enumerate(raw):
                yield from _where_conditions(alternative, (*where, name, number))
        else:
            yield (*where, name), raw


def _references_in(value: Any) -> list[tuple[str, str]]:
    """The ``${step.field}`` references an argument holds: itself, or items of a list (files to attach)."""
    if isinstance(value, list):
        return [found for item in value if (found := reference(item)) is not None]
    found = reference(value)
    return [] if found is None else [found]


def _reads_field(params: type[BaseModel], field: str) -> bool:
    """Whether a judge with ``field`` reads something of a call with these ``params``: an argument, or a
    field inside an argument that is itself a set of fields (an edit's ``updates``: its ``description``).
    """
    if field in params.model_fields:
        return True
    for info in params.model_fields.values():
        for kind in (info.annotation, *get_args(info.annotation)):
            if isinstance(kind, type) and issubclass(kind, BaseModel) and field in kind.model_fields:
                return True
    return False
