"""Noise: distractor events (promotions, group chatter, spam) arriving as a Poisson process.

The corpus is package data (``pare/sim/data/noise.yaml``): templates per app whose ``{slot[field]}``
placeholders are filled from the corpus's slot lists, so the number of distinct items runs into the
hundreds of thousands while every item reads like a real message. Within an episode no item repeats.

Noise events are routed like real events: each is an ``env`` call of the app's own arrival method
(``email.receive_email``, ``messaging.receive_message``), so it lands in the app's data and raises the
same notifications a real email or message would.
"""

from __future__ import annotations

import random
import string
from dataclasses import dataclass
from datetime import datetime, timedelta
from functools import cache
from importlib import resources
from typing import Any

import yaml
from pydantic import BaseModel, ConfigDict, Field

from pare.errors import SimulationBug
from pare.sim.events import EventAction

NOISE_EVENT_PREFIX = "noise-"
"""How a distractor's event id begins (``noise-00003``): what tells the world's noise from its story."""

NOISE_TOOLS: dict[str, str] = {"email": "receive_email", "messaging": "receive_message"}
"""For each app that can receive noise, the env method a noise item calls."""


class NoiseTemplate(BaseModel):
    """One kind of distractor: the fields of the arrival call, each a template string."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    kind: str = Field(description="promotion, newsletter, spam, group_chatter, service, ...")
    fields: dict[str, str] = Field(description="Arguments of the arrival call, as templates.")


class NoiseCorpus(BaseModel):
    """Slot values and per-app templates."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    slots: dict[str, list[Any]]
    apps: dict[str, list[NoiseTemplate]]

    def templates_for(self, apps: set[str]) -> list[tuple[str, NoiseTemplate]]:
        """Every template of the apps in ``apps``, in a fixed order."""
        return [(app, t) for app in sorted(self.apps) if app in apps for t in self.apps[app]]


@cache
def default_corpus() -> NoiseCorpus:
    """The corpus shipped with PARE."""
    text = resources.files("pare.sim").joinpath("data/noise.yaml").read_text(encoding="utf-8")
    return NoiseCorpus.model_validate(yaml.safe_load(text))


def _placeholders(template: str) -> list[str]:
    return [name.split("[")[0] for _, name, _, _ in string.Formatter().parse(template) if name]


@dataclass(frozen=True, slots=True)
class NoiseArrival:
    """One distractor: when it arrives and the call it makes."""

    event_id: str
    time: datetime
    action: EventAction
    kind: str


class NoiseStream:
    """Poisson arrivals of distractors at ``rate_per_minute`` simulated events per minute.

    Arrival times come from one seeded stream and contents from another, so the same seed gives the same
    noise whatever the actors do.
    """

    def __init__(
        self,
        *,
        rate_per_minute: float,
        start: datetime,
        apps: set[str],
        arrivals: random.Random,
        contents: random.Random,
        corpus: NoiseCorpus | None = None,
    ) -> None:
        if rate_per_minute < 0:
            raise ValueError(f"noise rate must be >= 0 events per minute, got {rate_per_minute}")
        self.rate_per_minute = rate_per_minute
        self._arrivals = arrivals
        self._contents = contents
        self._templates: list[tuple[str, NoiseTemplate]] = []
        self._slots: dict[str, list[Any]] = {}
        if rate_per_minute > 0:  # the corpus is read only when noise is on
            corpus = corpus or default_corpus()
            self._templates = corpus.templates_for({a for a in apps if a in NOISE_TOOLS})
            self._slots = corpus.slots
        self._seen: set[tuple[str, ...]] = set()
        self._count = 0
        self._next: datetime | None = None
        if rate_per_minute > 0 and self._templates:
            self._next = start + self._gap()

    def _gap(self) -> timedelta:
        return timedelta(minutes=self._arrivals.expovariate(self.rate_per_minute))

    @property
    def next_time(self) -> datetime | None:
        """When the next distractor arrives, or ``None`` when noise is off."""
        return self._next

    def skip_until(self, moment: datetime) -> None:
        """Let no distractor arrive before ``moment``: the stream restarts there.

        For jumps over idle time. Arrivals are a Poisson process, so restarting at ``moment`` draws the
        same kind of future as carrying on, without materialising hours of distractors nobody was around
        to see.
        """
        if self._next is not None and self._next < moment:
            self._next = moment + self._gap()

    def pop(self) -> NoiseArrival:
        """The next distractor; the stream moves on to the one after."""
        if self._next is None:
            raise SimulationBug("no noise is scheduled")
        app, template, args = self._draw()
        arrival = NoiseArrival(
            event_id=f"{NOISE_EVENT_PREFIX}{self._count:05d}",
            time=self._next,
            action=EventAction(app=app, tool=NOISE_TOOLS[app], args=args),
            kind=template.kind,
        )
        self._count += 1
        self._next = self._next + self._gap()
        return arrival

    def _draw(self) -> tuple[str, NoiseTemplate, dict[str, str]]:
        for _ in range(1000):
            app, template = self._contents.choice(self._templates)
            values: dict[str, Any] = {}
            for text in template.fields.values():
                for slot in _placeholders(text):
                    if slot not in values:
                        values[slot] = self._contents.choice(self._slots[slot])
            args = {name: text.format(**values) for name, text in template.fields.items()}
            key = (app, *args.values())
            if key not in self._seen:
                self._seen.add(key)
                return app, template, args
        raise SimulationBug("the noise corpus has run out of distinct items for this episode")
