"""What one role's requests carry: the configured parameters, adjusted to what the model accepts.

A :class:`RequestParams` starts from the parameters the configuration sets, applies what is known about
the model beforehand (:func:`~pare.agents.models.capabilities.known_adjustments`) and learns from the
provider's refusals as the run goes (:meth:`RequestParams.learn`), so a refused parameter costs one
failed round trip per run, not one per call. Every adjustment is logged once, as a warning that says
what is sent instead and that the configured setting is not honoured when a parameter is dropped. The
clients of one role share one (the judge's clients come and go; what they learnt stays), and listeners
hear of each adjustment learned (the runner records them in the run's manifest).
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Iterable
from typing import Any

from pare.agents.models.capabilities import Adjustment, apply_adjustments, known_adjustments
from pare.agents.models.config import ModelConfig

logger = logging.getLogger("pare.models")

Listener = Callable[["RequestParams"], None]


class RequestParams:
    """The request parameters of one role's model for one run, and how they came to be (thread-safe)."""

    def __init__(self, config: ModelConfig, role: str, learned: Iterable[Adjustment] = ()) -> None:
        self.config = config
        self.role = role
        self._lock = threading.Lock()
        self._known: list[Adjustment] | None = None  # computed on first use (litellm may need importing)
        self._learned: list[Adjustment] = list(learned)
        self._warned: set[tuple[str, str]] = set()
        self._listeners: list[Listener] = []

    def __repr__(self) -> str:
        return f"RequestParams(role={self.role!r}, model={self.config.model!r}, sent={self.sent()!r})"

    @property
    def configured(self) -> dict[str, Any]:
        """The parameters the configuration sets."""
        return dict(self.config.request_params())

    @property
    def adjustments(self) -> list[Adjustment]:
        """Every adjustment applied, those known beforehand first, then those learned, in order."""
        with self._lock:
            return self._adjustments()

    def _adjustments(self) -> list[Adjustment]:
        if self._known is None:
            self._known = known_adjustments(self.config)
        return [*self._known, *self._learned]

    def sent(self) -> dict[str, Any]:
        """The parameters each request carries now (warning once about each adjustment the first time)."""
        with self._lock:
            adjustments = self._adjustments()
            fresh = [a for a in adjustments if (a.param, a.action) not in self._warned]
            self._warned.update((a.param, a.action) for a in fresh)
            sent = apply_adjustments(self.config.request_params(), adjustments)
        for adjustment in fresh:
            self._warn(adjustment)
        return sent

    def learn(self, adjustment: Adjustment) -> bool:
        """Adjust every later request as ``adjustment`` says; ``False`` when it was known already."""
        with self._lock:
            adjustments = self._adjustments()
            if any(
                a.param == adjustment.param and adjustment.action in (a.action, "renamed")
                for a in adjustments
            ):
                return False  # learnt already (concurrent calls meet the same refusal)
            self._learned.append(adjustment)
            self._warned.add((adjustment.param, adjustment.action))
            listeners = list(self._listeners)
        self._warn(adjustment)
        for listener in listeners:
            listener(self)
        return True

    def subscribe(self, listener: Listener) -> None:
        """Call ``listener(self)`` after each adjustment learned."""
        with self._lock:
            self._listeners.append(listener)

    def record(self) -> dict[str, Any]:
        """What the requests carry, as JSON for the run's manifest: the model, the configured parameters,
        those sent now and every adjustment with its reason.
        """
        sent = self.sent()
        return {
            "model": self.config.model,
            "backend": self.config.backend,
            "configured": self.configured,
            "sent": sent,
            "adjusted": [adjustment.to_json() for adjustment in self.adjustments],
        }

    def _warn(self, adjustment: Adjustment) -> None:
        configured = self.config.request_params()
        value = configured.get(adjustment.param)
        setting = f"{adjustment.param}={value!r}" if adjustment.param in configured else adjustment.param
        where = f"{self.role} model '{self.config.model}'"
        if adjustment.action == "renamed":
            outcome = f"{setting} is sent as {adjustment.to}"
        else:
            outcome = f"{setting} is not sent: the configured setting is not honoured"
        if adjustment.learned:
            logger.warning("%s: %s for the rest of the run: %s", where, outcome, adjustment.why)
        else:
            logger.warning("%s: %s (%s)", where, outcome, adjustment.why)
