"""The leaderboard of a static export in headless Chromium: sorting by a column, and its links to the
episodes (the browser fixtures are those of test_browser: only the viewer's files may be reached).
"""

from __future__ import annotations

from pathlib import Path

from playwright.sync_api import Page, expect

from pare.cli import main
from tests.viewer.runs import Runs
from tests.viewer.test_browser import browser, page

__all__ = ["browser", "page"]  # fixtures, imported to be used here


def _first_column(page: Page) -> list[str]:
    return page.locator("#leaderboard tbody tr td:nth-child(2) a").all_inner_texts()


def test_the_leaderboard_sorts_and_leads_to_the_episodes(runs: Runs, page: Page, tmp_path: Path) -> None:
    site = tmp_path / "site"
    assert main(["view", str(runs.models), str(runs.oracle), "--export", str(site)]) == 0
    page.goto((site / "index.html").as_uri())
    page.get_by_role("link", name="The leaderboard").click()
    expect(page.locator("#leaderboard tbody tr")).to_have_count(2)
    assert _first_column(page) == ["oracle", "test-assistant (user test-user)"]  # ranked by success
    success = page.locator("#leaderboard th", has_text="Success rate")
    success.click()  # ascending
    expect(page.locator("#leaderboard tbody tr").first).to_contain_text("test-assistant")
    success.click()  # descending
    expect(page.locator("#leaderboard tbody tr").first).to_contain_text("oracle")
    page.locator("#leaderboard th", has_text="User").click()
    assert _first_column(page) == ["oracle", "test-assistant (user test-user)"]  # "oracle" < "test-user"
    page.locator("#leaderboard tbody tr", has_text="oracle").locator("td:nth-child(5) a").click()
    expect(page.locator("#episodes tbody tr")).to_have_count(4)  # the oracle's successful episodes
    expect(page.locator("select[name=success]")).to_have_value("yes")
