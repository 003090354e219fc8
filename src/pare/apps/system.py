"""The phone shell: home screen, opening and switching apps, going home and back, the time."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel

from pare.apps.base import App
from pare.apps.screens import Screen
from pare.apps.tools import tool
from pare.errors import ToolError, did_you_mean

HOME = "home"


class _NoData(BaseModel):
    pass


def _on_home(shell: SystemApp) -> bool:
    return shell.foreground is None


def _in_app(shell: SystemApp) -> bool:
    return shell.foreground is not None


def _has_background(shell: SystemApp) -> bool:
    return bool(shell.background)


def _can_go_back(shell: SystemApp) -> bool:
    return shell.foreground is not None and len(shell.stacks[shell.foreground]) > 1


class SystemApp(App):
    """The phone's shell. It holds the user's navigation state: which app is in the foreground, which
    apps are open in the background (most recent last), and each open app's back stack of screens.
    """

    name = "system"
    title = "System"
    description = "Home screen, app switching, navigation and the clock."
    State = _NoData

    def __init__(self, ctx: Any = None) -> None:
        super().__init__(ctx)
        self.foreground: str | None = None
        self.background: list[str] = []
        self.stacks: dict[str, list[Screen]] = {}

    # -- what the environment asks ------------------------------------------------------------------
    def openable_apps(self) -> list[str]:
        """Apps with screens, in registration order."""
        return [name for name, app in self.ctx.apps.items() if app.screens]

    def current_screen(self) -> Screen | None:
        """The screen the user is looking at, or ``None`` on the home screen."""
        return None if self.foreground is None else self.stacks[self.foreground][-1]

    def location(self) -> str:
        """Where the user is, e.g. ``home`` or ``email > Mailbox(folder='INBOX')``."""
        screen = self.current_screen()
        return HOME if screen is None else f"{self.foreground} > {screen.label()}"

    def snapshot(self, *, shared: bool = False) -> dict[str, Any]:
        """The navigation state (not app data), always the caller's own."""
        return {
            "foreground": self.foreground,
            "background": list(self.background),
            "stacks": {app: [s.label() for s in stack] for app, stack in self.stacks.items()},
        }

    def _check_app(self, app_name: str) -> str:
        openable = self.openable_apps()
        if app_name not in openable:
            raise ToolError(
                f"There is no app called '{app_name}' on this phone.{did_you_mean(app_name, openable)} "
                f"Apps: {', '.join(openable)}."
            )
        return app_name

    # -- the user's shell tools ---------------------------------------------------------------------
    @tool("ui", actors=("user",), available=_on_home)
    def open_app(self, app_name: str) -> str:
        """Open an app from the home screen. Only available on the home screen. An app that was opened
        before and is still in the background is resumed on the screen where you left it; otherwise it
        opens on its main screen.

        Args:
            app_name: the app to open, e.g. "email" or "messaging".

        Returns:
            the screen you are now on.
        """
        self._check_app(app_name)
        if app_name in self.stacks:
            self.background.remove(app_name)
        else:
            self.stacks[app_name] = [self.ctx.apps[app_name].root_screen()]
        self.foreground = app_name
        return self.location()

    @tool("ui", actors=("user",), available=_has_background)
    def switch_app(self, app_name: str) -> str:
        """Switch to an app that is already open in the background, on the screen where you left it.
        You cannot switch to the home screen this way; use go_home.

        Args:
            app_name: the background app to bring to the foreground.

        Returns:
            the screen you are now on.
        """
        if app_name == HOME:
            raise ToolError("Use go_home to return to the home screen.")
        self._check_app(app_name)
        if app_name == self.foreground:
            raise ToolError(f"'{app_name}' is already the app on screen.")
        if app_name not in self.background:
            raise ToolError(
                f"'{app_name}' is not open in the background; open it from the home screen. "
                f"Background apps: {', '.join(self.background) or 'none'}."
            )
        self.background.remove(app_name)
        if self.foreground is not None:
            self.background.append(self.foreground)
        self.foreground = app_name
        return self.location()

    @tool("ui", actors=("user",), available=_in_app)
    def go_home(self) -> str:
        """Go to the home screen. The current app stays open in the background.

        Returns:
            confirmation that you are on the home screen.
        """
        assert self.foreground is not None
        self.background.append(self.foreground)
        self.foreground = None
        return HOME

    @tool("ui", actors=("user",), available=_can_go_back)
    def go_back(self) -> str:
        """Go back to the previous screen of the current app.

        Returns:
            the screen you are now on.
        """
        assert self.foreground is not None
        self.stacks[self.foreground].pop()
        return self.location()

    @tool("read", actors=("user", "assistant"))
    def get_current_time(self) -> str:
        """Get the current date and time.

        Returns:
            the current time in ISO 8601 format.
        """
        return self.ctx.now().isoformat()

    @tool("control", actors=("user", "assistant"))
    def wait(self) -> str:
        """Do nothing for now and let time pass until something happens.

        Returns:
            confirmation that you are waiting.
        """
        return "waiting"
