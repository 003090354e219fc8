"""The turn protocol: the one declaration of its settings, their bounds and PARE's defaults.

Everything else derives from :class:`TurnBudget`: the episode loop's settings add the world to it
(:class:`pare.bench.EpisodeSettings`), a run configuration's protocol adds presets and the model actors'
format re-asks to it (:class:`pare.protocols.ProtocolSettings`), and the actors are told it at the
start of each episode. It is a small module of its own, low in the layers, so that the scenario loader
(which checks interventions against the limits) does not import the actors.
"""

from __future__ import annotations

from datetime import timedelta
from typing import Literal

from pydantic import BaseModel, ConfigDict, Field, model_validator

MAX_TURNS = 1_000
"""The most turns an episode may be given (the paper's protocol uses 10)."""
MAX_STEPS = 200
"""The most actions one actor may be given per turn, or to carry out a task."""
MAX_TURN_DURATION = timedelta(days=1)
MAX_REACTION_HORIZON = timedelta(days=30)

UserPromptWording = Literal["pare", "paper"]
"""How the user's prompt asks it to judge proposals: PARE's wording, or the paper's appendix word for word."""

UserTrust = Literal["demanding", "trusting", "busy", "sceptical"]
"""How readily the person PARE's user prompt plays trusts the assistant's proposals (a persona of trust):
``demanding`` accepts only what names concretely what they need and may check one thing first (PARE's
wording as it always was); ``trusting`` accepts what looks plausible without checking; ``busy`` answers at
once from what it already knows and rarely checks; ``sceptical`` checks in its apps before every answer."""
USER_TRUST: tuple[UserTrust, ...] = ("demanding", "trusting", "busy", "sceptical")


class TurnBudget(BaseModel):
    """The turn protocol's settings, which each actor is told: how long the session lasts, how many
    actions a turn allows, how long a proposal waits for its answer, how the clock moves, and how the
    user is asked to judge proposals. Every count is configurable within bounds that keep an episode
    finite; the defaults are PARE's protocol (``--protocol pare``).
    """

    model_config = ConfigDict(extra="forbid", frozen=True, allow_inf_nan=False)

    max_turns: int = Field(default=10, ge=1, le=MAX_TURNS, description="Turns before the episode is cut off.")
    user_steps: int = Field(default=1, ge=1, le=MAX_STEPS, description="User actions per turn.")
    observe_steps: int = Field(
        default=5, ge=1, le=MAX_STEPS, description="Assistant actions per turn in observe mode."
    )
    execute_steps: int = Field(
        default=10, ge=1, le=MAX_STEPS, description="Assistant actions to carry out an accepted task."
    )
    # 4, not 3: checking "the one thing you need first" in another app takes three actions (home, open the
    # app, open the item) before the answer; docs/what-models-see.md, "How long a proposal waits"
    proposal_ttl_turns: int | None = Field(
        default=4,
        ge=1,
        le=MAX_TURNS,
        description="Turns a proposal may wait for an answer before it is withdrawn; null: it never is "
        "(the paper's protocol).",
    )
    turn_duration: timedelta = Field(
        default=timedelta(minutes=1),
        gt=timedelta(0),
        le=MAX_TURN_DURATION,
        description="Simulated time one turn takes when someone acted.",
    )
    attention_turns: int = Field(
        default=3,
        ge=1,
        le=MAX_TURNS,
        description="Turns the world's timeline waits, after anything arrived (or the start), for a user "
        "who keeps using the phone while the assistant has nothing in hand; then it moves on to its next "
        "event whatever the user does.",
    )
    reaction_horizon: timedelta = Field(
        default=timedelta(days=1),
        ge=timedelta(0),
        le=MAX_REACTION_HORIZON,
        description="After the last turn, reactions already set in motion are delivered if due within "
        "this much simulated time of its end.",
    )
    user_prompt: UserPromptWording = Field(
        default="pare",
        description="How the user's prompt asks it to judge proposals: 'pare' (a demanding user who may "
        "check one thing first) or 'paper' (the appendix's EXTREMELY STRICT wording).",
    )
    user_trust: UserTrust = Field(
        default="demanding",
        description="The persona of trust PARE's user prompt plays: demanding (accepts only a concrete "
        "proposal that fits, may check one thing first), trusting (accepts what looks plausible without "
        "checking), busy (answers at once, rarely checks) or sceptical (checks before every answer).",
    )

    @model_validator(mode="after")
    def _trust_needs_our_wording(self) -> TurnBudget:
        if self.user_prompt == "paper" and self.user_trust != "demanding":
            raise ValueError(
                f"user_trust '{self.user_trust}' words PARE's user prompt, but user_prompt is 'paper' (the "
                "appendix's own strict wording, kept word for word): use user_prompt 'pare' with a persona "
                "of trust, or leave user_trust at 'demanding'"
            )
        return self

    @property
    def turn_minutes(self) -> float:
        """Simulated minutes one turn takes when someone acted (time jumps further when everyone waits)."""
        return self.turn_duration.total_seconds() / 60

    def budget(self) -> TurnBudget:
        """Only the turn protocol's settings (a subclass's extra fields left out): what the actors are told,
        and what prompts are cached by.
        """
        if type(self) is TurnBudget:
            return self
        return TurnBudget.model_validate({name: getattr(self, name) for name in TurnBudget.model_fields})


DEFAULT_BUDGET = TurnBudget()
