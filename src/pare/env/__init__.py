"""The environment: apps and kernel together, and what each actor may do and see."""

from pare.env.config import EnvConfig, WorldSettings
from pare.env.environment import Environment
from pare.env.views import AssistantObservation, NamedTool, ToolResult, TurnMark, UserView, describe_action

__all__ = [
    "AssistantObservation",
    "EnvConfig",
    "Environment",
    "NamedTool",
    "ToolResult",
    "TurnMark",
    "UserView",
    "WorldSettings",
    "describe_action",
]
