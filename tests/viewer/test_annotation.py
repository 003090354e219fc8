"""Annotation: the viewer's endpoint stores a person's marks, and ``pare agreement`` compares them with the
user simulator and the judge (Cohen's kappa worked out by hand).
"""

from __future__ import annotations

import csv
import io
import json
import random
import shutil
from pathlib import Path

import pytest
from starlette.testclient import TestClient

from pare.cli import main
from pare.errors import UserInputError
from pare.results.agreement import agreement_of_run, cohen_kappa, kappa_interval
from pare.results.annotations import ANNOTATIONS, read_annotations
from pare.results.run_folder import load_run
from pare.viewer import Catalog, Site
from pare.viewer._server import create_app
from tests.viewer.annotated_run import SCENARIO, make_annotated_run


@pytest.fixture(scope="module")
def played(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return make_annotated_run(tmp_path_factory.mktemp("annotated") / "run")


@pytest.fixture
def folder(played: Path, tmp_path: Path) -> Path:
    """A fresh copy of the run, to annotate."""
    copy = tmp_path / "run"
    shutil.copytree(played, copy)
    return copy


def serve(folder: Path) -> tuple[TestClient, str]:
    site = Site(Catalog.open([folder]))
    client = TestClient(create_app(site), base_url="http://127.0.0.1")
    assert site.data_key is not None
    return client, site.data_key


def mark(run: int, kind: str, item: str, label: str, annotator: str = "alice") -> dict[str, object]:
    return {
        "configuration": "run",
        "scenario_id": SCENARIO,
        "run": run,
        "kind": kind,
        "item": item,
        "label": label,
        "annotator": annotator,
    }


def judged_item(folder: Path, run: int) -> str:
    data = json.loads((folder / "trajectories" / SCENARIO / f"run-{run}.json").read_text())
    [(goal, check)] = [(g["id"], c) for g in data["outcome"]["goals"] for c in g["checks"] if c["judged"]]
    entries = "+".join(str(i) for i in check["judged"][0]["entries"])
    return f"{goal}:{check['index']}:{entries}"


# -- Cohen's kappa ------------------------------------------------------------------------------------------
def test_kappa_of_a_worked_example() -> None:
    # 50 pairs: 20 both yes, 5 person only, 10 machine only, 15 both no
    # p_o = 35/50 = 0.7; yes rates 25/50 and 30/50; p_e = 0.5*0.6 + 0.5*0.4 = 0.5; kappa = 0.2/0.5 = 0.4
    pairs = [(True, True)] * 20 + [(True, False)] * 5 + [(False, True)] * 10 + [(False, False)] * 15
    assert cohen_kappa(pairs) == pytest.approx(0.4)


def test_kappa_is_undefined_when_chance_agrees_always() -> None:
    assert cohen_kappa([(True, True), (True, True)]) is None
    assert cohen_kappa([]) is None
    assert cohen_kappa([(True, True), (False, False)]) == 1.0
    assert cohen_kappa([(True, False), (False, True)]) == -1.0


def test_the_bootstrap_interval_holds_kappa_and_is_reproducible() -> None:
    items = [[(True, True)]] * 20 + [[(True, False)]] * 5 + [[(False, True)]] * 10 + [[(False, False)]] * 15
    first = kappa_interval(items, samples=500, confidence=0.95, rng=random.Random(3))
    again = kappa_interval(items, samples=500, confidence=0.95, rng=random.Random(3))
    assert first is not None and first == again
    assert first[0] < 0.4 < first[1] and first[0] >= -1 and first[1] <= 1
    assert kappa_interval([[(True, True)]], samples=100, confidence=0.95, rng=random.Random(0)) is None


# -- the endpoint ------------------------------------------------------------------------------------------
def test_a_mark_is_appended_with_who_and_when(folder: Path) -> None:
    client, key = serve(folder)
    answer = client.post(f"/annotate?key={key}", json=mark(1, "proposal", "proposal-1", "reject"))
    assert answer.status_code == 200, answer.text
    assert answer.json()["annotator"] == "alice" and answer.json()["label"] == "reject"
    item = judged_item(folder, 1)
    assert client.post(f"/annotate?key={key}", json=mark(1, "judged", item, "fail")).status_code == 200
    [first, second] = read_annotations(folder)
    assert (first.kind, first.item, first.label, first.annotator) == (
        "proposal",
        "proposal-1",
        "reject",
        "alice",
    )
    assert (second.kind, second.item, second.label) == ("judged", item, "fail")
    assert first.at.endswith("+00:00") and first.at[:2] == "20"
    lines = (folder / ANNOTATIONS).read_text().splitlines()
    assert len(lines) == 2  # one line per mark, appended


@pytest.mark.parametrize(
    ("change", "status", "says"),
    [
        ({"label": "pass"}, 400, "a proposal is marked accept or reject"),
        ({"item": "proposal-9"}, 400, "no proposal 'proposal-9'"),
        ({"run": 7}, 400, "no complete episode"),
        ({"configuration": "other"}, 400, "no configuration 'other'"),
        ({"kind": "vote"}, 400, "kind"),
    ],
)
def test_a_mark_that_names_nothing_real_is_refused(
    folder: Path, change: dict[str, object], status: int, says: str
) -> None:
    client, key = serve(folder)
    answer = client.post(
        f"/annotate?key={key}", json={**mark(1, "proposal", "proposal-1", "accept"), **change}
    )
    assert answer.status_code == status and says in answer.json()["error"]
    assert not (folder / ANNOTATIONS).exists()


def test_a_mark_without_the_key_json_or_from_another_site_is_refused(folder: Path) -> None:
    client, key = serve(folder)
    body = json.dumps(mark(1, "proposal", "proposal-1", "accept"))
    json_type = {"content-type": "application/json"}
    assert client.post("/annotate?key=guess", content=body, headers=json_type).status_code == 403
    form = {"content-type": "text/plain"}
    assert client.post(f"/annotate?key={key}", content=body, headers=form).status_code == 403
    other_site = {**json_type, "sec-fetch-site": "cross-site", "sec-fetch-mode": "cors"}
    assert client.post(f"/annotate?key={key}", content=body, headers=other_site).status_code == 403
    assert client.put(f"/annotate?key={key}", content=body, headers=json_type).status_code == 405
    too_big = json.dumps({**mark(1, "proposal", "proposal-1", "accept"), "pad": "x" * 5000})
    assert client.post(f"/annotate?key={key}", content=too_big, headers=json_type).status_code == 413
    assert not (folder / ANNOTATIONS).exists()


def test_the_served_episode_page_offers_its_items_and_the_export_does_not(
    folder: Path, tmp_path: Path
) -> None:
    client, key = serve(folder)
    page = client.get(f"/c/run/e/{SCENARIO}/run-1.html").text
    assert 'id="annotate"' in page and 'data-item="proposal-1"' in page
    assert f'data-item="{judged_item(folder, 1)}"' in page and "user simulator: accept" in page
    assert f"annotate?key={key}" in page
    exported = Site(Catalog.open([folder])).page(f"c/run/e/{SCENARIO}/run-1.html")
    assert exported is not None and b'id="annotate"' not in exported.body


def test_a_damaged_annotations_file_is_named_by_line(folder: Path) -> None:
    (folder / ANNOTATIONS).write_text('{"scenario_id": "x"}\n', encoding="utf-8")
    with pytest.raises(UserInputError, match=r"annotations\.jsonl:1: not an annotation"):
        read_annotations(folder)


# -- agreement ---------------------------------------------------------------------------------------------
def annotate_the_worked_example(folder: Path) -> None:
    """The simulator accepted in runs 1 and 3 and rejected in run 2; the judge passed runs 1 and 3.

    user pairs (person, simulator): alice T/T, T/F (her second mark on run 2), T/T; bob T/T, F/F, F/T
    -> p_o = 4/6, both yes rates 4/6, p_e = 16/36 + 4/36 = 5/9, kappa = (2/3 - 5/9) / (4/9) = 0.25
    judge pairs: alice pass/pass on run 1, fail/pass on run 3 -> p_o = 1/2, p_e = 1/2, kappa = 0
    """
    client, key = serve(folder)
    marks = [
        mark(1, "proposal", "proposal-1", "accept"),
        mark(2, "proposal", "proposal-1", "reject"),
        mark(2, "proposal", "proposal-1", "accept"),  # alice changes her mind: the last mark counts
        mark(3, "proposal", "proposal-1", "accept"),
        mark(1, "proposal", "proposal-1", "accept", "bob"),
        mark(2, "proposal", "proposal-1", "reject", "bob"),
        mark(3, "proposal", "proposal-1", "reject", "bob"),
        mark(1, "judged", judged_item(folder, 1), "pass"),
        mark(3, "judged", judged_item(folder, 3), "fail"),
    ]
    for body in marks:
        assert client.post(f"/annotate?key={key}", json=body).status_code == 200


def test_agreement_with_the_simulator_and_the_judge(folder: Path) -> None:
    annotate_the_worked_example(folder)
    user, judge = agreement_of_run(load_run(folder), samples=200)
    assert (user.rater, user.items, user.annotators, user.pairs) == ("user", 3, 2, 6)
    assert (user.both_positive, user.person_only, user.machine_only, user.both_negative) == (3, 1, 1, 1)
    assert user.observed == pytest.approx(4 / 6) and user.kappa == pytest.approx(0.25)
    assert user.kappa_ci is not None and user.kappa_ci[0] <= 0.25 <= user.kappa_ci[1]
    assert (judge.rater, judge.items, judge.pairs, judge.observed, judge.kappa) == ("judge", 2, 2, 0.5, 0.0)


def test_pare_agreement_in_every_format(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    annotate_the_worked_example(folder)
    assert main(["agreement", str(folder), "--format", "json", "--samples", "200"]) == 0
    rows = json.loads(capsys.readouterr().out)["agreement"]
    assert [(row["rater"], row["kappa"]) for row in rows] == [("user", pytest.approx(0.25)), ("judge", 0.0)]
    assert main(["agreement", str(folder), "--format", "markdown", "--samples", "200"]) == 0
    markdown = capsys.readouterr().out
    assert (
        "## Agreement with people" in markdown and "| user simulator | 3 | 2 | 6 | 66.7% | 0.25 |" in markdown
    )
    assert main(["agreement", str(folder), "--format", "latex", "--samples", "200"]) == 0
    assert r"user simulator & 3 & 2 & 6 & 66.7\% & 0.25" in capsys.readouterr().out
    assert main(["agreement", str(folder), "--format", "csv", "--samples", "200"]) == 0
    [user, judge] = csv.DictReader(io.StringIO(capsys.readouterr().out))
    assert user["rater"] == "user" and float(user["kappa"]) == pytest.approx(0.25) and judge["kappa"] == "0.0"
    assert main(["agreement", str(folder), "--samples", "200"]) == 0
    assert "Agreement with people" in capsys.readouterr().out


def test_no_annotations_says_so(folder: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["agreement", str(folder)]) == 0
    assert "No annotations to compare" in capsys.readouterr().out


def test_a_mark_without_a_name_is_the_accounts(folder: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("LOGNAME", "dana")
    client, key = serve(folder)
    answer = client.post(f"/annotate?key={key}", json=mark(1, "proposal", "proposal-1", "accept", "  "))
    assert answer.status_code == 200 and answer.json()["annotator"] == "dana"
    assert [a.annotator for a in read_annotations(folder)] == ["dana"]
