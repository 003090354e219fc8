"""Actors: the policies that play the user and the proactive assistant, and what they need to do it.

* :mod:`pare.agents.policy` — the interfaces the turn loop calls, and the silent policies;
* :mod:`pare.agents.llm` — the model-backed user simulator and assistant (observe and execute);
* :mod:`pare.agents.prompts` — their system prompts; :mod:`pare.agents.actions` — the text action format;
* :mod:`pare.agents.models` — the model client (backends, retries, record/replay cache, usage and cost);
* :mod:`pare.agents.judge` — a model as the judge of free-text checks;
* :mod:`pare.agents.scripted` — a scripted model for tests and demos.
"""

from typing import TYPE_CHECKING

from pare._lazy import lazy_exports

if TYPE_CHECKING:
    from pare.agents.actions import ParsedAction, format_action, parse_action, to_action
    from pare.agents.judge import ModelJudge
    from pare.agents.llm import ChatModel, LLMAssistant, LLMUser
    from pare.agents.policy import (
        ASSISTANT_WAIT,
        SEND_MESSAGE,
        WAIT,
        Action,
        AssistantPolicy,
        Ending,
        SilentAssistant,
        SilentUser,
        Task,
        UserPolicy,
    )
    from pare.agents.scripted import ScriptedModel, ScriptExhausted

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "ParsedAction": "actions",
        "format_action": "actions",
        "parse_action": "actions",
        "to_action": "actions",
        "ModelJudge": "judge",
        "ChatModel": "llm",
        "LLMAssistant": "llm",
        "LLMUser": "llm",
        "ASSISTANT_WAIT": "policy",
        "SEND_MESSAGE": "policy",
        "WAIT": "policy",
        "Action": "policy",
        "AssistantPolicy": "policy",
        "Ending": "policy",
        "SilentAssistant": "policy",
        "SilentUser": "policy",
        "Task": "policy",
        "UserPolicy": "policy",
        "ScriptedModel": "scripted",
        "ScriptExhausted": "scripted",
    },
)

__all__ = [
    "ASSISTANT_WAIT",
    "SEND_MESSAGE",
    "WAIT",
    "Action",
    "AssistantPolicy",
    "ChatModel",
    "Ending",
    "LLMAssistant",
    "LLMUser",
    "ModelJudge",
    "ParsedAction",
    "ScriptExhausted",
    "ScriptedModel",
    "SilentAssistant",
    "SilentUser",
    "Task",
    "UserPolicy",
    "format_action",
    "parse_action",
    "to_action",
]
