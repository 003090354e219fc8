"""Take the viewer's screenshots for the docs from real runs: ``python scripts/viewer_screenshots.py``.

Makes the test runs (the oracle, and model-backed actors on local chat servers), exports them with
``pare view --export`` and photographs the pages in Debian's headless Chromium into ``docs/images/``.
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path

from playwright.sync_api import sync_playwright

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from tests.viewer.runs import KEY_VARIABLE, make_runs  # noqa: E402
from tests.viewer.test_browser import ARGS, CHROMIUM  # noqa: E402

from pare.cli import main  # noqa: E402

IMAGES = ROOT / "docs" / "images"


def shoot() -> None:
    """Write docs/images/viewer-episode.png, viewer-failed-checks.png and viewer-table.png."""
    os.environ.setdefault(KEY_VARIABLE, "not-a-real-key")
    with tempfile.TemporaryDirectory() as folder:
        runs = make_runs(Path(folder))
        site = Path(folder) / "site"
        assert main(["view", str(runs.oracle), str(runs.models), "--export", str(site)]) == 0
        with sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
            page = browser.new_page(viewport={"width": 1280, "height": 860})
            page.goto((site / "c" / "models" / "index.html").as_uri() + "#scenario=dentist")
            page.wait_for_selector("#episodes tbody tr a")
            page.screenshot(path=str(IMAGES / "viewer-table.png"))
            # the oracle's episode: the phone shows the email the user opened, then the proposal
            page.goto((site / "c" / "oracle" / "e" / "dentist_moves_checkup" / "run-1.html").as_uri())
            page.evaluate("document.getElementById('turn-2').scrollIntoView()")
            page.screenshot(path=str(IMAGES / "viewer-episode.png"))
            # the model-backed episode: a vague proposal accepted, nothing done, the checks that failed
            page.goto((site / "c" / "models" / "e" / "dentist_moves_checkup" / "run-1.html").as_uri())
            page.evaluate("document.getElementById('goals').scrollIntoView()")
            page.screenshot(path=str(IMAGES / "viewer-failed-checks.png"))
            browser.close()


if __name__ == "__main__":
    shoot()
