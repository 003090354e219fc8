"""Actors: the policies that play the user and the proactive assistant."""

from pare.agents.policy import (
    ASSISTANT_WAIT,
    SEND_MESSAGE,
    WAIT,
    Action,
    AssistantPolicy,
    SilentAssistant,
    SilentUser,
    Task,
    UserPolicy,
)

__all__ = [
    "ASSISTANT_WAIT",
    "SEND_MESSAGE",
    "WAIT",
    "Action",
    "AssistantPolicy",
    "SilentAssistant",
    "SilentUser",
    "Task",
    "UserPolicy",
]
