"""The cache of parsed scenarios gives back what the loader would, and never stands in its way."""

from __future__ import annotations

from pathlib import Path

import pytest

from pare.scenarios import parsed_cache
from pare.scenarios.library import scenario_files
from pare.scenarios.loader import load_scenario, parse_scenario


@pytest.fixture
def cache_dir(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.setenv("PARE_CACHE_DIR", str(tmp_path / "cache"))
    return tmp_path / "cache"


@pytest.fixture
def scenario_file(tmp_path: Path) -> Path:
    # one whose seed holds timestamps YAML reads as datetimes, and whose checks compare times
    source = next(f for f in scenario_files() if f.stem == "dentist_moves_checkup")
    copy = tmp_path / source.name
    copy.write_text(source.read_text(encoding="utf-8"), encoding="utf-8")
    return copy


def test_a_second_load_comes_from_the_cache_and_equals_a_fresh_parse(
    cache_dir: Path, scenario_file: Path
) -> None:
    first = load_scenario(scenario_file)
    entries = list(cache_dir.rglob("*.json"))
    assert len(entries) == 1
    again = load_scenario(scenario_file)
    assert again == first == parse_scenario(scenario_file.read_text(encoding="utf-8"))


def test_every_library_scenario_comes_back_from_the_cache_unchanged(cache_dir: Path) -> None:
    for file in scenario_files():
        text = file.read_text(encoding="utf-8")
        fresh = parse_scenario(text, source=str(file))
        parsed_cache.remember(text, fresh)
        assert parsed_cache.cached(text) == fresh, file.name


def test_an_edited_file_is_read_again(cache_dir: Path, scenario_file: Path) -> None:
    load_scenario(scenario_file)
    text = scenario_file.read_text(encoding="utf-8")
    scenario_file.write_text(text.replace("difficulty: easy", "difficulty: hard", 1), encoding="utf-8")
    assert load_scenario(scenario_file).difficulty == "hard"


def test_a_damaged_entry_is_passed_over(cache_dir: Path, scenario_file: Path) -> None:
    first = load_scenario(scenario_file)
    for entry in cache_dir.rglob("*.json"):
        entry.write_text("{not json", encoding="utf-8")
    assert load_scenario(scenario_file) == first


def test_off_turns_it_off_and_an_unwritable_folder_is_harmless(
    tmp_path: Path, scenario_file: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PARE_CACHE_DIR", "off")
    load_scenario(scenario_file)
    assert parsed_cache.cache_folder() is None
    blocker = tmp_path / "a-file"
    blocker.write_text("not a folder", encoding="utf-8")
    monkeypatch.setenv("PARE_CACHE_DIR", str(blocker))
    assert load_scenario(scenario_file).id == "dentist_moves_checkup"


def test_a_broken_file_is_never_cached(cache_dir: Path, tmp_path: Path) -> None:
    broken = tmp_path / "broken.yaml"
    broken.write_text("id: broken\ntitle: [unclosed\n", encoding="utf-8")
    with pytest.raises(Exception, match=r"broken\.yaml"):
        load_scenario(broken)
    assert not list(cache_dir.rglob("*.json"))


def test_folders_of_old_code_versions_are_pruned(cache_dir: Path, scenario_file: Path) -> None:
    import os

    old = cache_dir / "scenarios"
    for index in range(parsed_cache.KEPT_VERSIONS + 3):
        stale = old / f"old-{index}"
        stale.mkdir(parents=True)
        os.utime(stale, (1_000_000 + index, 1_000_000 + index))
    load_scenario(scenario_file)
    kept = sorted(p.name for p in old.iterdir())
    assert parsed_cache.code_fingerprint() in kept
    assert len(kept) == parsed_cache.KEPT_VERSIONS + 1
    assert "old-0" not in kept and f"old-{parsed_cache.KEPT_VERSIONS + 2}" in kept
