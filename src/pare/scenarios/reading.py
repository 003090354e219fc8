"""Reading logged calls with the app data they concern: whom each told what, and which files it carried.

A call's arguments say what was typed, not what happened: a reply names no recipient, a forward carries
no text of its own, a group message names a conversation, not its members, and an attachment is a path.
A :class:`CallReader` reads them as they landed, from the app data: the checks' reader from the final
state, the world's (its reactive events, the oracle's conditions) from the episode's live apps, each call
read once, just after it was made.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Mapping
from typing import TYPE_CHECKING, Any

from pare.scenarios.file_identity import ATTACHMENT_FIELDS, FileIdentity
from pare.scenarios.told import AppState, Delivery, delivery
from pare.sim.log import LogEntry

if TYPE_CHECKING:
    from pare.env import Environment


class CallReader:
    """Reads the calls of one episode's log against app data (see the module's docstring)."""

    __slots__ = ("_args", "_deliveries", "files", "state")

    def __init__(self, state: AppState, files: FileIdentity) -> None:
        self.state = state
        self.files = files
        self._deliveries: dict[int, Delivery | None] = {}
        self._args: dict[tuple[int, bool], Mapping[str, Any]] = {}

    @classmethod
    def of_state(cls, state: Callable[[], Mapping[str, Any]], files: FileIdentity) -> CallReader:
        """A reader of the episode's final state, which ``state()`` gives (taken only if needed)."""
        return cls(lambda app: _app(state(), app), files)

    @classmethod
    def live(cls, env: Environment, files: FileIdentity) -> CallReader:
        """A reader of ``env``'s apps as they are when a call is first read (just after it was made).

        It holds ``env`` weakly: the environment's scheduler holds the readers of its reactive events.
        """
        reference = weakref.ref(env)

        def state(app: str) -> Mapping[str, Any] | None:
            live = reference()
            if live is None or app not in live.apps:
                return None
            return live.apps[app].snapshot(shared=True)

        return cls(state, files)

    def delivery(self, entry: LogEntry) -> Delivery | None:
        """What ``entry`` delivered to whom (:func:`~pare.scenarios.told.delivery`), read once."""
        if entry.index not in self._deliveries:
            self._deliveries[entry.index] = delivery(entry, self.state)
        return self._deliveries[entry.index]

    def args(self, entry: LogEntry, *, told: bool) -> Mapping[str, Any]:
        """``entry``'s arguments with attached paths read as files (:mod:`~pare.scenarios.file_identity`);
        with ``told``, a sending call's ``content`` and ``attachments`` as delivered.
        """
        key = (entry.index, told)
        known = self._args.get(key)
        if known is not None:
            return known
        args: Mapping[str, Any] = entry.args
        sent = self.delivery(entry) if told else None
        if sent is not None:
            args = sent.as_args(args)
        if any(name in args for name in ATTACHMENT_FIELDS):
            args = {**args, **{name: self.attached(args[name]) for name in ATTACHMENT_FIELDS if name in args}}
        self._args[key] = args
        return args

    def attached(self, value: Any) -> Any:
        """An attachments value read as the files it names (:meth:`FileIdentity.read`)."""
        files = self.state("files")
        return self.files.read(value, (files or {}).get("files") or {})


def _app(state: Mapping[str, Any], app: str) -> Mapping[str, Any] | None:
    data = state.get(app)
    return data if isinstance(data, Mapping) else None


_LIVE: weakref.WeakKeyDictionary[Environment, CallReader] = weakref.WeakKeyDictionary()
"""The world's reader of each environment built from a scenario."""


def register_live(env: Environment, files: FileIdentity) -> CallReader:
    """Make (and keep, while ``env`` lives) the reader of ``env``'s world."""
    reader = _LIVE[env] = CallReader.live(env, files)
    return reader


def live_reader(env: Environment) -> CallReader:
    """The reader of ``env``'s world (one that knows no world files if ``env`` was not built from a
    scenario).
    """
    reader = _LIVE.get(env)
    return reader if reader is not None else register_live(env, FileIdentity({}))
