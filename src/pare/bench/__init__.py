"""The benchmark harness: episodes, the scenario self-test, and (later) many episodes and their metrics."""

from pare.bench.episode import EpisodeResult, EpisodeSettings, Step, arun_episode, run_episode

__all__ = ["EpisodeResult", "EpisodeSettings", "Step", "arun_episode", "run_episode"]
