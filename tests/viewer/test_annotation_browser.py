"""Annotating in headless Chromium: a person names themself, marks a proposal and a judged text on a served
episode page, sees the machine's verdict only then, and the marks land in the run's annotations.jsonl.
"""

from __future__ import annotations

import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Page, expect

from pare.results.annotations import read_annotations
from tests.viewer.annotated_run import SCENARIO, make_annotated_run
from tests.viewer.test_browser import browser, page

__all__ = ["browser", "page"]  # fixtures, shared with the viewer's other browser tests


@pytest.fixture(scope="module")
def folder(tmp_path_factory: pytest.TempPathFactory) -> Path:
    return make_annotated_run(tmp_path_factory.mktemp("annotated") / "run")


@pytest.fixture(scope="module")
def served(folder: Path, tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    command = [sys.executable, "-u", "-m", "pare", "view", str(folder)]
    log = tmp_path_factory.mktemp("server") / "stderr.txt"
    with (
        log.open("w", encoding="utf-8") as errors,
        subprocess.Popen(command, stdout=subprocess.PIPE, stderr=errors, text=True) as process,
    ):
        try:
            assert process.stdout is not None
            found = re.search(r"http://127\.0\.0\.1:(\d+)/", process.stdout.readline())
            assert found, log.read_text(encoding="utf-8")
            yield found.group(0)
        finally:
            process.terminate()
            process.wait(timeout=10)


def test_a_person_marks_a_proposal_and_a_judged_text(served: str, page: Page, folder: Path) -> None:
    page.goto(served + f"c/run/e/{SCENARIO}/run-1.html")
    panel = page.locator("#annotate")
    proposal = panel.locator('.annotation-item[data-kind="proposal"]')
    judged = panel.locator('.annotation-item[data-kind="judged"]')
    expect(proposal.locator(".machine")).to_be_hidden()  # not shown before the person's own verdict
    page.fill("#annotator", "carol")
    page.locator("#annotator").dispatch_event("change")
    proposal.get_by_role("button", name="reject").click()
    expect(proposal.locator(".your-mark")).to_have_text("saved: reject")
    expect(proposal.locator(".machine")).to_have_text("user simulator: accept")
    expect(proposal.locator(".marks")).to_contain_text("carol: reject")
    judged.get_by_role("button", name="pass").click()
    expect(judged.locator(".your-mark")).to_have_text("saved: pass")
    expect(judged.locator(".machine")).to_have_text("judge: pass")

    marks = [(a.annotator, a.run, a.kind, a.label) for a in read_annotations(folder)]
    assert marks == [("carol", 1, "proposal", "reject"), ("carol", 1, "judged", "pass")]
    page.reload()  # the name is remembered, and with it the verdicts already marked are shown
    expect(page.locator("#annotator")).to_have_value("carol")
    expect(proposal.locator(".machine")).to_be_visible()
    expect(proposal.locator(".marks")).to_contain_text("carol: reject")
