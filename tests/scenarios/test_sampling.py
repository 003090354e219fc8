"""The stratified sample keeps the library's mix, is the same for the same seed, and the ablation split
of the library is such a sample."""

from __future__ import annotations

from pathlib import Path

import pytest
import yaml

from pare.cli import main
from pare.scenarios.library import library, splits, write_split
from pare.scenarios.sampling import profile, stratified_sample


def test_a_sample_keeps_every_share_of_the_library_within_five_points() -> None:
    scenarios = list(library().values())
    drawn = stratified_sample(scenarios, 50, seed=0)
    assert len(drawn.ids) == 50 == len(set(drawn.ids))
    name, gap = drawn.largest_gap
    assert gap <= 0.05, (name, gap)
    assert stratified_sample(scenarios, 50, seed=0).ids == drawn.ids


def test_the_ablation_split_is_fifty_scenarios_in_the_library_proportions() -> None:
    named = splits()
    ablation = [library()[scenario_id] for scenario_id in named["ablation"]]
    assert len(ablation) == 50 == len(set(named["ablation"]))
    whole, part = profile(library().values()), profile(ablation)
    for feature, share in whole.items():
        assert abs(part.get(feature, 0.0) - share) <= 0.08, feature


def test_impossible_sizes_are_refused() -> None:
    scenarios = list(library().values())[:3]
    with pytest.raises(ValueError, match="not possible"):
        stratified_sample(scenarios, 4)


def test_write_split_adds_a_split_and_keeps_the_others(tmp_path: Path) -> None:
    file = tmp_path / "splits.yaml"
    file.write_text(
        'splits:\n  full:\n    description: Everything.\n    scenarios: "*"\n'
        "  smoke:\n    description: A few.\n    scenarios: [a, b]\n",
        encoding="utf-8",
    )
    write_split("trial", "A trial: of two 'quoted'", ["b", "c"], file=file)
    written = yaml.safe_load(file.read_text(encoding="utf-8"))["splits"]
    assert written["full"] == {"description": "Everything.", "scenarios": "*"}
    assert written["smoke"]["scenarios"] == ["a", "b"]
    assert written["trial"] == {"description": "A trial: of two 'quoted'", "scenarios": ["b", "c"]}


def test_the_sample_command_prints_the_profile_and_ids(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["scenarios", "sample", "--size", "5", "--seed", "3"]) == 0
    out = capsys.readouterr().out
    assert "largest difference" in out and "app:email" in out
    assert len([line for line in out.splitlines() if line in library()]) == 5
