"""Gymnasium environments for PARE (the ``gym`` extra); importing this module registers them.

* ``pare/ProactiveAssistant-v0`` (:class:`ProactiveAssistantEnv`): the agent plays the proactive assistant,
  the user is the oracle or a configured model;
* ``pare/User-v0`` (:class:`UserEnv`): the agent plays the user, the assistant is the oracle or a
  configured model.

``gymnasium.make("pare.gym:pare/ProactiveAssistant-v0")`` imports this module and makes the environment in
one call. Observations and actions are text, rewards and the rest as in :mod:`pare.training.envs`, whose
asynchronous environments these wrap (use those to step many environments at once).
"""

from __future__ import annotations

from pare.install import install_command

try:
    import gymnasium
except ImportError as error:  # the extra is not installed: say how to get it
    raise ImportError(f"pare.gym needs Gymnasium (the gym extra): {install_command('gym')}") from error

from pare.gym.envs import ProactiveAssistantEnv, TextSpace, UserEnv

__all__ = ["ASSISTANT_ENV_ID", "USER_ENV_ID", "ProactiveAssistantEnv", "TextSpace", "UserEnv"]

ASSISTANT_ENV_ID = "pare/ProactiveAssistant-v0"
USER_ENV_ID = "pare/User-v0"

for _env_id, _entry_point in (
    (ASSISTANT_ENV_ID, "pare.gym.envs:ProactiveAssistantEnv"),
    (USER_ENV_ID, "pare.gym.envs:UserEnv"),
):
    if _env_id not in gymnasium.registry:  # a module imported again (reloaded) registers nothing twice
        gymnasium.register(id=_env_id, entry_point=_entry_point, disable_env_checker=False)
