"""``pare play --browser`` end to end in headless Chromium (Debian's package, driven by Playwright): a
person plays a scenario on the page, the episode is recorded, and closing the page stops the command."""

from __future__ import annotations

import os
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest

from pare.results.run_folder import load_run

SCENARIO = "dentist_moves_checkup"
SCREENSHOT_ENV = "PARE_PLAY_SCREENSHOT"
"""Where to save a screenshot of the page with a proposal waiting (docs/images/play-browser.png)."""

playwright = pytest.importorskip("playwright.sync_api", reason="Playwright is installed with the dev tools")
from tests.viewer.test_browser import ARGS, CHROMIUM  # noqa: E402 - it needs Playwright too

pytestmark = pytest.mark.skipif(
    not Path(CHROMIUM).exists(),
    reason=f"Chromium is not installed at {CHROMIUM} (scripts/setup-dev.sh installs it)",
)


@pytest.fixture
def session(tmp_path: Path) -> Iterator[tuple[str, Path, subprocess.Popen[str]]]:
    """``pare play --browser`` as a person starts it; yields its URL, the run folder and the process."""
    folder = tmp_path / "run"
    command = [sys.executable, "-u", "-m", "pare", "play", SCENARIO, "--browser", "-o", str(folder)]
    with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True) as process:
        try:
            assert process.stdout is not None
            seen = []
            for line in process.stdout:
                seen.append(line)
                found = re.search(r"http://127\.0\.0\.1:\d+/", line)
                if found:
                    yield found.group(0), folder, process
                    break
            else:
                raise AssertionError("pare play printed no address:\n" + "".join(seen))
        finally:
            if process.poll() is None:
                process.terminate()
                process.wait(timeout=10)


def test_a_person_plays_on_the_phone_page_and_the_episode_is_recorded(
    session: tuple[str, Path, subprocess.Popen[str]],
) -> None:
    url, folder, process = session
    expect = playwright.expect
    with playwright.sync_playwright() as driver:
        browser = driver.chromium.launch(executable_path=CHROMIUM, args=ARGS)
        context = browser.new_context()
        context.route(
            "**/*",
            lambda route: (
                route.continue_() if route.request.url.startswith("http://127.0.0.1:") else route.abort()
            ),
        )
        context.set_default_timeout(15_000)
        page = context.new_page()
        page.goto(url)

        def act(tool: str, **args: str) -> None:
            expect(page.locator("#status")).to_contain_text("Your turn")
            form = page.locator(f'form[data-tool="{tool}"]')
            for name, value in args.items():
                form.locator(f'input[name="arg.{name}"]').fill(value)
            form.locator("button").click()

        expect(page.locator(".phone")).to_contain_text("Home screen")
        act("open_app", app_name="email")
        expect(page.locator(".phone")).to_contain_text("Mailbox")
        act("open_email", email_id="no-such-email")  # the app refuses it: played and recorded
        act("open_email", email_id="email-checkup-moves")
        expect(page.locator(".phone")).to_contain_text("Dr. Haddad")
        act("wait")
        expect(page.locator(".phone .proposal-sheet")).to_contain_text("Thursday 07:45")
        if shot := os.environ.get(SCREENSHOT_ENV):  # the documentation's image is made this way
            page.set_viewport_size({"width": 1280, "height": 900})
            page.screenshot(path=shot, full_page=False)
        act("accept_proposal")
        for _ in range(10):
            expect(page.locator("#status")).to_contain_text(re.compile("Your turn|session is over"))
            if page.locator("#outcome").count():
                break
            act("wait")
        expect(page.locator("#outcome")).to_contain_text("success: every goal met")
        page.locator("#close").click()
        browser.close()
    assert process.wait(timeout=15) == 0
    (episode,) = load_run(folder).records
    assert episode.success and episode.failed_steps == {"user": 1}
