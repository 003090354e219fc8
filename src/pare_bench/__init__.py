"""PARE's verifiers environment under the id the verifiers library loads it by (``pare-bench``).

The library imports an environment's id as a top-level module and takes the classes it exports; the
classes live in :mod:`pare.training.verifiers` (the ``verifiers`` extra).
"""

from pare.training.verifiers import PareEnv, PareHarness, PareTaskset, load_environment

__all__ = ["PareEnv", "PareHarness", "PareTaskset", "load_environment"]
