"""A seeded random user: picks an available action and plausible arguments at every step.

Used to exercise every screen of every app (the FSM sweep tests, ``benchmarks/kernel.py``) and as the
simplest baseline policy. Arguments are drawn from each tool's JSON Schema; strings come from the values
of the foreground app's data (ids, names, addresses), so opened items mostly exist and forms mostly
validate, while some calls still fail the way a careless user's would.
"""

from __future__ import annotations

import random
from datetime import UTC, datetime, timedelta
from typing import Any

from pare.env.environment import Environment
from pare.env.views import NamedTool, ToolResult
from pare.sim.log import AssistantMode

_WORDS = ("meeting", "dinner", "hello", "tomorrow", "invoice", "Alice", "INBOX", "work", "2025-03-04 10:00")


class RandomAssistant:
    """Calls a random tool of the assistant's current mode with plausible arguments (``wait`` and
    proposals left out): a load generator for the flat API of every app.
    """

    def __init__(self, rng: random.Random, mode: AssistantMode = "execute") -> None:
        self.mode: AssistantMode = mode
        self._arguments = RandomUser(rng)
        self.rng = rng

    def step(self, env: Environment) -> ToolResult:
        """Make one random call as the assistant."""
        tool, args = self.choose(env)
        return env.call("assistant", tool.name, args, mode=self.mode)

    def choose(self, env: Environment) -> tuple[NamedTool, dict[str, Any]]:
        """A random app tool of the current mode and plausible arguments for it."""
        tools = [t for t in env.assistant_tools(self.mode) if t.spec.app not in ("system", "agent_ui")]
        tool = self.rng.choice(tools)
        self._arguments.now = env.clock.now
        return tool, self._arguments.arguments(env, tool)


class RandomUser:
    """Chooses uniformly among the tools available now; ``wait`` is left out so the walk keeps moving."""

    def __init__(self, rng: random.Random) -> None:
        self.rng = rng
        self._by_app: dict[str, tuple[int, list[str], dict[str, list[str]]]] = {}
        self._strings: list[str] | None = None
        self._named: dict[str, list[str]] = {}
        self._recent: dict[str, list[str]] = {}
        self.now = datetime(2025, 1, 1, tzinfo=UTC)

    def step(self, env: Environment) -> ToolResult:
        """Take one random action as the user."""
        tool = self.choose(env)
        result = env.call("user", tool.name, self.arguments(env, tool))
        seen: dict[str, list[str]] = {}
        _collect_ids(result.value, seen)
        if seen:  # a user types the ids they were just shown
            self._recent = {field: sorted(set(values)) for field, values in seen.items()}
        return result

    def choose(self, env: Environment) -> NamedTool:
        """A tool available now, uniformly (``wait`` excluded)."""
        self.now = env.clock.now
        return self.rng.choice([t for t in env.user_tools() if t.name != "wait"])

    def arguments(self, env: Environment, tool: NamedTool) -> dict[str, Any]:
        """Plausible arguments for ``tool`` in ``env``'s current state.

        Ids come from the tool's own app when it is an app tool (the assistant's flat API), else from
        the app on screen.
        """
        if tool.name in ("open_app", "switch_app"):
            candidates = env.system.openable_apps() if tool.name == "open_app" else env.system.background
            return {"app_name": self.rng.choice(candidates or ["none"])}
        ids, strings = self._pools(env, tool.spec.app if tool.spec.app in env.apps else None)
        screen = env.system.current_screen()
        if screen is not None:  # what is on the screen (a draft's attendees) is what a user would type
            on_screen: list[str] = []
            _harvest(screen.model_dump(mode="json"), [], on_screen)
            strings = strings + on_screen * 5
        schema = tool.spec.parameters_schema
        definitions = schema.get("$defs", {})
        args: dict[str, Any] = {}
        required = set(schema.get("required", []))
        for name, prop in schema["properties"].items():
            if name in required or self.rng.random() < 0.3:
                args[name] = self._value(name, prop, definitions, ids, strings, depth=0)
        return args

    def _pools(self, env: Environment, app_name: str | None = None) -> tuple[list[str], list[str]]:
        """Ids from the app on screen (kept current); strings (addresses, paths, names) from every app's
        data as it was when the walk started.
        """
        if self._strings is None:
            strings: list[str] = []
            for app in env.apps.values():
                _harvest(app.snapshot(), [], strings)
            pool = sorted(set(strings))
            self.rng.shuffle(pool)
            self._strings = pool[:400] or list(_WORDS)
        if app_name is None or app_name in ("system", "agent_ui"):
            app_name = env.system.foreground or "system"
        app = env.apps[app_name]
        cached = self._by_app.get(app_name)
        if cached is None or cached[0] != app.write_count:  # re-read the app's ids after it changed
            found: list[str] = []
            named: dict[str, list[str]] = {}
            _harvest(app.snapshot(), found, [], named)
            by_field = {field: sorted(set(values)) for field, values in named.items()}
            cached = (app.write_count, sorted(set(found)) or ["none"], by_field)
            self._by_app[app_name] = cached
        self._named = cached[2]
        return cached[1], self._strings

    def _value(
        self,
        name: str,
        prop: dict[str, Any],
        defs: dict[str, Any],
        ids: list[str],
        strings: list[str],
        depth: int,
    ) -> Any:
        if "$ref" in prop:
            prop = defs[prop["$ref"].rsplit("/", 1)[-1]]
        if "anyOf" in prop:
            options = [p for p in prop["anyOf"] if p.get("type") != "null"] or prop["anyOf"]
            prop = self.rng.choice(options)
        kind = prop.get("type")
        if "enum" in prop:
            return self.rng.choice(prop["enum"])
        if kind == "integer":
            return self.rng.randint(0, 4)
        if kind == "number":
            return round(self.rng.uniform(0, 100), 2)
        if kind == "boolean":
            return self.rng.random() < 0.5
        if kind == "array":
            item = prop.get("items", {"type": "string"})
            return [
                self._value(name, item, defs, ids, strings, depth + 1) for _ in range(self.rng.randint(1, 2))
            ]
        if kind == "object" and depth < 2:
            props = prop.get("properties", {})
            chosen = [k for k in props if self.rng.random() < 0.5] or list(props)[:1]
            return {k: self._value(k, props[k], defs, ids, strings, depth + 1) for k in chosen}
        if kind == "null":
            return None
        if prop.get("format") in ("date-time", "date"):
            moment = self.now + timedelta(minutes=15 * self.rng.randint(-200, 400))
            return moment.date().isoformat() if prop["format"] == "date" else moment.isoformat()
        if name.endswith("_id") or name == "id":
            recent = self._recent.get(name)
            if recent and self.rng.random() < 0.6:
                return self.rng.choice(recent)
            typed = self._named.get(name)
            return self.rng.choice(typed if typed and self.rng.random() < 0.8 else ids)
        if self.rng.random() < 0.2:
            return self.rng.choice(_WORDS)
        return self.rng.choice(strings)


def _harvest(
    value: Any, ids: list[str], strings: list[str], named: dict[str, list[str]] | None = None
) -> None:
    if isinstance(value, dict):
        for key, item in value.items():
            if isinstance(item, dict):
                ids.append(key)
                if named is not None:  # a record keyed by its own id field: remember which kind of id it is
                    for field, field_value in item.items():
                        if field_value == key and field.endswith("_id"):
                            named.setdefault(field, []).append(key)
                if key.startswith("/"):  # a file path keyed by itself: what a user types to attach it
                    strings.append(key)
            _harvest(item, ids, strings, named)
    elif isinstance(value, list):
        for item in value:
            _harvest(item, ids, strings, named)
    elif isinstance(value, str) and len(value) <= 80:
        strings.append(value)
        if "-" in value and " " not in value and len(value) <= 40:
            ids.append(value)


def _collect_ids(value: Any, found: dict[str, list[str]]) -> None:
    """Every ``*_id`` field anywhere in ``value``, by field name."""
    if isinstance(value, dict):
        for key, item in value.items():
            if key.endswith("_id") and isinstance(item, str):
                found.setdefault(key, []).append(item)
            else:
                _collect_ids(item, found)
    elif isinstance(value, list):
        for item in value:
            _collect_ids(item, found)
