"""Lazy re-exports for package ``__init__`` modules.

A package such as :mod:`pare.scenarios` offers its main names at the top (``from pare.scenarios import
Scenario``) but importing one of its modules (``pare.scenarios.seed_format``) must not import all the
others: the command line would pay for the whole library on every ``pare --help``. Each name is imported
from its module on first use.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from typing import Any


def lazy_exports(
    package: str, exports: Mapping[str, str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``__getattr__`` and ``__dir__`` for ``package`` that import each of ``exports`` (name -> module,
    relative to the package, e.g. ``{"Scenario": "model"}``) when first asked for.
    """
    namespace: dict[str, Any] = {}

    def __getattr__(name: str) -> Any:
        if name in namespace:
            return namespace[name]
        module = exports.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(f"{package}.{module}"), name)
        namespace[name] = value
        return value

    def __dir__() -> list[str]:
        return sorted(exports)

    return __getattr__, __dir__
