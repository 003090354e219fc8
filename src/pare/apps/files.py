"""A minimal sandboxed in-memory file store for attachments.

Attachments in Email and Messaging refer to files here by path. Every path is confined to the sandbox:
``..`` that climbs above the root and absolute paths elsewhere are refused.
"""

from __future__ import annotations

from datetime import datetime

from pydantic import BaseModel, ConfigDict, Field

from pare.apps.base import App
from pare.apps.tools import tool
from pare.errors import ToolError


class StoredFile(BaseModel):
    """A file's text content and when it was last written."""

    model_config = ConfigDict(extra="forbid")

    content: str = ""
    modified: datetime | None = None


class FilesState(BaseModel):
    """Every file, keyed by its normalised path (``/Documents/lease.pdf``)."""

    model_config = ConfigDict(extra="forbid")

    files: dict[str, StoredFile] = Field(default_factory=dict)


def normalize_path(path: str) -> str:
    """The canonical sandbox path of ``path``; :class:`ToolError` when it would leave the sandbox."""
    if not path or not path.strip():
        raise ToolError("The path is empty.")
    if "\x00" in path or "\\" in path:
        raise ToolError(f"Invalid path {path!r}: use '/' as separator and no control characters.")
    parts: list[str] = []
    for part in path.strip().split("/"):
        if part in ("", "."):
            continue
        if part == "..":
            if not parts:
                raise ToolError(f"Path {path!r} leaves the phone's file storage.")
            parts.pop()
            continue
        parts.append(part)
    return "/" + "/".join(parts)


class FilesApp(App):
    """The phone's files (documents, downloads, attachments)."""

    name = "files"
    title = "Files"
    description = "Documents and attachments stored on the phone."
    State = FilesState
    state: FilesState

    def exists(self, path: str) -> bool:
        """Whether a file is stored at ``path``."""
        return normalize_path(path) in self.state.files

    def require(self, path: str) -> str:
        """The normalised path of an existing file; :class:`ToolError` naming it otherwise."""
        normalized = normalize_path(path)
        if normalized not in self.state.files:
            raise ToolError(f"No file at {normalized}. Use files__list_files to see what is stored.")
        return normalized

    def store(self, path: str, content: str) -> str:
        """Write ``content`` at ``path`` (creating or replacing it) and return the normalised path."""
        normalized = normalize_path(path)
        if normalized == "/":
            raise ToolError("A file needs a name, not just '/'.")
        self.state.files[normalized] = StoredFile(content=content, modified=self.ctx.now())
        return normalized

    @tool("read")
    def list_files(self, directory: str = "/") -> list[str]:
        """List the files stored under a directory, recursively.

        Args:
            directory: the directory to list, e.g. "/Downloads"; "/" lists everything.

        Returns:
            the paths of the files, sorted.
        """
        prefix = normalize_path(directory).rstrip("/") + "/"
        return sorted(path for path in self.state.files if path.startswith(prefix))

    @tool("read")
    def read_file(self, path: str) -> str:
        """Read a text file.

        Args:
            path: the file's path, e.g. "/Documents/agenda.txt".

        Returns:
            the file's content.
        """
        return self.state.files[self.require(path)].content

    @tool("write")
    def write_file(self, path: str, content: str) -> str:
        """Create or overwrite a text file.

        Args:
            path: where to write it, e.g. "/Documents/notes.txt".
            content: the text to store.

        Returns:
            the normalised path of the file.
        """
        return self.store(path, content)

    @tool("env", actors=())
    def create_file(self, path: str, content: str = "") -> str:
        """Create a file as part of a scenario's world (a document the user already has).

        Args:
            path: where to create it.
            content: the file's text.

        Returns:
            the normalised path of the file.
        """
        return self.store(path, content)
