"""The renderers on a two-configuration fixture: the numbers appear formatted as the paper does."""

from __future__ import annotations

import csv
import io
import json

import pytest
from rich.console import Console

from pare.errors import UserInputError
from pare.results.metrics import ConfigurationMetrics, Estimate, compute_metrics
from pare.results.report import (
    SECTIONS,
    format_ci,
    format_estimate,
    format_percent,
    format_usd,
    render_csv,
    render_json,
    render_latex,
    render_markdown,
    render_terminal,
)
from tests.results.test_metrics import PLANNED, fixture_records, record

# "full" is tests/results/test_metrics.py's fixture (numbers worked out there); "small" has every planned
# episode complete: A and B, runs 1..2, every episode costs user $0.01 + observe $0.02 = $0.03.
#   A1 yes (1 proposal, accepted), A2 no (1 proposal, rejected), B1 yes, B2 yes (no proposals)
# success per run: run 1: 2/2 = 1, run 2: 1/2 -> 75.0% ± 25.0%; Success@2 = 2/2, Success^2 = 1/2
# acceptance per run: 1/1, 0/1 -> 50.0% ± 50.0%; cost $0.12 total, 3 successes -> $0.0400 per success


def small() -> ConfigurationMetrics:
    records = [
        record("A", 1, success=True, proposals=(("accept", "accepted"),), read_actions=4),
        record("A", 2, proposals=(("reject", "rejected"),), read_actions=6),
        record("B", 1, success=True, read_actions=2),
        record("B", 2, success=True, read_actions=8),
    ]
    planned = [(s, r) for s in "AB" for r in (1, 2)]
    return compute_metrics(records, label="small-model", runs=2, planned=planned, params={"noise": 2.0})


@pytest.fixture(scope="module")
def configurations() -> list[ConfigurationMetrics]:
    full = compute_metrics(
        fixture_records(), label="full-model", runs=3, planned=PLANNED, params={"assistant": "full"}
    )
    return [full, small()]


def test_formatting_helpers() -> None:
    assert format_percent(0.42) == "42.0%"
    assert format_percent(None) == "n/a"
    assert format_estimate(Estimate(mean=0.42, se=0.01, n=4)) == "42.0% ± 1.0%"
    assert format_estimate(Estimate(mean=0.42, se=None, n=1)) == "42.0%"
    assert format_estimate(Estimate()) == "n/a"
    assert format_estimate(Estimate(mean=20.24, se=0.2, n=4), percent=False) == "20.2 ± 0.2"
    assert format_ci((0.35, 0.49)) == "[35.0%, 49.0%]"
    assert format_ci(None) == "n/a"
    assert format_usd(0.0123) == "$0.0123"
    assert format_usd(None, known=False) == "unknown"
    assert format_usd(None) == "n/a"


def terminal(configurations: list[ConfigurationMetrics], **kwargs: object) -> str:
    console = Console(record=True, width=200)
    render_terminal(configurations, console, **kwargs)  # type: ignore[arg-type]
    return console.export_text()


def test_terminal_main_table(configurations: list[ConfigurationMetrics]) -> None:
    text = terminal(configurations, sections=("main",))
    assert "Main results" in text
    assert "Success@k" in text  # k differs between the two configurations (3 and 2)
    # full: success 13/18 = 72.2% ± sqrt(7)/18 = 14.7%; proposal 30.0% ± 5.8%; acceptance 19/36 = 52.8%
    assert "72.2% ± 14.7%" in text
    assert "30.0% ± 5.8%" in text
    assert "52.8% ± 13.9%" in text
    assert "20.0 ± 5.8" in text  # read actions
    assert "7/9 (77.8%)" in text
    assert "100.0%" in text and "50.0%" in text  # Success@3, Success^3
    # small: success 75.0% ± 25.0%, acceptance 50.0% ± 50.0%, read actions (4+2)/2=3, (6+8)/2=7 -> 5.0 ± 2.0
    assert "75.0% ± 25.0%" in text
    assert "50.0% ± 50.0%" in text
    assert "5.0 ± 2.0" in text
    assert "4/4" in text
    assert "Proposal decisions" not in text
    assert "Coverage problems" not in text


def test_terminal_decisions_resolution_cost(configurations: list[ConfigurationMetrics]) -> None:
    text = terminal(configurations, sections=("decisions", "resolution", "cost"))
    # full accept per run 2/3, 1/3, 1/4 -> 41.7%; gather 1/3, 1/3, 1/2 -> 38.9% ± 5.6%
    assert "41.7% ± 12.7%" in text
    assert "38.9% ± 5.6%" in text
    # small: accept 1/1, 0/1 -> 50.0% ± 50.0%; reject the other way round
    assert "G→Expired" in text and "G→Truncated" in text
    assert "unknown (1 of 109 calls unpriced; $0.2160 known)" in text
    assert "$0.1200" in text  # small's total
    assert "$0.0400" in text  # small's cost per success: 0.12 / 3
    assert "unknown" in text


def test_terminal_breakdowns_and_coverage(configurations: list[ConfigurationMetrics]) -> None:
    text = terminal(configurations)
    for title in ("By app", "By tag", "By difficulty", "Coverage problems"):
        assert title in text
    assert "83.3% ± 16.7%" in text  # full, email
    assert "messaging" in text
    assert "provider_unavailable" in text and "provider down" in text
    assert "missing" in text


def test_terminal_colours_coverage_problems(configurations: list[ConfigurationMetrics]) -> None:
    console = Console(record=True, width=200, force_terminal=True, color_system="standard")
    render_terminal(configurations, console, sections=("coverage",))
    styled = console.export_text(styles=True)
    assert "\x1b[31m" in styled  # red: failed
    assert "\x1b[33m" in styled  # yellow: missing


def test_no_coverage_table_without_problems() -> None:
    assert "Coverage problems" not in terminal([small()])
    assert "Coverage problems" not in render_markdown([small()])


def test_unknown_section() -> None:
    with pytest.raises(UserInputError, match="Did you mean 'tags'"):
        render_markdown([small()], sections=("tag",))


def test_markdown(configurations: list[ConfigurationMetrics]) -> None:
    text = render_markdown(configurations)
    for heading in (
        "## Main results",
        "## Proposal decisions",
        "## Gather-context resolution",
        "## Cost and tokens per role",
        "## By app",
        "## By tag",
        "## By difficulty",
        "## Coverage problems",
    ):
        assert heading in text
    lines = text.splitlines()
    header = next(line for line in lines if line.startswith("| Configuration | Success@k"))
    assert lines[lines.index(header) + 1].startswith("|:---|---:|")
    row = next(line for line in lines if line.startswith("| small-model | 100.0% | 50.0% | 75.0% ± 25.0%"))
    assert row.endswith("| 4/4 |")
    assert "| full-model | C | 2 | failed (provider_unavailable) | provider down |" in text


def test_csv(configurations: list[ConfigurationMetrics]) -> None:
    rows = list(csv.DictReader(io.StringIO(render_csv(configurations))))
    assert [row["label"] for row in rows] == ["full-model", "small-model"]
    full, small_row = rows
    assert full["param.assistant"] == "full" and full["param.noise"] == ""
    assert small_row["param.noise"] == "2.0"
    assert float(full["success_rate_mean"]) == pytest.approx(13 / 18)
    assert float(full["success_rate_se"]) == pytest.approx(7**0.5 / 18)
    assert full["success_rate_n"] == "3"
    assert float(full["success_at_k"]) == 1.0 and float(full["success_all_k"]) == 0.5
    assert float(small_row["success_rate_mean"]) == 0.75
    assert float(small_row["success_rate_se"]) == 0.25
    assert float(full["decision.gather_context_mean"]) == pytest.approx(7 / 18)  # (1/3 + 1/3 + 1/2) / 3
    assert float(full["resolution.expired_mean"]) == pytest.approx(1 / 6)
    assert (full["episodes_failed"], full["episodes_missing"], full["episodes_unplanned"]) == ("1", "1", "2")
    assert float(full["complete_share"]) == pytest.approx(7 / 9)
    assert full["usage.total.cost_usd"] == ""  # unknown, never 0
    assert full["usage.total.cost"].startswith("unknown")
    assert float(small_row["usage.total.cost_usd"]) == pytest.approx(0.12)
    assert float(small_row["usage.total.cost_per_success"]) == pytest.approx(0.04)
    assert small_row["usage.judge.calls"] == ""  # small has no judge calls
    assert float(full["success_rate_ci_low"]) <= float(full["success_rate_ci_high"])


def test_json_round_trip(configurations: list[ConfigurationMetrics]) -> None:
    text = render_json(configurations)
    assert text == render_json(configurations)
    data = json.loads(text)
    assert list(data) == ["configurations"]
    restored = [ConfigurationMetrics.model_validate(item) for item in data["configurations"]]
    assert restored == configurations
    assert '\n  "configurations": [\n' in text  # indent 2


def test_sections_constant() -> None:
    assert SECTIONS[0] == "main" and SECTIONS[-1] == "coverage"


def test_empty() -> None:
    assert terminal([]) == "No results to report.\n"
    assert render_markdown([]) == "No results to report.\n"
    assert render_json([]) == '{\n  "configurations": []\n}\n'


def test_reliability_consistency_and_kinds_in_every_format(
    configurations: list[ConfigurationMetrics],
) -> None:
    # small: A (yes, no), B (yes, yes): pass^1 = 75%, pass^2 = (0 + 1) / 2 = 50%, pass@2 = 100%;
    # A flips (1 of 2 scenarios); R_Accept per run: (+1 + 0) / 2, (-1 + 0) / 2 -> 0.00 ± 0.50
    sections = ("reliability", "consistency", "kinds")
    text = terminal([configurations[1]], sections=sections)
    assert "Success over k runs" in text and "Consistency and reward" in text and "By kind" in text
    assert "0.00 ± 0.50" in text
    markdown = render_markdown([configurations[1]], sections=sections)
    assert "| small-model | 2 | 50.0% | 100.0% |" in markdown
    assert "| small-model | 1 | 50.0% | 0.00 ± 0.50 |" in markdown
    assert "| unspecified | small-model |" in markdown  # records without a kind
    latex = render_latex([configurations[1]], sections=sections)
    assert r"small-model & 1 & 75.0\% & 75.0\% \\" in latex
    row = next(csv.DictReader(io.StringIO(render_csv([configurations[1]]))))
    assert float(row["pass_hat.2"]) == 0.5 and float(row["pass_at.2"]) == 1.0
    assert row["flip_scenarios"] == "1" and float(row["flip_rate"]) == 0.5
    assert float(row["accept_reward_se"]) == 0.5
    data = json.loads(render_json([configurations[1]]))["configurations"][0]
    assert data["pass_hat"] == {"1": 0.75, "2": 0.5}


def test_wrong_irreversible_actions_sit_beside_the_success_rate_in_every_format() -> None:
    from tests.results.test_metrics import harm_metrics

    metrics = harm_metrics()  # wrong irreversible per episode 0.5 ± 0.5 over runs 1 and 2, 2 in all
    header = "Wrong irreversible / episode ± SE"
    text = terminal([metrics], sections=("main",))
    assert "irreversible /" in text and "0.50 ± 0.50" in text  # the header wraps at its spaces
    markdown = render_markdown([metrics], sections=["main"])
    columns = next(line for line in markdown.splitlines() if line.startswith("| Configuration"))
    names = [cell.strip() for cell in columns.strip("|").split("|")]
    assert names.index(header) == names.index("Success rate ± SE") + 2  # after the rate and its interval
    row = next(line for line in markdown.splitlines() if line.startswith("| harm "))
    assert [cell.strip() for cell in row.strip("|").split("|")][names.index(header)] == "0.50 ± 0.50"
    latex = render_latex([metrics], sections=["main"])
    assert r"\textbf{Wrong irreversible / episode $\pm$ SE}" in latex and r"0.50 $\pm$ 0.50" in latex
    cells = next(csv.DictReader(io.StringIO(render_csv([metrics]))))
    assert float(cells["wrong_irreversible_actions_mean"]) == 0.5
    assert float(cells["wrong_irreversible_actions_se"]) == 0.5
    assert cells["wrong_irreversible_actions_n"] == "2" and cells["wrong_irreversible_total"] == "2"
    assert float(cells["irreversible_actions_mean"]) == 2.0
    data = json.loads(render_json([metrics]))["configurations"][0]
    assert data["wrong_irreversible_actions"] == {"mean": 0.5, "se": 0.5, "n": 2}
    assert data["irreversible_actions"]["mean"] == 2.0


@pytest.mark.parametrize("width", range(150, 262, 8))
def test_a_table_that_fits_is_drawn_whole_at_any_width(
    configurations: list[ConfigurationMetrics], width: int
) -> None:
    # rich narrowed the widest columns below what their cells need and drew the table past the console's
    # edge, where it was cut (a long label made it happen at 168-184 and 204-224 columns)
    labelled = [m.model_copy(update={"label": "baseline: generic_offer"}) for m in configurations]
    console = Console(record=True, width=width)
    render_terminal(labelled, console, sections=("main",))
    lines = console.export_text().splitlines()
    assert all(len(line) <= width for line in lines)
    rows = [line for line in lines if line.startswith("│")]
    if rows:  # drawn as a table rather than as blocks
        assert all(row.rstrip().endswith("│") for row in rows)
