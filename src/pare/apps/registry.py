"""The app registry: names to app classes, imported lazily."""

from __future__ import annotations

import importlib

from pare.apps.base import App
from pare.errors import UserInputError, did_you_mean

CORE_APPS = ("system", "agent_ui", "files")
"""Apps every environment has: the phone shell, the assistant's channel to the user, and files."""

_APPS: dict[str, str] = {
    "system": "pare.apps.system:SystemApp",
    "agent_ui": "pare.apps.agent_ui:AgentUIApp",
    "files": "pare.apps.files:FilesApp",
    "email": "pare.apps.email:EmailApp",
    "messaging": "pare.apps.messaging:MessagingApp",
    "contacts": "pare.apps.contacts:ContactsApp",
    "calendar": "pare.apps.calendar:CalendarApp",
    "reminder": "pare.apps.reminder:ReminderApp",
    "notes": "pare.apps.notes:NotesApp",
    "shopping": "pare.apps.shopping:ShoppingApp",
    "cab": "pare.apps.cab:CabApp",
    "apartment": "pare.apps.apartment:ApartmentApp",
    "banking": "pare.apps.banking:BankingApp",
}


def app_names(*, include_core: bool = False) -> list[str]:
    """Names of the registered apps with screens (or, with ``include_core``, every app), in order."""
    return [name for name in _APPS if include_core or name not in CORE_APPS]


def phone_apps() -> list[str]:
    """The apps a phone shows: every app with screens, and Files (which has none)."""
    return [*app_names(), "files"]


_LOADED: dict[str, type[App]] = {}
"""App classes already imported, by name: every environment looks its apps up."""


def get_app_class(name: str) -> type[App]:
    """The app class registered as ``name``; a :class:`UserInputError` suggests close names."""
    known = _LOADED.get(name)
    if known is not None:
        return known
    target = _APPS.get(name)
    if target is None:
        choices = app_names()
        raise UserInputError(
            f"Unknown app '{name}'.{did_you_mean(name, choices)} Known apps: {', '.join(choices)}."
        )
    module_name, _, class_name = target.partition(":")
    cls: type[App] = getattr(importlib.import_module(module_name), class_name)
    _LOADED[name] = cls
    return cls
