"""What each role's model requests carry during one run, shared by every client of the run and recorded in
its manifest.

A run keeps one :class:`~pare.agents.models.request_params.RequestParams` per role: the role's clients
share it, so a refusal one call learns is known to every later call. The record (:meth:`RunRequests.record`)
goes to the manifest when the run starts and again each time a refusal is learned; the next session of
the run starts from the refusals the manifest holds (:func:`learned_refusals`). Episodes played in other
processes (Ray tasks) start from what the run knows and send back what they learned
(:meth:`RunRequests.absorb`), so the driver warns and records for them.
"""

from __future__ import annotations

import contextlib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

from pare.agents.models.capabilities import Adjustment
from pare.agents.models.request_params import RequestParams

if TYPE_CHECKING:
    from pare.bench.runconfig import RunConfig
    from pare.bench.store import RunStore

REQUESTS = "requests"
"""The manifest's key for the record (see :meth:`pare.bench.store.RunStore.record_requests`)."""

Learned = Mapping[str, Sequence[Adjustment]]
"""Refusals learned from providers, by role."""


@dataclass
class RunRequests:
    """The request parameters of every configured role of one run."""

    params: dict[str, RequestParams] = field(default_factory=dict)

    @classmethod
    def create(cls, config: RunConfig, learned: Learned | None = None) -> RunRequests:
        """One per configured role, knowing the refusals ``learned`` before (by role)."""
        return cls(
            {
                role: RequestParams(model, role, (learned or {}).get(role, ()))
                for role, model in config.models.roles().items()
            }
        )

    def record(self) -> dict[str, Any]:
        """Per role, what its requests carry and how that differs from its configuration."""
        return {role: params.record() for role, params in self.params.items()}

    def record_in(self, store: RunStore) -> None:
        """Record in ``store``'s manifest now, and again whenever a role learns a refusal."""
        store.record_requests(self.record())
        for params in self.params.values():
            params.subscribe(lambda _: store.record_requests(self.record()))

    def learned(self) -> dict[str, list[Adjustment]]:
        """The refusals learned so far, by role."""
        found = {role: [a for a in params.adjustments if a.learned] for role, params in self.params.items()}
        return {role: adjustments for role, adjustments in found.items() if adjustments}

    def absorb(self, learned: Learned) -> None:
        """Take in refusals learned elsewhere (another process); each new one is warned about and recorded."""
        for role, adjustments in learned.items():
            params = self.params.get(role)
            if params is not None:
                for adjustment in adjustments:
                    params.learn(adjustment)


def learned_refusals(manifest: Mapping[str, Any]) -> dict[str, list[Adjustment]]:
    """The parameter refusals learned in earlier sessions of a run, by role, from its manifest."""
    learned: dict[str, list[Adjustment]] = {}
    for role, record in (manifest.get(REQUESTS) or {}).items():
        adjusted = record.get("adjusted", []) if isinstance(record, dict) else []
        for item in adjusted:
            if isinstance(item, dict) and item.get("learned"):
                with contextlib.suppress(ValueError):  # a record this PARE cannot read is learnt again
                    learned.setdefault(str(role), []).append(Adjustment.from_json(item))
    return learned
