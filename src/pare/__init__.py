"""PARE: the Proactive Agent Research Environment."""

from __future__ import annotations

__all__ = ["__version__"]


def __getattr__(name: str) -> str:
    # The version is read from the installed package's metadata when first asked for: importing
    # importlib.metadata costs more than the rest of ``import pare``, and most commands never need it.
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            found = version("pare-bench")
        except PackageNotFoundError:  # running from a source tree that is not installed
            found = "0.0.0+unknown"
        globals()["__version__"] = found
        return found
    raise AttributeError(f"module 'pare' has no attribute {name!r}")
