"""The benchmark harness: episodes, the scenario self-test, many episodes into a run folder, metrics,
reports, sweeps and figures.
"""

from typing import TYPE_CHECKING

from pare._lazy import lazy_exports

if TYPE_CHECKING:
    from pare.bench.episode import EpisodeResult, EpisodeSettings, Step, arun_episode, run_episode
    from pare.bench.metrics import ConfigurationMetrics, Estimate, compute_metrics
    from pare.bench.policies import PolicyContext
    from pare.bench.records import EpisodeRecord, ProposalRecord
    from pare.bench.runconfig import RunConfig, build_config
    from pare.bench.runner import RunSummary, run_benchmark
    from pare.bench.store import LoadedRun, load_run

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "EpisodeResult": "episode",
        "EpisodeSettings": "episode",
        "Step": "episode",
        "arun_episode": "episode",
        "run_episode": "episode",
        "ConfigurationMetrics": "metrics",
        "Estimate": "metrics",
        "compute_metrics": "metrics",
        "PolicyContext": "policies",
        "EpisodeRecord": "records",
        "ProposalRecord": "records",
        "RunConfig": "runconfig",
        "build_config": "runconfig",
        "RunSummary": "runner",
        "run_benchmark": "runner",
        "LoadedRun": "store",
        "load_run": "store",
    },
)

__all__ = [
    "ConfigurationMetrics",
    "EpisodeRecord",
    "EpisodeResult",
    "EpisodeSettings",
    "Estimate",
    "LoadedRun",
    "PolicyContext",
    "ProposalRecord",
    "RunConfig",
    "RunSummary",
    "Step",
    "arun_episode",
    "build_config",
    "compute_metrics",
    "load_run",
    "run_benchmark",
    "run_episode",
]
