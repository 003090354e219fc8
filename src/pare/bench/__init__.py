"""The benchmark harness: episodes, the scenario self-test, many episodes into a run folder, metrics,
reports, sweeps and figures.
"""

from pare.bench.episode import EpisodeResult, EpisodeSettings, Step, arun_episode, run_episode
from pare.bench.metrics import ConfigurationMetrics, Estimate, compute_metrics
from pare.bench.records import EpisodeRecord, ProposalRecord
from pare.bench.runconfig import RunConfig, build_config
from pare.bench.runner import RunSummary, run_benchmark
from pare.bench.store import LoadedRun, load_run

__all__ = [
    "ConfigurationMetrics",
    "EpisodeRecord",
    "EpisodeResult",
    "EpisodeSettings",
    "Estimate",
    "LoadedRun",
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
