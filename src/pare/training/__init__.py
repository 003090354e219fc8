"""Training interfaces: PARE's episodes stepped by an agent outside the turn loop.

* :mod:`pare.training.driver` — the episode loop run as a task whose agent side waits for answers given from
  outside (the inverse of :func:`~pare.bench.episode.arun_episode` driving its policies);
* :mod:`pare.training.envs` — the asynchronous environments (``reset`` / ``step`` on text) built on it;
* :mod:`pare.training.setup` — what an environment plays: its scenarios, protocol and the other role;
* :mod:`pare.training.verifiers` — ``load_environment``: rollouts and a rubric in the verifiers library's
  shape, without that library.

:mod:`pare.gym` registers the Gymnasium environments (the ``gym`` extra) on top of these.
"""
