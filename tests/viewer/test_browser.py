"""End to end in headless Chromium (Debian's package, driven by Playwright): ``pare view`` serving runs
made by the tests, and the static export opened from disk. The browser may reach only the viewer.
"""

from __future__ import annotations

import functools
import http.server
import os
import re
import subprocess
import sys
import threading
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, Page, Route, expect, sync_playwright

from pare.cli import main
from tests.viewer.runs import WORLD_SCENARIO, Runs

CHROMIUM = "/usr/bin/chromium"
ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--disable-dev-shm-usage",  # containers often have a small /dev/shm
]
SCREENSHOT_ENV = "PARE_VIEWER_SCREENSHOT"
"""Where to save the episode's screenshot as well (the README's image is made this way)."""


@pytest.fixture(scope="module")
def browser() -> Iterator[Browser]:
    assert Path(CHROMIUM).exists(), "Chromium is installed by scripts/setup-dev.sh (apt-get install chromium)"
    with sync_playwright() as playwright:
        launched = playwright.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        yield launched
        launched.close()


@pytest.fixture(scope="module")
def server(runs: Runs, tmp_path_factory: pytest.TempPathFactory) -> Iterator[str]:
    """``pare view`` on both runs, as a user starts it; yields the URL it prints."""
    command = [sys.executable, "-u", "-m", "pare", "view", str(runs.oracle), str(runs.models)]
    log = tmp_path_factory.mktemp("server") / "stderr.txt"
    with (
        log.open("w", encoding="utf-8") as errors,
        subprocess.Popen(command, stdout=subprocess.PIPE, stderr=errors, text=True) as process,
    ):
        try:
            assert process.stdout is not None
            line = process.stdout.readline()
            found = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
            assert found, line + log.read_text(encoding="utf-8")
            yield found.group(0)
        finally:
            process.terminate()
            process.wait(timeout=10)


def _only_local(route: Route) -> None:
    url = route.request.url
    if url.startswith(("http://127.0.0.1:", "file://", "about:")):
        route.continue_()
    else:
        route.abort()


@pytest.fixture
def page(browser: Browser) -> Iterator[Page]:
    context = browser.new_context(viewport={"width": 1400, "height": 1000})
    context.route("**/*", _only_local)
    context.set_default_timeout(5_000)
    opened = context.new_page()
    errors: list[str] = []
    opened.on("pageerror", lambda error: errors.append(str(error)))
    yield opened
    context.close()
    assert not errors, errors


def _read_a_failed_episode(page: Page, start: str, shot: Path) -> None:
    """The user's path: runs page, the model run's table, filter it, open an episode, read it."""
    page.goto(start)
    expect(page.locator("#configurations tbody tr")).to_have_count(2)
    page.get_by_role("link", name=re.compile("test-assistant")).click()
    rows = page.locator("#episodes tbody tr")
    expect(rows).to_have_count(4)
    page.fill("input[name=scenario]", "five_a_side")
    expect(rows).to_have_count(2)
    page.select_option("select[name=decision]", "accept")
    expect(rows).to_have_count(2)
    page.fill("input[name=scenario]", "")
    page.select_option("select[name=app]", "email")
    expect(rows).to_have_count(2)
    page.select_option("select[name=app]", "")
    page.select_option("select[name=success]", "no")
    expect(rows).to_have_count(4)
    page.locator("th[data-sort=goal_rate]").click()
    page.locator("th[data-sort=goal_rate]").click()  # descending: the scenario with a goal met first
    expect(rows.first.locator("td").first).to_have_text("five_a_side_kickoff_moved")
    page.fill("input[name=scenario]", "dentist")
    expect(rows).to_have_count(2)
    rows.first.get_by_role("link").click()

    expect(page.locator("h1")).to_contain_text("dentist_moves_checkup")
    proposal = page.locator(".step.proposal .proposal-box").first
    expect(proposal).to_contain_text("I can take care of what just came in for you")
    expect(proposal.locator(".decision")).to_have_text("decision: accept")
    expect(proposal.locator(".resolution")).to_have_text("resolution: accepted")
    failed = page.locator(".check.failed").first
    expect(failed.locator(".verdict")).to_have_text("fail")
    expect(failed.locator(".detail")).to_contain_text("calendar.events: 0 of 18 items match")
    expect(page.locator(".phone .proposal-sheet").first).to_contain_text("I can take care of")
    expect(page.locator(".phone .notification").first).to_contain_text("brightsmile")
    expect(page.locator(".execute-group .task").first).to_contain_text("proposal-1")
    page.screenshot(path=str(shot), full_page=False)
    assert shot.stat().st_size > 10_000
    if os.environ.get(SCREENSHOT_ENV):
        page.screenshot(path=os.environ[SCREENSHOT_ENV], full_page=False)


def test_a_served_run_reads_from_the_runs_page_to_a_failed_check(
    server: str, page: Page, tmp_path: Path
) -> None:
    _read_a_failed_episode(page, server, tmp_path / "episode.png")
    page.locator(".evidence a, .log-ref").first.click()
    assert "#log-" in page.url or "#step-" in page.url or page.url.endswith(".html")


def test_the_table_keeps_its_filters_in_the_address(server: str, page: Page) -> None:
    page.goto(server + "c/models/index.html#success=no&scenario=five")
    expect(page.locator("#episodes tbody tr")).to_have_count(2)
    expect(page.locator("input[name=scenario]")).to_have_value("five")


def test_compare_shows_both_configurations_side_by_side(server: str, page: Page) -> None:
    page.goto(server + "c/models/e/dentist_moves_checkup/run-2.html")
    page.locator("#compare-go").click()
    summary = page.locator("#compare-summary")
    expect(summary).to_contain_text("oracle")
    expect(summary.locator("tr", has_text="success")).to_contain_text("no")
    left = page.frame_locator("#left")
    right = page.frame_locator("#right")
    expect(left.locator("h1")).to_contain_text("dentist_moves_checkup")
    expect(left.locator("h1 .verdict")).to_have_text("failure")
    expect(right.locator("h1 .verdict")).to_have_text("success")


def test_the_exported_site_opens_from_disk(runs: Runs, page: Page, tmp_path: Path) -> None:
    site = tmp_path / "site"
    assert main(["view", str(runs.oracle), str(runs.models), "--export", str(site)]) == 0
    _read_a_failed_episode(page, (site / "index.html").as_uri(), tmp_path / "exported.png")


def test_the_state_diff_links_a_friends_reply_to_its_event(
    world_run: Path, page: Page, tmp_path: Path
) -> None:
    site = tmp_path / "site"
    assert main(["view", str(world_run), "--export", str(site)]) == 0
    page.goto((site / "c" / "oracle" / "e" / WORLD_SCENARIO / "run-1.html").as_uri())
    reply = page.locator("#changes tr", has_text="msg-ana-tue")
    expect(reply.locator("td.credits")).to_have_text(re.compile(r"^event ana_tuesday #\d+$"))
    mine = page.locator("#changes tr", has_text='"msg-1"')
    expect(mine.locator("td.credits")).to_have_text(re.compile(r"^assistant #\d+$"))
    reply.locator("td.credits a").click()
    target = page.url.rsplit("#", 1)[1]
    expect(page.locator(f"#{target} td").nth(3)).to_have_text("env")
    expect(page.locator(f"#{target}")).to_contain_text("ana_tuesday")


def test_a_page_of_another_site_cannot_read_the_episodes_table(
    server: str, page: Page, tmp_path: Path
) -> None:
    """A page on another origin loads every way it can reach the table (with the key guessed, without
    it); none gives it a row. The viewer's own page, loaded just before in the same browser, does.
    """
    page.goto(server + "c/models/index.html")
    expect(page.locator("#episodes tbody tr")).to_have_count(4)
    evil = tmp_path / "evil"
    evil.mkdir()
    target = server + "c/models/rows.js"
    (evil / "index.html").write_text(
        f'<!doctype html><script src="{target}"></script><script src="{target}?key=guess"></script>'
        '<script src="read.js"></script>',
        encoding="utf-8",
    )
    (evil / "read.js").write_text(
        "document.title = JSON.stringify(window.PARE_ROWS || null);", encoding="utf-8"
    )
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=str(evil))
    with http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler) as other:
        threading.Thread(target=other.serve_forever, daemon=True).start()
        try:
            page.goto(f"http://127.0.0.1:{other.server_address[1]}/index.html")
            expect(page).to_have_title("null")
        finally:
            other.shutdown()
