"""Training interfaces: PARE's episodes stepped by an agent outside the turn loop.

* :mod:`pare.training.driver` — the episode loop run as a task whose agent side waits for answers given from
  outside (the inverse of :func:`~pare.bench.episode.arun_episode` driving its policies);
* :mod:`pare.training.envs` — the asynchronous environments (``reset`` / ``step`` on text) built on it;
* :mod:`pare.training.setup` — what an environment plays: its scenarios, protocol and the other role;
* :mod:`pare.training.rollout` — one episode with the assistant played by a model behind an
  OpenAI-compatible client;
* :mod:`pare.training.verifiers` — ``load_environment``: the verifiers library's environment (the
  ``verifiers`` extra), its rollouts PARE's turn loop, its rewards PARE's verdict.

:mod:`pare.gym` registers the Gymnasium environments (the ``gym`` extra) on top of these.
"""
