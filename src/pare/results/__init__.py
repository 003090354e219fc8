"""What a benchmark run leaves behind, read without running anything: the trajectory (its model, writer
and reader), the episode records, the run folder's reader, metrics, reports and figures. Nothing here
imports :mod:`pare.bench` (the package that runs models), so a results-only install, the viewer and
re-grading stay light.
"""

from typing import TYPE_CHECKING

from pare._lazy import lazy_exports

if TYPE_CHECKING:
    from pare.results.metrics import ConfigurationMetrics, Estimate, compute_metrics
    from pare.results.records import EpisodeRecord, ProposalRecord
    from pare.results.run_folder import LoadedRun, load_run, run_folders
    from pare.results.trajectory import Trajectory, read_trajectory, write_trajectory

__getattr__, __dir__ = lazy_exports(
    __name__,
    {
        "ConfigurationMetrics": "metrics",
        "Estimate": "metrics",
        "compute_metrics": "metrics",
        "EpisodeRecord": "records",
        "ProposalRecord": "records",
        "LoadedRun": "run_folder",
        "load_run": "run_folder",
        "run_folders": "run_folder",
        "Trajectory": "trajectory",
        "read_trajectory": "trajectory",
        "write_trajectory": "trajectory",
    },
)

__all__ = [
    "ConfigurationMetrics",
    "EpisodeRecord",
    "Estimate",
    "LoadedRun",
    "ProposalRecord",
    "Trajectory",
    "compute_metrics",
    "load_run",
    "read_trajectory",
    "run_folders",
    "write_trajectory",
]
