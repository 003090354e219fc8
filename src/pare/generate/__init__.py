"""Scenario generation: the paper's four-stage pipeline on PARE's scenario format, with the gate as judge.

A generator model writes a candidate in four stages (the story; the apps' initial data; the events with
the oracle's user and assistant actions; the validation: goals and variants). After each stage from the
second on, the candidate is loaded and played through the self-test gate as far as it has got, and the
problems go back to the model a bounded number of times. The story is checked for uniqueness against the
library (``pare scenarios similar``'s measure as a filter, then a model judge). Passing candidates are
written with a provenance header for a person to review (``pare scenarios review``).

.. code-block:: python

    from pare.agents.models import ModelConfig
    from pare.generate import GenerateConfig, generate

    config = GenerateConfig(apps=["email", "calendar"], count=5, output="generated",
                            generator=ModelConfig(model="gpt-4o"))
    summary = generate(config)
"""

from pare.generate.config import GenerateConfig, build_generate_config
from pare.generate.folder import CandidateRecord, GenerationFolder, read_provenance
from pare.generate.pipeline import generate_candidate
from pare.generate.review import PendingCandidate, accept, pending, reject
from pare.generate.runner import GenerationProgress, GenerationSummary, NoProgress, generate
from pare.generate.sections import STAGES

__all__ = [
    "STAGES",
    "CandidateRecord",
    "GenerateConfig",
    "GenerationFolder",
    "GenerationProgress",
    "GenerationSummary",
    "NoProgress",
    "PendingCandidate",
    "accept",
    "build_generate_config",
    "generate",
    "generate_candidate",
    "pending",
    "read_provenance",
    "reject",
]
