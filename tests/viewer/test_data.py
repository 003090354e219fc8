"""The viewer's data layer: configurations, table rows, and episodes built from real trajectories."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from pare.errors import UserInputError
from pare.results.trajectory import parse_trajectory, write_trajectory
from pare.viewer import Catalog, Site, build_episode, export_site, slug
from pare.viewer._episode import ExecuteGroup, split_observation, thought_of
from pare.viewer._evidence import final_state, library_scenario, matched_entries
from pare.viewer._rows import filter_choices, rows
from tests.viewer.runs import SCENARIOS, Runs


def _episode(runs: Runs, scenario: str = "dentist_moves_checkup", run: int = 1):  # type: ignore[no-untyped-def]
    configuration = Catalog.open([runs.models]).configurations[0]
    record = configuration.records[(scenario, run)]
    data = configuration.trajectory(record)
    assert data is not None
    return record, data


def test_catalog_finds_each_run_and_every_run_of_a_sweep(runs: Runs, sweep: Path) -> None:
    catalog = Catalog.open([runs.oracle, runs.models, sweep])
    assert [c.cid for c in catalog.configurations][:2] == ["oracle", "models"]
    assert len(catalog.configurations) == 4
    swept = catalog.configurations[2:]
    assert [c.sweep_point["world.tool_failure_probability"] for c in swept] == [0.0, 0.5]
    assert catalog.get("models") is catalog.configurations[1]


def test_a_sweep_exports_every_run(sweep: Path, tmp_path: Path) -> None:
    written = export_site(Site(Catalog.open([sweep])), tmp_path / "site")
    pages = sorted(p.relative_to(tmp_path / "site").as_posix() for p in (tmp_path / "site").rglob("*.html"))
    assert written == len([p for p in (tmp_path / "site").rglob("*") if p.is_file()])
    assert len([p for p in pages if "/e/dentist_moves_checkup/run-1.html" in p]) == 2
    assert (
        export_site(Site(Catalog.open([sweep])), tmp_path / "site") == written
    )  # an earlier export: rewritten
    (tmp_path / "other").mkdir()
    (tmp_path / "other" / "notes.txt").write_text("mine", encoding="utf-8")
    with pytest.raises(UserInputError, match="not empty"):
        export_site(Site(Catalog.open([sweep])), tmp_path / "other")


def test_two_folders_of_one_name_get_distinct_ids(tmp_path: Path, runs: Runs) -> None:
    twin = tmp_path / "elsewhere" / "oracle"
    twin.parent.mkdir()
    twin.symlink_to(runs.oracle.resolve(), target_is_directory=True)
    catalog = Catalog.open([runs.oracle, twin])
    assert [c.cid for c in catalog.configurations] == ["oracle", "oracle-2"]


def test_a_folder_that_is_not_a_run_is_named(tmp_path: Path) -> None:
    with pytest.raises(UserInputError, match="no PARE run"):
        Catalog.open([tmp_path])


def test_metrics_are_the_reports_numbers(runs: Runs) -> None:
    oracle, models = Catalog.open([runs.oracle, runs.models]).configurations
    assert oracle.metrics.success_rate.mean == 1.0
    assert models.metrics.success_rate.mean == 0.0
    assert models.metrics.decision_counts["accept"] == 2 * len(SCENARIOS)


def test_rows_carry_what_the_filters_need(runs: Runs) -> None:
    models = Catalog.open([runs.models]).configurations[0]
    table = rows(models.records.values())
    assert len(table) == 2 * len(SCENARIOS)
    first = table[0]
    assert first["scenario"] == "dentist_moves_checkup" and first["run"] == 1
    assert first["success"] == "no" and first["decisions"] == ["accept"]
    assert first["href"] == "e/dentist_moves_checkup/run-1.html"
    assert first["tokens"] > 0 and first["cost_text"].startswith("$")
    choices = filter_choices(table)
    assert choices["scenario"] == sorted(SCENARIOS)
    assert "email" in choices["app"] and choices["success"] == ["no"]
    assert choices["decision"] == ["accept"]


def test_episode_shows_the_proposal_its_decision_and_the_task_it_became(runs: Runs) -> None:
    record, data = _episode(runs)
    episode = build_episode(data, list(record.proposals))
    proposals = [
        s for t in episode.turns for s in t.assistant if not isinstance(s, ExecuteGroup) and s.proposal
    ]
    assert len(proposals) == 1
    proposal = proposals[0].proposal
    assert proposal is not None and (proposal.decision, proposal.resolution) == ("accept", "accepted")
    answers = [s for t in episode.turns for s in t.user if s.answer]
    assert [(s.answer, s.proposal.proposal_id if s.proposal else None) for s in answers] == [
        ("accept", proposal.proposal_id)
    ]
    groups = [item for t in episode.turns for item in t.assistant if isinstance(item, ExecuteGroup)]
    assert len(groups) == 1 and groups[0].proposal == proposal
    assert groups[0].steps[-1].is_report


def test_user_steps_show_the_phone_as_the_user_saw_it(runs: Runs) -> None:
    record, data = _episode(runs)
    episode = build_episode(data, list(record.proposals))
    phones = [s.phone for t in episode.turns for s in t.user]
    assert all(phone is not None and phone.recorded for phone in phones)
    assert any(p and any("reception@brightsmile.example" in n for n in p.notifications) for p in phones)
    answering = [s for t in episode.turns for s in t.user if s.answer]
    assert answering[0].phone is not None and answering[0].phone.pending_proposal
    assert all(s.thought for t in episode.turns for s in t.user)  # the model's thought, from its answer


def test_failed_checks_keep_their_detail_and_tokens_are_per_step(runs: Runs) -> None:
    record, data = _episode(runs)
    episode = build_episode(data, list(record.proposals))
    failed = [c for g in episode.goals for c in g.checks if not c.passed]
    assert failed and all(c.detail for c in failed)
    steps = [s for t in episode.turns for s in t.user]
    assert all(s.usage is not None and s.usage.tokens > 0 for s in steps)
    assert set(episode.usage) == {"user", "observe", "execute", "total"}
    assert episode.usage["total"].calls == sum(u.calls for r, u in episode.usage.items() if r != "total")


def test_state_diff_and_check_evidence_link_to_the_log(runs: Runs) -> None:
    configuration = Catalog.open([runs.oracle]).configurations[0]
    record = configuration.records[("dentist_moves_checkup", 1)]
    data = configuration.trajectory(record)
    assert data is not None
    episode = build_episode(data, list(record.proposals))
    assert episode.changes is not None
    moved = [c for c in episode.changes if c.app == "calendar"]
    assert moved and all(c.credits and c.credits[-1].who == "assistant" for c in moved)
    made_by = moved[0].credits[-1].log_index
    assert made_by is not None and data.entries[made_by].actor == "assistant"
    first_check = episode.goals[0].checks[0]
    assert first_check.passed and made_by in first_check.evidence


def test_steps_and_checks_find_their_entries_by_index_when_one_is_malformed(runs: Runs) -> None:
    configuration = Catalog.open([runs.oracle]).configurations[0]
    record = configuration.records[("dentist_moves_checkup", 1)]
    data = configuration.trajectory(record)
    assert data is not None
    first = next(s.log_index for s in data.steps if s.actor == "assistant")
    assert first is not None
    data.log.pop(first - 1)  # every later entry moves up one place in the list
    episode = build_episode(data, list(record.proposals))
    steps = [s for t in episode.turns for s in [*t.user, *t.assistant] if not isinstance(s, ExecuteGroup)]
    for step in steps:
        if step.log_index is not None:
            entry = next(e for e in episode.log if e.index == step.log_index)
            assert entry.tool in step.tool and entry.actor == step.actor
    assert any(s.log_index == first for s in steps)
    indexes = {e.index for e in episode.log}
    assert all(i in indexes for g in episode.goals for c in g.checks for i in c.evidence)
    assert any(c.evidence for g in episode.goals for c in g.checks)


def test_checks_link_the_entries_their_patterns_match(runs: Runs) -> None:
    configuration = Catalog.open([runs.oracle]).configurations[0]
    record = configuration.records[("dentist_moves_checkup", 1)]
    data = configuration.trajectory(record)
    assert data is not None
    scenario = library_scenario(record.scenario_id, record.scenario_hash)
    assert scenario is not None
    matched = matched_entries(scenario, data, final_state(scenario, data))  # whom each call told
    episode = build_episode(data, list(record.proposals), matched)
    assert not matched_entries(scenario, data)[("practice_told", 0)]  # 'to' needs the final state
    (told,) = [g for g in episode.goals if g.id == "practice_told"]
    replies = [e.index for e in data.log if e.tool == "reply_to_email" and e.actor == "assistant"]
    assert told.checks[0].form == "judge" and told.checks[0].evidence == replies
    assert library_scenario(record.scenario_id, "0" * 16) is None  # changed since: no precise links
    assert library_scenario("no_such_scenario", record.scenario_hash) is None


def test_trajectories_from_before_the_view_was_recorded_still_open(runs: Runs) -> None:
    record, data = _episode(runs)
    data = data.model_copy(
        update={"steps": [step.model_copy(update={"view": None}) for step in data.steps], "state_diff": None}
    )
    episode = build_episode(data, list(record.proposals))
    phones = [s.phone for t in episode.turns for s in t.user]
    assert phones and all(p is not None and not p.recorded for p in phones)
    assert episode.changes is None


def test_site_pages_render_for_every_path(runs: Runs) -> None:
    site = Site(Catalog.open([runs.oracle, runs.models]))
    paths = list(site.paths())
    assert len([p for p in paths if "/e/" in p]) == 2 * 2 * len(SCENARIOS)
    for path in paths:
        page = site.page(path)
        assert page is not None and page.body, path
    episode = site.page("c/models/e/dentist_moves_checkup/run-1.html")
    assert episode is not None
    text = episode.body.decode()
    assert "decision: accept" in text and "resolution: accepted" in text
    assert site.page("c/models/e/dentist_moves_checkup/run-9.html") is None
    assert site.page("c/nobody/index.html") is None


def test_names_that_are_not_safe_file_names_get_hashed_slugs() -> None:
    assert slug("dentist_moves_checkup") == "dentist_moves_checkup"
    for name in ("..", "a/b", "../../etc", "x y", "", "C:evil"):
        made = slug(name)
        assert "/" not in made and made not in ("..", ".") and "~" in made
    assert slug("a/b") != slug("a b")


def test_model_text_parts() -> None:
    assert thought_of('Thought: look first\nAction: {"action": "wait"}') == "look first"
    assert thought_of(None) is None
    assert split_observation('ok\nOn screen: {"a": 1}') == ("ok", {"a": 1})
    assert split_observation("plain") == ("plain", None)


def test_trajectory_size_and_shape_are_checked(runs: Runs, tmp_path: Path) -> None:
    configuration = Catalog.open([runs.models]).configurations[0]
    record = configuration.records[("dentist_moves_checkup", 1)]
    file = runs.models / str(record.trajectory)
    original = file.read_bytes()
    try:
        file.write_text(json.dumps({"not": "a trajectory"}), encoding="utf-8")
        with pytest.raises(UserInputError, match="not a PARE trajectory"):
            configuration.trajectory(record)
    finally:
        file.write_bytes(original)


def test_the_replies_after_the_last_turn_are_a_phase_of_their_own() -> None:
    from pare.bench import EpisodeSettings, run_episode
    from pare.scenarios import OracleAssistant, OracleUser
    from tests.scenarios.helpers import parse, replying

    scenario = parse(replying())
    data = run_episode(
        scenario, OracleUser(scenario), OracleAssistant(scenario), EpisodeSettings(max_turns=4)
    ).trajectory()
    episode = build_episode(parse_trajectory(write_trajectory(data)), [])
    *played, after = episode.turns
    assert [turn.number for turn in played] == [1, 2, 3, 4] and not any(turn.after_last for turn in played)
    assert after.after_last and after.number == 5
    assert [entry.event_id for entry in after.world] == ["ann_thanks", "ann_ps"]
    assert after.user == [] and after.assistant == []
