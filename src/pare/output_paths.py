"""Where a command writes: the folders and files named on its command line, made or written with a clear
error when the path cannot be one (a file where a folder is wanted, a folder where a file is, a path
through a file, a place the system refuses), instead of the system's exception.
"""

from __future__ import annotations

from pathlib import Path

from pare.errors import UserInputError


def make_output_folder(path: Path, what: str) -> None:
    """Make the folder ``path`` (with its parents) unless it exists; ``what`` names it in the error.

    Raises:
        UserInputError: ``path`` is a file, runs through a file, or cannot be made; the message says which.
    """
    try:
        path.mkdir(parents=True, exist_ok=True)
    except FileExistsError:
        raise UserInputError(f"{what} {path} is a file, not a folder: choose another path") from None
    except NotADirectoryError:
        raise UserInputError(f"{what} {path} cannot be made: a part of its path is a file") from None
    except OSError as error:
        raise UserInputError(f"{what} {path} cannot be made ({error.strerror or error})") from None


def write_output_file(path: Path, text: str, what: str = "the output file") -> None:
    """Write ``text`` (UTF-8) to the file ``path``, whose folder must exist; ``what`` names it in errors.

    Raises:
        UserInputError: ``path`` is a folder, its folder does not exist or is a file, or the system
            refused the write (no permission, no space); the message says which.
    """
    try:
        path.write_text(text, encoding="utf-8")
    except IsADirectoryError:
        raise UserInputError(f"{what} {path} is a folder: name a file") from None
    except FileNotFoundError:
        raise UserInputError(f"{what} {path} cannot be written: its folder does not exist") from None
    except NotADirectoryError:
        raise UserInputError(f"{what} {path} cannot be written: a part of its path is a file") from None
    except OSError as error:
        raise UserInputError(f"{what} {path} cannot be written ({error.strerror or error})") from None
