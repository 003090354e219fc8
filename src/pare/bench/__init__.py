"""Running the benchmark: episodes (the turn loop), the scenario self-test, many episodes into a run
folder, and sweeps. What a run leaves behind is read by :mod:`pare.results`.
"""

from typing import TYPE_CHECKING

from pare._lazy import lazy_exports

if TYPE_CHECKING:
    from pare.bench.episode import EpisodeResult, EpisodeSettings, Step, arun_episode, run_episode
    from pare.bench.policies import PolicyContext
    from pare.bench.runconfig import RunConfig, build_config
    from pare.bench.runner import RunSummary, run_benchmark

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "EpisodeResult": "episode",
        "EpisodeSettings": "episode",
        "Step": "episode",
        "arun_episode": "episode",
        "run_episode": "episode",
        "PolicyContext": "policies",
        "RunConfig": "runconfig",
        "build_config": "runconfig",
        "RunSummary": "runner",
        "run_benchmark": "runner",
    },
)

__all__ = [
    "EpisodeResult",
    "EpisodeSettings",
    "PolicyContext",
    "RunConfig",
    "RunSummary",
    "Step",
    "arun_episode",
    "build_config",
    "run_benchmark",
    "run_episode",
]
