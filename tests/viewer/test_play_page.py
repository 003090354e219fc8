"""``pare play --browser``'s page and endpoints, offline: the episode and the app share one event loop and
an in-process HTTP client plays the person, as the browser's forms would."""

from __future__ import annotations

import asyncio
from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any

import httpx

from pare.agents.human_input import SeatLeft
from pare.bench.play import PLAY_SETTINGS, Seat, play, prepare, record
from pare.bench.runconfig import build_config
from pare.results.run_folder import load_run
from pare.viewer._play import BrowserUser, create_play_app

SCENARIO = "dentist_moves_checkup"
KEY = "the-page-key"
ORIGIN = "http://127.0.0.1"


def _seat(folder: Path) -> Seat:
    overrides = [("scenarios", {"ids": [SCENARIO]}), ("output", str(folder)), *PLAY_SETTINGS]
    return prepare(build_config({}, overrides=overrides))


Session = Callable[[httpx.AsyncClient, BrowserUser], Awaitable[None]]


def _with_page(seat: Seat, session: Session) -> tuple[BrowserUser, Any]:
    """Play the seat's episode while ``session`` acts through the app; the user and what the episode
    gave (its output, or the exception that ended it)."""
    user = BrowserUser(persona="Sam", goal="Get the check-up moved.")
    app = create_play_app(user, key=KEY)

    async def main() -> Any:
        transport = httpx.ASGITransport(app=app)
        async with httpx.AsyncClient(transport=transport, base_url=ORIGIN) as client:
            episode = asyncio.create_task(play(seat, user))
            await session(client, user)
            try:
                return await asyncio.wait_for(episode, 30)
            except (Exception, SeatLeft) as error:
                return error

    return user, asyncio.run(main())


async def _state(client: httpx.AsyncClient) -> dict[str, Any]:
    for _ in range(200):
        state = (await client.get("/state.json")).json()
        if state["state"] not in ("starting", "assistant"):
            return state
        await asyncio.sleep(0.01)
    raise AssertionError("the page never came back to the person")


async def _act(client: httpx.AsyncClient, tool: str, key: str = KEY, **args: str) -> httpx.Response:
    state = await _state(client)
    form = {"token": key, "version": str(state["version"]), "tool": tool}
    form.update({f"arg.{name}": value for name, value in args.items()})
    return await client.post("/act", data=form)


def test_the_person_plays_the_episode_through_the_forms_and_it_is_recorded(tmp_path: Path) -> None:
    seat = _seat(tmp_path / "run")
    pages: list[str] = []

    async def session(client: httpx.AsyncClient, user: BrowserUser) -> None:
        first = await _state(client)
        assert first["turn"] == 1 and "open_app" in first["tools"]
        page = (await client.get("/")).text
        assert 'data-tool="open_app"' in page and 'name="arg.app_name"' in page
        assert "What the user model would read this turn" in page and "You are on the home screen." in page
        answered = await _act(client, "open_app", app_name="email")
        assert answered.status_code == 303 and answered.headers["location"] == "/"
        await _act(client, "open_email", email_id="email-checkup-moves")
        pages.append((await client.get("/")).text)  # the email open on the phone
        await _act(client, "wait")
        state = await _state(client)
        assert state["pending_proposal"] and "accept_proposal" in state["tools"]
        pages.append((await client.get("/")).text)
        await _act(client, "accept_proposal", reason="")
        for _ in range(10):
            if (await _state(client))["state"] != "your_turn":
                break
            await _act(client, "wait")

    user, output = _with_page(seat, session)
    assert not isinstance(output, BaseException), output
    assert user.state == "ended" and "The session is over" in (user.ending or "")
    assert "Your check-up tomorrow with Dr. Haddad" in pages[0]  # the phone shows the opened email
    assert "Assistant proposes" in pages[1]
    # the answers come first, in view without scrolling
    assert pages[1].index('data-tool="accept_proposal"') < pages[1].index('data-tool="refresh"')
    folder = record(seat, output)
    (episode,) = load_run(folder).records
    assert episode.success and [p.resolution for p in episode.proposals] == ["accepted"]
    assert load_run(folder).manifest["policies"]["user"] == "human"


def test_slips_stale_forms_and_foreign_requests_are_refused_and_the_person_asked_again(
    tmp_path: Path,
) -> None:
    seat = _seat(tmp_path / "run")

    async def session(client: httpx.AsyncClient, user: BrowserUser) -> None:
        state = await _state(client)
        assert (await _act(client, "open_app")).status_code == 303  # no app named
        assert "'app_name' is required" in (await _state(client))["error"]
        assert "&#39;app_name&#39; is required" in (await client.get("/")).text
        await _act(client, "open_mail")
        assert "Did you mean 'open_app'" in (await _state(client))["error"]
        stale = {"token": KEY, "version": str(state["version"] - 1), "tool": "wait"}
        await client.post("/act", data=stale)
        assert "earlier screen" in (await _state(client))["error"]
        assert (await _act(client, "wait", key="guessed")).status_code == 403
        foreign = {"token": KEY, "version": str(state["version"]), "tool": "wait"}
        refused = await client.post("/act", data=foreign, headers={"sec-fetch-site": "cross-site"})
        assert refused.status_code == 403
        elsewhere = await client.get("/state.json", headers={"host": "attacker.example"})
        assert elsewhere.status_code == 400
        assert (await _state(client))["turn"] == 1  # none of it was played
        await client.post("/quit", data={"token": KEY})

    user, output = _with_page(seat, session)
    assert isinstance(output, SeatLeft) and user.left
    assert not seat.folder.exists()


def test_the_page_says_what_the_server_sends(tmp_path: Path) -> None:
    seat = _seat(tmp_path / "run")

    async def session(client: httpx.AsyncClient, user: BrowserUser) -> None:
        await _state(client)
        page = await client.get("/")
        assert "form-action 'self'" in page.headers["content-security-policy"]
        assert (await client.get("/static/play.css")).status_code == 200
        assert (await client.get("/static/../_play.py")).status_code == 404
        assert (await client.get("/act")).status_code == 405
        closing = await client.post("/close", data={"token": KEY})
        assert closing.status_code == 303
        assert "not over yet" in (await _state(client))["error"]
        await client.post("/quit", data={"token": KEY})

    _, output = _with_page(seat, session)
    assert isinstance(output, SeatLeft)


def test_a_proposal_rejected_on_the_page_is_recorded_as_rejected(tmp_path: Path) -> None:
    seat = _seat(tmp_path / "run")

    async def session(client: httpx.AsyncClient, user: BrowserUser) -> None:
        await _act(client, "open_app", app_name="email")
        await _act(client, "open_email", email_id="email-checkup-moves")
        await _act(client, "wait")
        assert "reject_proposal" in (await _state(client))["tools"]
        await _act(client, "reject_proposal", reason="Not Thursday, please.")
        for _ in range(10):
            if (await _state(client))["state"] != "your_turn":
                break
            await _act(client, "wait")

    _, output = _with_page(seat, session)
    assert [proposal.resolution for proposal in output.record.proposals] == ["rejected"]
    assert not output.record.success
