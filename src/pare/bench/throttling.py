"""How a run tells that it is being rate limited: a line for the progress bar, lines for the run summary."""

from __future__ import annotations

from collections.abc import Sequence

from pare.agents.models.limiter import LimiterState

HELD_BY_TEXT = {
    "requests_per_minute": "paced by requests_per_minute",
    "tokens_per_minute": "paced by tokens_per_minute",
}


def endpoint_name(state: LimiterState) -> str:
    """The endpoint named by the roles that call it: ``user endpoint``, ``user+assistant endpoint``."""
    roles = list(state.roles)
    if "observe" in roles and "execute" in roles:  # the assistant's two modes on one endpoint
        roles[roles.index("observe")] = "assistant"
        roles.remove("execute")
    return f"{'+'.join(roles) or state.endpoint} endpoint"


def throttling_status(states: Sequence[LimiterState]) -> str:
    """The progress bar's note on rate limiting now, empty when nothing is held back, e.g.
    ``throttled: user endpoint at 4/16, 3 queued, waiting 2.0 s for rate limit``.
    """
    parts = []
    for state in states:
        if not state.throttled:
            continue
        text = f"{endpoint_name(state)} at {state.limit}/{state.max_concurrency}"
        if state.waiting:
            text += f", {state.waiting} queued"
        if state.paused_s > 0:
            text += f", waiting {state.paused_s:.1f} s for rate limit"
        elif state.held_by in HELD_BY_TEXT:
            text += f", {HELD_BY_TEXT[state.held_by]}"
        parts.append(text)
    return "throttled: " + "; ".join(parts) if parts else ""


def throttling_summary(states: Sequence[LimiterState], seconds: float) -> list[str]:
    """One line per endpoint that was rate limited during a session of ``seconds``: the 429s, the time
    calls were held back by rate limiting (a pause, a cut limit or a budget), the limit at the end.
    """
    lines = []
    for state in states:
        if not state.rate_limited and state.throttled_s <= 0:
            continue
        share = f" ({state.throttled_s / seconds:.0%} of the session)" if seconds > 0 else ""
        answers = f"{state.rate_limited} rate-limit answer{'' if state.rate_limited == 1 else 's'} (429)"
        lines.append(
            f"throttling: {endpoint_name(state)}: {answers}, calls held back for {state.throttled_s:.1f} s"
            f"{share}; concurrency {state.limit}/{state.max_concurrency} at the end, cut {state.cuts} "
            f"time{'' if state.cuts == 1 else 's'}"
        )
    return lines
