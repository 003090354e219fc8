"""A tiny app for kernel and environment tests: a notebook of items with two screens."""

from __future__ import annotations

from pydantic import BaseModel, Field

from pare.apps.base import App
from pare.apps.screens import BACK, Screen, Transition, action, back, push, stay
from pare.apps.tools import tool
from pare.errors import ToolError


class NotebookState(BaseModel):
    items: dict[str, str] = Field(default_factory=dict)


class NotebookApp(App):
    """Items with text."""

    name = "notebook"
    title = "Notebook"
    State = NotebookState
    state: NotebookState

    @tool("read")
    def list_items(self) -> dict[str, str]:
        """List every item.

        Returns:
            item ids and texts.
        """
        return dict(self.state.items)

    @tool("write")
    def add_item(self, text: str, count: int = 1) -> list[str]:
        """Add items.

        Args:
            text: the text of the item.
            count: how many copies to add.
        """
        if not text:
            raise ToolError("An item needs text.")
        added = []
        for _ in range(count):
            item_id = self.new_id("item", self.state.items)
            self.state.items[item_id] = text
            added.append(item_id)
        return added

    @tool("env", actors=())
    def arrive(self, text: str, sender: str = "Ada") -> str:
        """An item arrives from someone else.

        Args:
            text: the text.
            sender: who sent it.
        """
        item_id = self.new_id("item", self.state.items)
        self.state.items[item_id] = text
        self.notify(
            "new_item", f"New item from {sender}", subject="Item", body=text, data={"item_id": item_id}
        )
        return item_id


class Index(Screen):
    name = "Index"

    @action(kind="read")
    def show(self, app: NotebookApp) -> dict[str, str]:
        """Show the items."""
        return app.list_items()

    @action("Page")
    def open_item(self, app: NotebookApp, item_id: str) -> Transition:
        """Open an item.

        Args:
            item_id: the item.
        """
        if item_id not in app.state.items:
            raise ToolError(f"No item {item_id}.")
        return push(Page(item_id=item_id))

    @action("Page")
    def broken_jump(self, app: NotebookApp) -> Transition:
        """Declares Page but stays: a declaration bug the environment must catch."""
        return stay("oops")


class Page(Screen):
    name = "Page"
    item_id: str
    draft: str = ""

    @action()
    def type_text(self, app: NotebookApp, text: str) -> str:
        """Type into the draft.

        Args:
            text: what to type.
        """
        self.draft += text
        if "!" in text:
            raise ToolError("No shouting.")
        return self.draft

    @action(BACK, kind="write")
    def save_copy(self, app: NotebookApp) -> Transition:
        """Save the draft as a new item and go back."""
        return back(app.add_item(self.draft or app.state.items[self.item_id]))


NotebookApp.set_screens(Index, Page)


class AlarmState(BaseModel):
    alarms: list[str] = Field(default_factory=list)
    """ISO times, sorted; each rings once."""


class AlarmApp(App):
    """Alarms that ring at their simulated time: the wakeup hook."""

    name = "alarm"
    title = "Alarm"
    State = AlarmState
    state: AlarmState
    wakeup_tool = "ring"

    def next_wakeup(self):  # type: ignore[no-untyped-def]
        from datetime import datetime

        return datetime.fromisoformat(self.state.alarms[0]) if self.state.alarms else None

    @tool("read")
    def list_alarms(self) -> list[str]:
        """List alarms.

        Returns:
            the alarm times.
        """
        return list(self.state.alarms)

    @tool("write")
    def set_alarm(self, at: str) -> str:
        """Set an alarm.

        Args:
            at: ISO time.
        """
        self.state.alarms = sorted([*self.state.alarms, at])
        return at

    @tool("env", actors=())
    def ring(self) -> list[str]:
        """Ring every alarm that is due."""
        from datetime import datetime

        now = self.ctx.now()
        rung = [a for a in self.state.alarms if datetime.fromisoformat(a) <= now]
        self.state.alarms = [a for a in self.state.alarms if a not in rung]
        for alarm in rung:
            self.notify("alarm", f"Alarm {alarm}")
        return rung
