"""The cache of parsed scenarios gives back what the loader would, and never stands in its way."""

from __future__ import annotations

import copy
import pickle
from pathlib import Path

import pytest

from pare.scenarios import parsed_cache
from pare.scenarios.library import scenario_files
from pare.scenarios.loader import load_scenario, parse_scenario
from pare.scenarios.model import Scenario


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
        again = parsed_cache.cached(text)
        assert again is not None
        # the hash stored with the entry is the one the scenario has (the store tells changes by it)
        assert again.content_hash() == fresh.content_hash(), file.name
        assert again == fresh, file.name
        assert again.model_copy(update={"title": again.title}).content_hash() == fresh.content_hash()


def test_variants_are_validated_when_first_read_and_the_scenario_behaves_as_a_fresh_one(
    cache_dir: Path, scenario_file: Path
) -> None:
    text = scenario_file.read_text(encoding="utf-8")
    fresh = parse_scenario(text)
    assert fresh.variants
    parsed_cache.remember(text, fresh)

    def lazy() -> Scenario:
        scenario = parsed_cache.cached(text)
        assert scenario is not None and "variants" not in scenario.__dict__
        return scenario

    assert lazy().variants == fresh.variants
    assert lazy().solution(fresh.variants[0].id) == fresh.solution(fresh.variants[0].id)
    assert lazy().model_dump(mode="json") == fresh.model_dump(mode="json")
    assert lazy().model_dump_json(exclude_unset=True) == fresh.model_dump_json(exclude_unset=True)
    assert lazy().model_fields_set == fresh.model_fields_set
    assert pickle.loads(pickle.dumps(lazy())) == fresh
    assert copy.deepcopy(lazy()) == fresh
    assert lazy().model_copy() == fresh
    assert "variants=[Variant(" in repr(lazy())
    changed = lazy().model_copy(update={"variants": []})
    assert changed.variants == [] and changed.content_hash() != fresh.content_hash()
    assert changed.content_hash() == fresh.model_copy(update={"variants": []}).content_hash()


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


def test_variants_a_damaged_entry_cannot_give_are_read_from_the_file(
    cache_dir: Path, scenario_file: Path
) -> None:
    text = scenario_file.read_text(encoding="utf-8")
    fresh = parse_scenario(text)
    parsed_cache.remember(text, fresh)
    for entry in cache_dir.rglob("*.json"):
        head, _, _ = entry.read_text(encoding="utf-8").partition("\n")
        entry.write_text(head + "\n[{not json", encoding="utf-8")
    again = parsed_cache.cached(text)
    assert again is not None and again.variants == fresh.variants and again == fresh
