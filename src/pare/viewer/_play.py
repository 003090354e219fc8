"""A person plays the user in the browser (``pare play --browser``): the viewer's phone made interactive.

:class:`BrowserUser` is the user policy: each step it puts the phone on the page and waits until the
person submits an action. The page (``GET /``) shows the phone as the viewer draws it, what the user model
would read this turn, the pending proposal with accept and reject, and one form per action on offer with a
field per argument; ``POST /act`` plays the form's action (a slip, such as a missing argument, is shown on
the page and asked again, as at the terminal), ``POST /quit`` leaves, ``POST /close`` stops the server
once the episode is over, and ``GET /state.json`` says where the episode stands. The page needs no script:
plain forms, and a page that reloads itself while the assistant acts.

The server listens on the loopback interface only and takes requests that name it as their host; the
forms carry a key made when the server started, so no other site can act in the person's name.
"""

from __future__ import annotations

import asyncio
import secrets
import socket
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from importlib import resources
from typing import Any, Literal, TypeVar
from urllib.parse import parse_qsl

from jinja2 import Environment as Templates
from jinja2 import PackageLoader, StrictUndefined, select_autoescape
from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import JSONResponse, PlainTextResponse, RedirectResponse, Response
from starlette.routing import Route

from pare.agents.human_input import HumanInputError, SeatLeft, action_from_fields, argument_fields
from pare.agents.policy import DEFAULT_BUDGET, Action, Ending, TurnBudget, UserPolicy
from pare.agents.terminal_user import HUMAN, closing_text, observation_text, readable
from pare.env import Environment, ToolResult, UserView
from pare.results.trajectory import ActionRecord, LogRecord, StepRecord, ViewRecord
from pare.viewer._episode import Phone, _Screen
from pare.viewer._server import SECURITY_HEADERS, _host_names
from pare.viewer._site import pretty, short

SeatState = Literal["starting", "your_turn", "assistant", "ended"]
PAGE_WAIT_S = 30.0
"""How long an action's request waits for the next screen before the page shows the assistant at work
(and reloads itself until the screen is there)."""
RELOAD_S = 1
PLAY_HEADERS = {
    **SECURITY_HEADERS,
    "Content-Security-Policy": (
        "default-src 'none'; style-src 'self'; img-src 'self' data:; form-action 'self'; "
        "frame-ancestors 'none'; base-uri 'none'"
    ),
}
STATIC = {"viewer.css": "text/css", "play.css": "text/css"}
_OWN_SITE = ("same-origin", "none")
ANSWERS = ("accept_proposal", "reject_proposal")

T = TypeVar("T")


@dataclass
class Outcome:
    """What the page shows once the episode is over and recorded."""

    lines: list[str]
    success: bool | None = None


@dataclass
class _Seen:
    """One step the person took, as the viewer's phone follows what the screen shows."""

    step: StepRecord
    entry: LogRecord | None


@dataclass
class BrowserUser(UserPolicy):
    """The user played by a person in the browser; the server's handlers answer its steps."""

    persona: str | None = None
    goal: str | None = None
    state: SeatState = "starting"
    version: int = 0
    """Counts the screens shown: a form carries the version it was made for, so a stale one is refused."""
    view: UserView | None = None
    previous: ToolResult | None = None
    error: str | None = None
    """The last slip, shown on the page until the next screen."""
    ending: str | None = None
    outcome: Outcome | None = None
    budget: TurnBudget = DEFAULT_BUDGET
    left: bool = False
    seen: list[_Seen] = field(default_factory=list)
    _answer: asyncio.Future[Action] | None = None
    _changed: asyncio.Event = field(default_factory=asyncio.Event)
    _last_view: ViewRecord | None = None

    name = HUMAN

    def start(self, env: Environment, budget: TurnBudget = DEFAULT_BUDGET) -> None:
        """Keep the episode's limits, told on the page."""
        self.budget = budget

    async def step(self, view: UserView, previous: ToolResult | None) -> Action:
        """Put the phone on the page and wait for the person's action."""
        if self._last_view is not None and previous is not None:
            step = _step(self._last_view, previous.observation(), ok=previous.ok)
            entry = previous.entry
            self.seen.append(
                _Seen(step, None if entry is None else LogRecord.model_validate(entry, from_attributes=True))
            )
        self.view, self.previous = view, previous
        self._answer = asyncio.get_running_loop().create_future()
        self._show("your_turn")
        try:
            action = await self._answer
        finally:
            self._answer = None
        self._last_view = _view_record(view)
        self.error = None
        self._show("assistant")
        return action

    def finish(self, ending: Ending, previous: ToolResult | None, notifications: list[str]) -> str | None:
        """Show the end of the session with the last result and what arrived since."""
        self.ending = closing_text(ending, previous, notifications)
        self._show("ended")
        return None

    # -- what the handlers do ------------------------------------------------------------------------------
    def act(self, version: int, tool: str, typed: dict[str, str]) -> None:
        """Play the action a form submitted, if it can be played now.

        Raises:
            HumanInputError: Not the person's turn, a form of an earlier screen, or the action is not
                valid on this screen.
        """
        if self.state != "your_turn" or self._answer is None or self.view is None:
            raise HumanInputError("It is not your turn: the assistant is acting, or the session is over.")
        if version != self.version:
            raise HumanInputError("That form was for an earlier screen; here is the current one.")
        action = action_from_fields(self.view, tool, typed)
        self._answer.set_result(action)

    def leave(self) -> None:
        """The person leaves the seat: the episode stops and nothing is recorded."""
        self.left = True
        if self._answer is not None and not self._answer.done():
            self._answer.set_exception(SeatLeft())

    async def changed(self, since: int, timeout: float) -> None:
        """Return once the page has moved on from version ``since`` (or after ``timeout`` seconds)."""
        while self.version == since and self.state != "ended":
            event = self._changed
            try:
                await asyncio.wait_for(event.wait(), timeout)
            except TimeoutError:
                return

    def ended(self, outcome: Outcome) -> None:
        """The episode is over and recorded: ``outcome`` is what the page says about it."""
        self.outcome = outcome
        self._show("ended")

    def _show(self, state: SeatState) -> None:
        self.state = state
        self.version += 1
        event, self._changed = self._changed, asyncio.Event()
        event.set()

    # -- what the page shows -------------------------------------------------------------------------------
    def phone(self) -> Phone | None:
        """The phone now, drawn as the viewer draws a recorded step (what earlier steps revealed on the
        screen stays on view until the person moves on).
        """
        if self.view is None:
            return None
        screen = _Screen()
        for seen in self.seen:
            screen.before(seen.step, seen.entry)
        return screen.before(_step(_view_record(self.view), ""), None)

    def forms(self) -> list[dict[str, Any]]:
        """One form per action on offer: its name, what it does, and its argument fields."""
        if self.view is None:
            return []
        forms = [
            {
                "tool": tool.name,
                "signature": tool.spec.signature,
                "summary": tool.spec.summary,
                "fields": argument_fields(tool),
            }
            for tool in self.view.tools
        ]
        # the answers to a waiting proposal first: the page's most urgent choice, in view without scrolling
        return sorted(forms, key=lambda form: form["tool"] not in ANSWERS)

    def snapshot(self) -> dict[str, Any]:
        """Where the episode stands, as ``GET /state.json`` gives it."""
        view = self.view
        return {
            "state": self.state,
            "version": self.version,
            "turn": view.turn.turn if view is not None and view.turn is not None else None,
            "tools": view.tool_names if view is not None and self.state == "your_turn" else [],
            "pending_proposal": view.pending_proposal if view is not None else None,
            "error": self.error,
            "ending": self.ending,
            "outcome": None if self.outcome is None else self.outcome.lines,
            "success": None if self.outcome is None else self.outcome.success,
        }


def _view_record(view: UserView) -> ViewRecord:
    """What the viewer's phone reads of a view (the fields a trajectory keeps of it)."""
    return ViewRecord(
        time=view.time,
        app=view.app,
        screen=view.screen,
        background_apps=view.background_apps,
        screen_update=view.screen_update,
        notifications=view.notifications,
        pending_proposal=view.pending_proposal,
        tools=view.tool_names,
    )


def _step(view: ViewRecord, observation: str, *, ok: bool = True) -> StepRecord:
    """A user's step as the viewer's phone follows it: the view before it and what it was told after."""
    return StepRecord(
        turn=0, actor="user", action=ActionRecord(tool=""), ok=ok, observation=observation, view=view
    )


# -- the web app ------------------------------------------------------------------------------------------
def _templates() -> Templates:
    templates = Templates(
        loader=PackageLoader("pare.viewer", "templates"),
        autoescape=select_autoescape(default=True),
        undefined=StrictUndefined,
        trim_blocks=True,
        lstrip_blocks=True,
    )
    templates.filters.update(pretty=pretty, short=short)
    return templates


def create_play_app(user: BrowserUser, *, bound: str = "127.0.0.1", key: str | None = None) -> Starlette:
    """The ASGI app of the play page for ``user``; requests must name the loopback (or ``bound``) as their
    host, and every form carries ``key`` (made here when not given).
    """
    token = key or secrets.token_urlsafe(18)
    templates = _templates()
    closed = asyncio.Event()

    async def page(request: Request) -> Response:
        if refusal := _cross_site(request):
            return PlainTextResponse(refusal, status_code=403, headers=PLAY_HEADERS)
        body = templates.get_template("play.html").render(
            user=user,
            phone=user.phone(),
            observation=readable(observation_text(user.previous, user.view)) if user.view else "",
            forms=user.forms() if user.state == "your_turn" else [],
            token=token,
            reload=RELOAD_S if user.state in ("starting", "assistant") else None,
            closed=closed.is_set(),
        )
        return Response(body, media_type="text/html; charset=utf-8", headers=PLAY_HEADERS)

    async def state(request: Request) -> Response:
        if refusal := _cross_site(request):
            return PlainTextResponse(refusal, status_code=403, headers=PLAY_HEADERS)
        return JSONResponse(user.snapshot(), headers=PLAY_HEADERS)

    async def static(request: Request) -> Response:
        name = request.path_params["name"]
        if name not in STATIC:
            return PlainTextResponse("not found", status_code=404, headers=PLAY_HEADERS)
        body = resources.files("pare.viewer").joinpath("static", name).read_bytes()
        return Response(body, media_type=STATIC[name], headers=PLAY_HEADERS)

    async def act(request: Request) -> Response:
        form = await _form(request, token)
        if isinstance(form, Response):
            return form
        since = user.version
        try:
            version = int(form.pop("version", "-1"))
            tool = form.pop("tool", "")
            typed = {name[len("arg.") :]: value for name, value in form.items() if name.startswith("arg.")}
            user.act(version, tool, typed)
        except (HumanInputError, ValueError) as error:
            user.error = str(error)
            return _back()
        await user.changed(since, PAGE_WAIT_S)
        return _back()

    async def leave(request: Request) -> Response:
        form = await _form(request, token)
        if isinstance(form, Response):
            return form
        user.leave()
        await user.changed(user.version, 1.0)
        return _back()

    async def close(request: Request) -> Response:
        form = await _form(request, token)
        if isinstance(form, Response):
            return form
        if user.state != "ended":
            user.error = "The session is not over yet: finish it, or leave with Quit."
            return _back()
        closed.set()
        return _back()

    app = Starlette(
        routes=[
            Route("/", page, methods=["GET", "HEAD"]),
            Route("/state.json", state, methods=["GET"]),
            Route("/static/{name}", static, methods=["GET"]),
            Route("/act", act, methods=["POST"]),
            Route("/quit", leave, methods=["POST"]),
            Route("/close", close, methods=["POST"]),
        ],
        middleware=[Middleware(TrustedHostMiddleware, allowed_hosts=_host_names(bound))],
    )
    app.state.closed = closed
    return app


async def _awaited(episode: Callable[[], Awaitable[T]]) -> T:
    return await episode()


def _back() -> Response:
    return RedirectResponse("/", status_code=303, headers=PLAY_HEADERS)


def _cross_site(request: Request) -> str | None:
    """Why a request must not be answered: it comes from a page of another site."""
    fetch_site = request.headers.get("sec-fetch-site")
    navigating = request.headers.get("sec-fetch-mode") in (None, "navigate")
    if (
        fetch_site is not None
        and fetch_site not in _OWN_SITE
        and not (navigating and request.method == "GET")
    ):
        return "refused: the play page answers its own pages only"
    return None


async def _form(request: Request, token: str) -> dict[str, str] | Response:
    """The posted form's fields, or the refusal of a request that is not the play page's own."""
    if refusal := _cross_site(request):
        return PlainTextResponse(refusal, status_code=403, headers=PLAY_HEADERS)
    body = (await request.body()).decode("utf-8", "replace")
    form = dict(parse_qsl(body, keep_blank_values=True))
    given = form.pop("token", "")
    if not secrets.compare_digest(given.encode(), token.encode()):
        return PlainTextResponse(
            "refused: this form was not made by this play session's page",
            status_code=403,
            headers=PLAY_HEADERS,
        )
    return form


async def serve_episode(
    user: BrowserUser,
    sock: socket.socket,
    episode: Callable[[], Awaitable[T]],
    settle: Callable[[T], Outcome],
) -> T:
    """Serve the play page on ``sock`` while ``episode`` plays; once it ends, ``settle`` records it and
    says what the page shows; then serve until the person closes the page (or Ctrl-C).

    Raises:
        SeatLeft: The person left before the episode ended (the page says nothing was recorded).
    """
    import uvicorn

    bound = sock.getsockname()[0]
    app = create_play_app(user, bound=bound)
    config = uvicorn.Config(app, log_level="warning", access_log=False, lifespan="off")
    server = uvicorn.Server(config)
    serving = asyncio.create_task(server.serve(sockets=[sock]))
    playing = asyncio.create_task(_awaited(episode))
    try:
        await asyncio.wait({playing, serving}, return_when=asyncio.FIRST_COMPLETED)
        if not playing.done():  # the server stopped first (Ctrl+C): the episode cannot go on
            playing.cancel()
            await asyncio.wait({playing})
            raise KeyboardInterrupt
        try:
            result = playing.result()
        except SeatLeft:
            user.ended(Outcome(["You left before the session ended: nothing was recorded."]))
            await asyncio.sleep(0.5)  # the page that asked to leave is answered
            raise
        user.ended(settle(result))
        closed = asyncio.create_task(app.state.closed.wait())
        await asyncio.wait({closed, serving}, return_when=asyncio.FIRST_COMPLETED)
        closed.cancel()
        return result
    finally:
        server.should_exit = True
        await serving
