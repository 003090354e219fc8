"""Files: the phone's sandboxed in-memory file system.

Documents, downloads and attachments live here; Email, Messaging and Notes refer to files by path. Every
path is confined to the sandbox rooted at ``/``: climbing above the root with ``..``, home (``~``), drive
(``C:``) and URL (``file://``) forms, backslashes and control characters are refused with a clear error.
Like the paper's FileSystem core app it has no screens: the assistant uses it through its flat API and
the user attaches files by path from the compose and edit screens of the other apps.
"""

from __future__ import annotations

import re
from datetime import datetime
from typing import cast

from pydantic import BaseModel, ConfigDict, Field, field_validator

from pare.apps.base import App
from pare.apps.done import Done
from pare.apps.tools import tool
from pare.errors import ToolError

MAX_PATH = 1024
MAX_NAME = 255
_FORBIDDEN_START = re.compile(r"^(~|[A-Za-z]:|[A-Za-z][A-Za-z0-9+.-]*://)")


def normalize_path(path: str) -> str:
    """The canonical sandbox path of ``path`` (``/Documents/a.txt``); :class:`ToolError` if it escapes."""
    if not path or not path.strip():
        raise ToolError("The path is empty.")
    text = path.strip()
    if len(text) > MAX_PATH:
        raise ToolError(f"The path is longer than {MAX_PATH} characters.")
    if any(ord(ch) < 32 for ch in text) or "\\" in text:
        raise ToolError(f"Invalid path {path!r}: use '/' as the separator and no control characters.")
    if _FORBIDDEN_START.match(text):
        raise ToolError(f"Path {path!r} is outside the phone's file storage; paths start at '/'.")
    parts: list[str] = []
    for part in text.split("/"):
        if part in ("", "."):
            continue
        if part == "..":
            if not parts:
                raise ToolError(f"Path {path!r} leaves the phone's file storage.")
            parts.pop()
            continue
        if len(part) > MAX_NAME:
            raise ToolError(f"The name {part[:20]!r}… is longer than {MAX_NAME} characters.")
        parts.append(part)
    return "/" + "/".join(parts)


def _parent(path: str) -> str:
    return path.rsplit("/", 1)[0] or "/"


def _ancestors(path: str) -> list[str]:
    """Every directory above ``path``, outermost first, without the root."""
    parts = path.strip("/").split("/")[:-1]
    return ["/" + "/".join(parts[: i + 1]) for i in range(len(parts))]


def _inside(path: str, directory: str) -> bool:
    return directory == "/" or path == directory or path.startswith(directory.rstrip("/") + "/")


class StoredFile(BaseModel):
    """A file's text content and when it was last written."""

    model_config = ConfigDict(extra="forbid")

    content: str = ""
    modified: datetime | None = None


class FilesState(BaseModel):
    """Every file by normalised path, and the directories (a file's parents exist implicitly)."""

    model_config = ConfigDict(extra="forbid")

    files: dict[str, StoredFile] = Field(default_factory=dict)
    directories: list[str] = Field(default_factory=list)

    @field_validator("files")
    @classmethod
    def _normalized_file_paths(cls, files: dict[str, StoredFile]) -> dict[str, StoredFile]:
        for path in files:
            try:
                canonical = normalize_path(path)
            except ToolError as error:
                raise ValueError(str(error)) from None
            if canonical != path or path == "/":
                raise ValueError(f"file path {path!r} must be written as {canonical!r}")
        return files

    @field_validator("directories")
    @classmethod
    def _normalized_directories(cls, directories: list[str]) -> list[str]:
        try:
            return sorted({normalize_path(d) for d in directories} - {"/"})
        except ToolError as error:
            raise ValueError(str(error)) from None


class DirectoryEntry(BaseModel):
    """One entry of a directory listing."""

    name: str
    path: str
    type: str = Field(description="file or directory")
    size: int | None = Field(default=None, description="characters, for files")
    modified: datetime | None = None


class FileInfo(BaseModel):
    """What is known about a file."""

    path: str
    size: int
    modified: datetime | None


class FilesApp(App):
    """The phone's files (documents, downloads, attachments)."""

    name = "files"
    title = "Files"
    description = "Documents, downloads and attachments stored on the phone (no screens; attach by path)."
    State = FilesState
    harm = {
        "write_file": "reversible",
        "make_directory": "reversible",
        "move": "reversible",
        "copy_file": "reversible",
        "delete": "irreversible",
    }
    state: FilesState

    # -- helpers used by other apps ------------------------------------------------------------------
    def exists(self, path: str) -> bool:
        """Whether a file is stored at ``path``."""
        return normalize_path(path) in self.state.files

    def require(self, path: str) -> str:
        """The normalised path of an existing file; :class:`ToolError` naming it otherwise."""
        normalized = normalize_path(path)
        if normalized not in self.state.files:
            if self.is_directory(normalized):
                raise ToolError(f"{normalized} is a directory, not a file.")
            raise ToolError(f"No file at {normalized}. Use files__list_directory to see what is stored.")
        return normalized

    def _dangling_note(self, gone: set[str], how: str) -> str:
        """What a move or delete of the files ``gone`` leaves pointing at nothing: attachments of emails,
        notes and messages are paths in Files, so they keep the old path and can no longer be opened,
        downloaded or forwarded. Said in the result so that whoever did it knows (empty when none).
        """
        holders: list[str] = []
        for app in self.ctx.apps.values():
            attached = getattr(app, "attached_paths", None)
            if attached is not None:
                holders.extend(holder for holder, path in attached() if path in gone)
        if not holders:
            return ""
        shown = ", ".join(holders[:5]) + (f" and {len(holders) - 5} more" if len(holders) > 5 else "")
        return f" Attachments still point at what you {how} and now show it as missing: {shown}."

    def missing_attachment(self, path: str, holder: str) -> ToolError:
        """The error for an attachment of ``holder`` whose file is no longer in Files."""
        return ToolError(
            f"The file {path} attached to {holder} is no longer in Files (it was moved or deleted after it "
            "was attached)."
        )

    def check_can_store(self, path: str) -> None:
        """Raise :class:`ToolError` when :meth:`store` at ``path`` would fail (so a caller storing several
        files can check them all before writing any).
        """
        self._check_can_hold_file(normalize_path(path))

    def store(self, path: str, content: str) -> str:
        """Write ``content`` at ``path`` (creating or replacing it) and return the normalised path."""
        normalized = normalize_path(path)
        self._check_can_hold_file(normalized)
        self.state.files[normalized] = StoredFile(content=content, modified=self.ctx.now())
        return normalized

    def is_directory(self, path: str) -> bool:
        """Whether ``path`` is a directory (made explicitly, or holding files)."""
        if path == "/" or path in self.state.directories:
            return True
        prefix = path + "/"
        return any(f.startswith(prefix) for f in self.state.files)

    def _check_can_hold_file(self, path: str) -> None:
        if path == "/":
            raise ToolError("A file needs a name, not just '/'.")
        if self.is_directory(path):
            raise ToolError(f"{path} is a directory; choose a file name inside it.")
        for ancestor in _ancestors(path):
            if ancestor in self.state.files:
                raise ToolError(f"{ancestor} is a file, so it cannot contain {path}.")

    def _entries_under(self, directory: str) -> tuple[list[str], list[str]]:
        files = sorted(p for p in self.state.files if _inside(p, directory) and p != directory)
        directories = sorted(d for d in self.state.directories if _inside(d, directory) and d != directory)
        return files, directories

    # -- agent API: reading ----------------------------------------------------------------------------
    @tool("read")
    def list_directory(self, path: str = "/") -> list[DirectoryEntry]:
        """List what a directory directly contains: its files and sub-directories.

        Args:
            path: the directory, e.g. "/Documents"; "/" is the top of the phone's storage.

        Returns:
            the entries, directories first, each with its name, full path, type and (for files) size.
        """
        directory = normalize_path(path)
        if directory in self.state.files:
            raise ToolError(f"{directory} is a file; use files__read_file to read it.")
        if not self.is_directory(directory):
            raise ToolError(f"No directory at {directory}.")
        depth = 0 if directory == "/" else directory.count("/")
        files, directories = self._entries_under(directory)
        children = {
            "/" + "/".join(p.strip("/").split("/")[: depth + 1])
            for p in files + directories
            if p != directory
        }
        entries = []
        for child in sorted(children):
            if child in self.state.files:
                stored = self.state.files[child]
                entries.append(
                    DirectoryEntry(
                        name=child.rsplit("/", 1)[1],
                        path=child,
                        type="file",
                        size=len(stored.content),
                        modified=stored.modified,
                    )
                )
            else:
                entries.append(DirectoryEntry(name=child.rsplit("/", 1)[1], path=child, type="directory"))
        return sorted(entries, key=lambda e: (e.type != "directory", e.name.lower(), e.path))

    @tool("read")
    def list_files(self, directory: str = "/") -> list[str]:
        """List every file under a directory, at any depth.

        Args:
            directory: the directory to list, e.g. "/Downloads"; "/" lists everything.

        Returns:
            the paths of the files, sorted.
        """
        normalized = normalize_path(directory)
        if normalized in self.state.files:
            raise ToolError(f"{normalized} is a file, not a directory.")
        return self._entries_under(normalized)[0]

    @tool("read")
    def read_file(self, path: str) -> str:
        """Read a text file.

        Args:
            path: the file's path, e.g. "/Documents/agenda.txt".

        Returns:
            the file's content.
        """
        return self.state.files[self.require(path)].content

    @tool("read")
    def get_file_info(self, path: str) -> FileInfo:
        """Get a file's size and when it was last changed.

        Args:
            path: the file's path.

        Returns:
            the path, size in characters and modification time.
        """
        normalized = self.require(path)
        stored = self.state.files[normalized]
        return FileInfo(path=normalized, size=len(stored.content), modified=stored.modified)

    # -- agent API: writing ----------------------------------------------------------------------------
    @tool("write")
    def write_file(self, path: str, content: str, overwrite: bool = True) -> Done:
        """Create or overwrite a text file. Missing parent directories are created.

        Args:
            path: where to write it, e.g. "/Documents/notes.txt".
            content: the text to store.
            overwrite: replace an existing file at that path (when false, an existing file is an error).

        Returns:
            what was written where, and the file's normalised path as its id.
        """
        normalized = normalize_path(path)
        existed = normalized in self.state.files
        if not overwrite and existed:
            raise ToolError(f"{normalized} already exists; pass overwrite=true to replace it.")
        stored = self.store(normalized, content)
        verb = "Replaced" if existed else "Created"
        return Done(done=f"{verb} {stored} ({len(content)} characters).", id=stored)

    @tool("write")
    def make_directory(self, path: str) -> Done:
        """Create a directory (and any missing parents).

        Args:
            path: the directory to create, e.g. "/Documents/Taxes".

        Returns:
            what was made, and the directory's normalised path as its id.
        """
        normalized = normalize_path(path)
        if normalized == "/" or self.is_directory(normalized):
            raise ToolError(f"The directory {normalized} already exists.")
        if normalized in self.state.files:
            raise ToolError(f"{normalized} is a file; a directory cannot have the same path.")
        self._check_can_hold_file(normalized)  # no file above
        self.state.directories = sorted({*self.state.directories, normalized})
        return Done(done=f"Created directory {normalized}.", id=normalized)

    @tool("write")
    def move(self, source: str, destination: str) -> Done:
        """Move or rename a file or a directory (with everything in it).

        Args:
            source: the file or directory to move.
            destination: its new path; an existing directory receives the source inside it.

        Returns:
            what was moved where, and the new path as its id.
        """
        src = normalize_path(source)
        dst = normalize_path(destination)
        is_file = src in self.state.files
        if not is_file and (src == "/" or not self.is_directory(src)):
            raise ToolError(f"Nothing to move at {src}." if src != "/" else "The root cannot be moved.")
        if self.is_directory(dst):
            dst = (
                (dst.rstrip("/") + "/" + src.rsplit("/", 1)[1]) if dst != "/" else "/" + src.rsplit("/", 1)[1]
            )
        if dst == src:
            raise ToolError(f"{src} is already there.")
        if not is_file and _inside(dst, src):
            raise ToolError(f"A directory cannot be moved inside itself ({src} -> {dst}).")
        if dst in self.state.files or self.is_directory(dst):
            raise ToolError(f"{dst} already exists; delete it first or choose another name.")
        for ancestor in _ancestors(dst):
            if ancestor in self.state.files:
                raise ToolError(f"{ancestor} is a file, so it cannot contain {dst}.")
        if is_file:
            self.state.files[dst] = self.state.files.pop(src)
            return Done(done=f"Moved {src} to {dst}." + self._dangling_note({src}, "moved away from"), id=dst)
        files, directories = self._entries_under(src)
        for path in files:
            self.state.files[dst + path[len(src) :]] = self.state.files.pop(path)
        moved = [dst + d[len(src) :] for d in directories]
        kept = [d for d in self.state.directories if d != src and d not in directories]
        self.state.directories = sorted({*kept, *moved, dst})
        note = self._dangling_note(set(files), "moved away from")
        return Done(done=f"Moved directory {src} and {len(files)} files to {dst}." + note, id=dst)

    @tool("write")
    def copy_file(self, source: str, destination: str) -> Done:
        """Copy a file.

        Args:
            source: the file to copy.
            destination: the new file's path (an existing directory receives a copy with the same name).

        Returns:
            what was copied where, and the copy's path as its id.
        """
        src = self.require(source)
        dst = normalize_path(destination)
        if self.is_directory(dst):
            dst = (
                (dst.rstrip("/") + "/" + src.rsplit("/", 1)[1]) if dst != "/" else "/" + src.rsplit("/", 1)[1]
            )
        if dst in self.state.files:
            raise ToolError(f"{dst} already exists; choose another name.")
        copied = self.store(dst, self.state.files[src].content)
        return Done(done=f"Copied {src} to {copied}.", id=copied)

    @tool("write")
    def delete(self, path: str, recursive: bool = False) -> str:
        """Delete a file, or a directory (which must be empty unless recursive is true).

        Args:
            path: the file or directory to delete.
            recursive: also delete everything inside a directory.

        Returns:
            what was deleted.
        """
        normalized = normalize_path(path)
        if normalized in self.state.files:
            del self.state.files[normalized]
            return f"Deleted file {normalized}." + self._dangling_note({normalized}, "deleted")
        if normalized == "/":
            raise ToolError("The root of the phone's storage cannot be deleted.")
        if not self.is_directory(normalized):
            raise ToolError(f"Nothing to delete at {normalized}.")
        files, directories = self._entries_under(normalized)
        if (files or directories) and not recursive:
            raise ToolError(
                f"The directory {normalized} is not empty ({len(files)} files); "
                "pass recursive=true to delete everything in it."
            )
        for file_path in files:
            del self.state.files[file_path]
        gone = {normalized, *directories}
        self.state.directories = [d for d in self.state.directories if d not in gone]
        return f"Deleted directory {normalized} and {len(files)} files." + self._dangling_note(
            set(files), "deleted"
        )

    # -- the world -------------------------------------------------------------------------------------
    @tool("env", actors=())
    def create_file(self, path: str, content: str = "") -> str:
        """Create a file as part of a scenario's world (a document the user already has, a download).

        Args:
            path: where to create it.
            content: the file's text.

        Returns:
            the normalised path of the file.
        """
        return self.store(path, content)


def files_of(app: App) -> FilesApp:
    """The Files app of the phone ``app`` runs on, where attachments live."""
    files = app.ctx.apps.get("files")
    if files is None:
        raise ToolError("Attachments need the Files app, which this phone does not have.")
    return cast(FilesApp, files)


def browse(app: App, directory: str) -> list[DirectoryEntry]:
    """What a compose or edit screen shows when the user looks for a file to attach."""
    return files_of(app).list_directory(directory)
