"""Notes: the user's notes, in folders, with attachments (files in the Files app)."""

from __future__ import annotations

from collections.abc import Iterable
from datetime import datetime
from typing import Any

from pydantic import BaseModel, ConfigDict, Field, field_validator, model_validator

from pare.apps.base import App, DatedRecord
from pare.apps.done import Done
from pare.apps.files import DirectoryEntry, FilesApp, browse, files_of, normalize_path
from pare.apps.paging import Paged, showing_screen
from pare.apps.screens import BACK, Screen, Transition, action, back, back_to, push, replace
from pare.apps.text import PAGE, preview, short_time
from pare.apps.tools import tool
from pare.apps.types import SimTime
from pare.errors import ToolError

DEFAULT_FOLDER = "Notes"
"""The folder new notes go to; it cannot be deleted or renamed."""


class Note(BaseModel):
    """A note: a title, free text and attached files."""

    model_config = ConfigDict(extra="forbid")

    note_id: str
    title: str
    content: str = ""
    folder: str = DEFAULT_FOLDER
    attachments: list[str] = Field(default_factory=list, description="Paths of files in the Files app.")
    created_at: SimTime
    updated_at: SimTime
    pinned: bool = Field(default=False, description="pinned notes are listed first in their folder")

    @field_validator("attachments")
    @classmethod
    def _normalized_paths(cls, paths: list[str]) -> list[str]:
        cleaned: list[str] = []
        for path in paths:
            try:
                normalized = normalize_path(path)
            except ToolError as error:
                raise ValueError(str(error)) from None
            if normalized in cleaned:
                raise ValueError(f"{normalized} is attached twice")
            cleaned.append(normalized)
        return cleaned

    @model_validator(mode="after")
    def _updated_after_created(self) -> Note:
        if self.updated_at < self.created_at:
            raise ValueError(f"note '{self.note_id}' is updated before it was created")
        return self


class NotesState(BaseModel):
    """The folders, in the order the phone shows them, and every note by id."""

    model_config = ConfigDict(extra="forbid")

    folders: list[str] = Field(default_factory=lambda: [DEFAULT_FOLDER, "Personal", "Work"])
    notes: dict[str, Note] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _consistent(self) -> NotesState:
        seen: set[str] = set()
        for folder in self.folders:
            if not folder.strip() or folder != folder.strip():
                raise ValueError(f"folder name {folder!r} is empty or has surrounding spaces")
            if folder.casefold() in seen:
                raise ValueError(f"folder '{folder}' is listed twice (names are case-insensitive)")
            seen.add(folder.casefold())
        if DEFAULT_FOLDER not in self.folders:
            raise ValueError(f"the default folder '{DEFAULT_FOLDER}' is missing from folders")
        for key, note in self.notes.items():
            if key != note.note_id:
                raise ValueError(f"note stored under '{key}' has note_id '{note.note_id}'")
            if note.folder not in self.folders:
                raise ValueError(
                    f"note '{key}' is in folder '{note.folder}', which is not one of {self.folders}"
                )
        return self


class NotePage(Paged):
    """One page of a folder's notes, or of every folder's."""

    rows_field = "notes"

    folder: str | None = Field(description="the folder listed; null when the notes of every folder are")
    notes: list[Note]
    total: int
    offset: int


class FolderInfo(BaseModel):
    """A folder and how many notes it holds."""

    name: str
    note_count: int


class NoteDraft(BaseModel):
    """A note being written or edited, not saved yet."""

    note_id: str | None = Field(description="the note being edited; null for a new note")
    folder: str
    title: str
    content: str
    attachments: list[str]


def _newest_first(notes: Iterable[Note]) -> list[Note]:
    """Most recently updated first; on a tie, the most recently created, then by id."""
    by_id = sorted(notes, key=lambda n: n.note_id)
    return sorted(by_id, key=lambda n: (n.updated_at, n.created_at), reverse=True)


class NotesApp(App):
    """The notes app."""

    name = "notes"
    title = "Notes"
    description = "The user's notes, organised in folders, with attached files."
    State = NotesState
    harm = {
        "create_note": "reversible",
        "update_note": "reversible",
        "delete_note": "irreversible",
        "move_note": "reversible",
        "duplicate_note": "reversible",
        "new_folder": "reversible",
        "rename_folder": "reversible",
        "delete_folder": "reversible",  # only an empty folder: new_folder makes it again
        "add_attachment_to_note": "reversible",
        "remove_attachment": "reversible",
    }
    also_writes = ("files",)
    state: NotesState

    # -- helpers used by other apps and screens -----------------------------------------------------
    def attached_paths(self) -> list[tuple[str, str]]:
        """Every (holder, path) of a file a note has attached."""
        return [(f"note '{n.note_id}'", path) for n in self.state.notes.values() for path in n.attachments]

    def records_dated_after(self, now: datetime) -> list[DatedRecord]:
        """See :meth:`App.records_dated_after`."""
        return [
            DatedRecord(
                ("notes", key, "created_at" if note.created_at > now else "updated_at"),
                f"note '{note.note_id}' created or updated "
                f"{max(note.created_at, note.updated_at):%Y-%m-%d %H:%M}",
            )
            for key, note in self.state.notes.items()
            if max(note.created_at, note.updated_at) > now
        ]

    def require(self, note_id: str) -> Note:
        """Return the note with ``note_id``; raise a :class:`ToolError` naming it otherwise."""
        note = self.state.notes.get(note_id)
        if note is None:
            raise ToolError(f"No note with id '{note_id}'. Use search_notes or list_notes to find note ids.")
        return note

    def folder_named(self, name: str) -> str:
        """Return the folder called ``name`` (any case) as it is spelled; :class:`ToolError` otherwise."""
        wanted = name.strip().casefold()
        for folder in self.state.folders:
            if folder.casefold() == wanted:
                return folder
        raise ToolError(f"No folder named '{name.strip()}'. Folders: {', '.join(self.state.folders)}.")

    def files(self) -> FilesApp:
        """Return the Files app, where attachments live."""
        return files_of(self)

    def in_folder(self, folder: str | None) -> list[Note]:
        """Return the notes of ``folder`` (of every folder for ``None``) as listed: pinned first, then most
        recently updated first.
        """
        notes = _newest_first(n for n in self.state.notes.values() if folder is None or n.folder == folder)
        return [n for n in notes if n.pinned] + [n for n in notes if not n.pinned]

    def folder_counts(self) -> dict[str, int]:
        """How many notes each folder holds, in the order the app shows the folders."""
        counts = {folder: 0 for folder in self.state.folders}
        for note in self.state.notes.values():
            counts[note.folder] += 1
        return counts

    def _check_new_folder_name(self, name: str, *, renaming: str | None = None) -> str:
        """Return ``name`` stripped, refusing an empty name or one another folder has (any case)."""
        cleaned = name.strip()
        if not cleaned:
            raise ToolError("A folder needs a name.")
        for folder in self.state.folders:
            if folder.casefold() == cleaned.casefold() and folder != renaming:
                raise ToolError(f"A folder named '{folder}' already exists.")
        return cleaned

    @staticmethod
    def check_not_empty(title: str, content: str) -> None:
        """Raise a :class:`ToolError` if both ``title`` and ``content`` are blank."""
        if not title.strip() and not content.strip():
            raise ToolError("A note needs a title or some content; both are empty.")

    # -- agent API: notes ----------------------------------------------------------------------------
    @tool("write")
    def create_note(self, title: str, content: str = "", folder: str = DEFAULT_FOLDER) -> Done:
        """Create a note.

        Args:
            title: the note's title, e.g. "Packing list". May be empty if the content is not.
            content: the note's text.
            folder: the folder to put it in (case-insensitive), e.g. "Work"; list_folders lists them.

        Returns:
            what was created in which folder, and the new note's id.
        """
        self.check_not_empty(title, content)
        target = self.folder_named(folder)
        now = self.ctx.now()
        note_id = self.new_id("note", self.state.notes)
        self.state.notes[note_id] = Note(
            note_id=note_id,
            title=title.strip(),
            content=content,
            folder=target,
            created_at=now,
            updated_at=now,
        )
        return Done(done=f"Created note {note_id} '{title.strip()}' in folder '{target}'.", id=note_id)

    @tool("read")
    def get_note_by_id(self, note_id: str) -> Note:
        """Get one note, with its full content and attachments.

        Args:
            note_id: the note's id.

        Returns:
            the note.
        """
        return self.require(note_id)

    @tool("write")
    def update_note(self, note_id: str, title: str | None = None, content: str | None = None) -> Note:
        """Change a note's title, its content, or both; what is not given is kept.

        The content given replaces the whole text: to add a line, pass the old content with the line added.

        Args:
            note_id: the note to change.
            title: the new title.
            content: the new full content.

        Returns:
            the note as it is now.
        """
        note = self.require(note_id)
        if title is None and content is None:
            raise ToolError("Nothing to change: give a new title, new content, or both.")
        new_title = note.title if title is None else title.strip()
        new_content = note.content if content is None else content
        self.check_not_empty(new_title, new_content)
        if (new_title, new_content) != (note.title, note.content):
            note.title, note.content = new_title, new_content
            note.updated_at = self.ctx.now()
        return note

    @tool("write")
    def delete_note(self, note_id: str) -> str:
        """Delete a note for good (its attached files stay in Files).

        Args:
            note_id: the note to delete.

        Returns:
            confirmation.
        """
        note = self.require(note_id)
        del self.state.notes[note_id]
        return f"Deleted note {note_id} ({note.title or 'untitled'})."

    @tool("read")
    def list_notes(self, folder: str = DEFAULT_FOLDER, offset: int = 0, limit: int = PAGE) -> NotePage:
        """List the notes of a folder, a page at a time: pinned notes first, then most recently updated.

        Args:
            folder: the folder (case-insensitive), e.g. "Personal"; list_folders lists them.
            offset: how many notes to skip.
            limit: how many notes to return (1-100).

        Returns:
            the folder, the page of notes, and the total number of notes in the folder.
        """
        name = self.folder_named(folder)
        if offset < 0 or not 1 <= limit <= 100:
            raise ToolError("offset must be >= 0 and limit between 1 and 100.")
        notes = self.in_folder(name)
        return NotePage(folder=name, notes=notes[offset : offset + limit], total=len(notes), offset=offset)

    @tool("read")
    def search_notes(self, query: str) -> list[Note]:
        """Search the notes of every folder by title and content.

        The search is case-insensitive and every word of the query must appear in the title or content.
        It matches parts of words too: "Priya" finds "Priyanka".

        Args:
            query: words to look for, e.g. "wifi password" or "lisbon".

        Returns:
            the matching notes, most recently updated first.
        """
        words = query.casefold().split()
        if not words:
            raise ToolError("The search query is empty.")
        found = [
            note
            for note in self.state.notes.values()
            if all(word in f"{note.title}\n{note.content}".casefold() for word in words)
        ]
        return _newest_first(found)

    @tool("write")
    def move_note(self, note_id: str, folder: str) -> Note:
        """Move a note to another folder.

        Args:
            note_id: the note to move.
            folder: the destination folder (case-insensitive); list_folders lists them.

        Returns:
            the note as it is now.
        """
        note = self.require(note_id)
        target = self.folder_named(folder)
        if note.folder == target:
            raise ToolError(f"Note '{note_id}' is already in {target}.")
        note.folder = target
        return note

    @tool("write")
    def duplicate_note(self, note_id: str) -> Done:
        """Copy a note into the same folder; the copy is titled "<title> (copy)" and has the same attachments.

        Args:
            note_id: the note to copy.

        Returns:
            what was copied where, and the copy's id.
        """
        note = self.require(note_id)
        now = self.ctx.now()
        copy_id = self.new_id("note", self.state.notes)
        self.state.notes[copy_id] = Note(
            note_id=copy_id,
            title=f"{note.title} (copy)".strip(),
            content=note.content,
            folder=note.folder,
            attachments=list(note.attachments),
            created_at=now,
            updated_at=now,
        )
        copy = self.state.notes[copy_id]
        return Done(
            done=f"Copied note {note_id} as {copy_id} '{copy.title}' in folder '{copy.folder}'.", id=copy_id
        )

    # -- agent API: folders --------------------------------------------------------------------------
    @tool("read")
    def list_folders(self) -> list[FolderInfo]:
        """List the folders with how many notes each holds.

        Returns:
            the folders, in the order the app shows them.
        """
        return [FolderInfo(name=folder, note_count=count) for folder, count in self.folder_counts().items()]

    @tool("write")
    def new_folder(self, name: str) -> Done:
        """Create an empty folder.

        Args:
            name: the folder's name, e.g. "Recipes"; it must differ (ignoring case) from existing folders.

        Returns:
            what was created, and the new folder's name (folders go by name).
        """
        cleaned = self._check_new_folder_name(name)
        self.state.folders.append(cleaned)
        return Done(done=f"Created the empty folder '{cleaned}'.", id=cleaned)

    @tool("write")
    def rename_folder(self, name: str, new_name: str) -> str:
        """Rename a folder; its notes stay in it. The default "Notes" folder cannot be renamed.

        Args:
            name: the folder to rename (case-insensitive).
            new_name: its new name, which no other folder may have (ignoring case).

        Returns:
            confirmation.
        """
        old = self.folder_named(name)
        if old == DEFAULT_FOLDER:
            raise ToolError(f"The default folder '{DEFAULT_FOLDER}' cannot be renamed.")
        new = self._check_new_folder_name(new_name, renaming=old)
        if new == old:
            raise ToolError(f"The folder is already called '{old}'.")
        self.state.folders[self.state.folders.index(old)] = new
        moved = 0
        for note in self.state.notes.values():
            if note.folder == old:
                note.folder = new
                moved += 1
        return f"Renamed folder '{old}' to '{new}' ({moved} note{'' if moved == 1 else 's'})."

    @tool("write")
    def delete_folder(self, name: str) -> str:
        """Delete an empty folder. The default "Notes" folder cannot be deleted.

        Move or delete a folder's notes first (move_note, delete_note) to delete it.

        Args:
            name: the folder to delete (case-insensitive).

        Returns:
            confirmation.
        """
        folder = self.folder_named(name)
        if folder == DEFAULT_FOLDER:
            raise ToolError(f"The default folder '{DEFAULT_FOLDER}' cannot be deleted.")
        count = sum(1 for note in self.state.notes.values() if note.folder == folder)
        if count:
            raise ToolError(
                f"Folder '{folder}' still holds {count} note{'' if count == 1 else 's'}; move them to "
                "another folder (move_note) or delete them (delete_note) before deleting the folder."
            )
        self.state.folders.remove(folder)
        return f"Deleted folder '{folder}'."

    # -- agent API: attachments ----------------------------------------------------------------------
    @tool("write")
    def add_attachment_to_note(self, note_id: str, path: str) -> Note:
        """Attach a file from the Files app to a note.

        Args:
            note_id: the note.
            path: the file's path in Files, e.g. "/Documents/floor_plan.pdf".

        Returns:
            the note as it is now.
        """
        note = self.require(note_id)
        stored = self.files().require(path)
        if stored in note.attachments:
            raise ToolError(f"{stored} is already attached to note '{note_id}'.")
        note.attachments.append(stored)
        note.updated_at = self.ctx.now()
        return note

    @tool("write")
    def remove_attachment(self, note_id: str, path: str) -> Note:
        """Remove an attached file from a note (the file itself stays in Files).

        Args:
            note_id: the note.
            path: the attachment's path, as list_attachments shows it.

        Returns:
            the note as it is now.
        """
        note = self.require(note_id)
        target = normalize_path(path)
        if target not in note.attachments:
            attached = ", ".join(note.attachments) or "none"
            raise ToolError(f"{target} is not attached to note '{note_id}'. Attachments: {attached}.")
        note.attachments.remove(target)
        note.updated_at = self.ctx.now()
        return note

    @tool("read")
    def list_attachments(self, note_id: str) -> list[str]:
        """List the files attached to a note.

        Args:
            note_id: the note.

        Returns:
            the attachments' paths in the Files app, in the order they were attached.
        """
        return list(self.require(note_id).attachments)

    # -- the world -----------------------------------------------------------------------------------
    @tool("env", actors=())
    def update_shared_note(self, note_id: str, content: str, editor: str) -> Note:
        """Someone the note is shared with changes its text. The user is notified.

        Args:
            note_id: the shared note.
            content: the note's new full content.
            editor: the name of the person who edited it, e.g. "Carol Rivera".

        Returns:
            the note as it is now.
        """
        note = self.require(note_id)
        who = editor.strip()
        if not who:
            raise ToolError("editor cannot be empty.")
        self.check_not_empty(note.title, content)
        note.content = content
        note.updated_at = self.ctx.now()
        self.notify(
            "note_updated",
            f"{who} edited a shared note",
            subject=note.title or "Untitled note",
            body=content,
            data={"note_id": note_id},
        )
        return note


# -- screens -----------------------------------------------------------------------------------------


def _row(note: Note) -> dict[str, Any]:
    """A note as the list shows it: title, folder, when it was last changed and the start of its text."""
    row: dict[str, Any] = {
        "note_id": note.note_id,
        "title": note.title,
        "folder": note.folder,
        "updated": short_time(note.updated_at),
        "preview": preview(note.content),
    }
    if note.pinned:
        row["pinned"] = True
    if note.attachments:
        row["attachments"] = len(note.attachments)
    return row


class NoteList(Screen):
    """The notes of one folder, or of every folder (where the app opens, so that the user's notes show
    wherever they are filed).
    """

    name = "List"
    title = "Notes"
    folder: str | None = Field(default=None, description="the folder shown; None shows every folder's notes")

    def label(self) -> str:
        """``List(folder='Work')``, or ``List(all folders)`` rather than a bare None."""
        return super().label() if self.folder is not None else f"{self.screen_name()}(all folders)"

    def display(self, app: NotesApp) -> dict[str, Any]:
        """The first notes listed (pinned first, then most recently updated), each with its folder and a
        preview, the total, and every folder with its note count.
        """
        folder = self.folder
        if folder is not None and folder not in app.state.folders:
            return {"folder": folder, "gone": "This folder no longer exists.", "folders": app.folder_counts()}
        notes = app.in_folder(folder)
        return {
            "folder": folder or "all folders",
            "total": len(notes),
            "notes": [_row(note) for note in notes[:PAGE]],
            **showing_screen(notes[:PAGE], len(notes), "list_notes(offset={offset})"),
            "folders": app.folder_counts(),
        }

    @action(kind="read")
    def list_notes(self, app: NotesApp, offset: int = 0, limit: int = PAGE) -> NotePage:
        """Show a page of the notes on screen (this folder's, or every folder's): pinned first, then most
        recently updated.

        Args:
            offset: how many notes to skip.
            limit: how many to show.
        """
        if self.folder is not None:
            return app.list_notes(self.folder, offset=offset, limit=limit)
        if offset < 0 or not 1 <= limit <= 100:
            raise ToolError("offset must be >= 0 and limit between 1 and 100.")
        notes = app.in_folder(None)
        return NotePage(folder=None, notes=notes[offset : offset + limit], total=len(notes), offset=offset)

    @action(kind="read")
    def search_notes(self, app: NotesApp, query: str) -> list[Note]:
        """Search the notes of every folder by title and content. It matches parts of words too: "Priya"
        finds "Priyanka".

        Args:
            query: what to look for.
        """
        return app.search_notes(query)

    @action("Detail")
    def open_note(self, app: NotesApp, note_id: str) -> Transition:
        """Open a note.

        Args:
            note_id: the note's id.
        """
        return push(NoteDetail(note_id=note_id), app.require(note_id))

    @action("Edit")
    def new_note(self, app: NotesApp) -> Transition:
        """Start writing a new note in this folder (in "Notes" when every folder is shown)."""
        draft = NoteEdit(folder=app.folder_named(self.folder or DEFAULT_FOLDER))
        return push(draft, draft.draft())

    @action("Folders")
    def list_folders(self, app: NotesApp) -> Transition:
        """Show the folders."""
        return push(FolderList(), app.list_folders())


class FolderList(Screen):
    """Every folder, with how many notes each holds."""

    name = "Folders"
    title = "Folders"

    def display(self, app: NotesApp) -> list[FolderInfo]:
        """Every folder with its note count, as list_folders shows them."""
        return app.list_folders()

    @action(kind="read")
    def list_folders(self, app: NotesApp) -> list[FolderInfo]:
        """Show the folders with their note counts."""
        return app.list_folders()

    @action("List")
    def show_all_notes(self, app: NotesApp) -> Transition:
        """Show the notes of every folder together, as the app does when it opens."""
        return back_to("List", None, NoteList())

    @action("List")
    def open_folder(self, app: NotesApp, folder: str) -> Transition:
        """Show the notes of a folder.

        Args:
            folder: the folder's name, e.g. "Work".
        """
        page = app.list_notes(folder)
        return back_to("List", page, NoteList(folder=page.folder))


class NoteDetail(Screen):
    """One note."""

    name = "Detail"
    title = "Note"
    note_id: str

    def display(self, app: NotesApp) -> Note | str:
        """The note in full, as open_note shows it (or a line saying it is gone)."""
        note = app.state.notes.get(self.note_id)
        return note if note is not None else f"Note {self.note_id} no longer exists."

    @action(kind="read")
    def refresh(self, app: NotesApp) -> Note:
        """Show this note as it is now."""
        return app.require(self.note_id)

    @action(kind="read")
    def list_attachments(self, app: NotesApp) -> list[str]:
        """Show the files attached to this note."""
        return app.list_attachments(self.note_id)

    @action(kind="read")
    def browse_files(self, app: NotesApp, directory: str = "/") -> list[DirectoryEntry]:
        """Look through the files on your phone to find one to attach.

        Args:
            directory: the folder to look in, e.g. "/Documents"; "/" is the top.
        """
        return browse(app, directory)

    @action(kind="write")
    def add_attachment(self, app: NotesApp, path: str) -> Note:
        """Attach a file from your files to this note.

        Args:
            path: the file's path, e.g. "/Documents/floor_plan.pdf".
        """
        return app.add_attachment_to_note(self.note_id, path)

    @action(kind="write")
    def remove_attachment(self, app: NotesApp, path: str) -> Note:
        """Remove an attached file from this note.

        Args:
            path: the attachment's path, as list_attachments shows it.
        """
        return app.remove_attachment(self.note_id, path)

    @action("List", kind="write")
    def delete(self, app: NotesApp) -> Transition:
        """Delete this note and return to the list."""
        return back_to("List", app.delete_note(self.note_id))

    @action("Edit")
    def edit(self, app: NotesApp) -> Transition:
        """Edit this note's title and text."""
        note = app.require(self.note_id)
        draft = NoteEdit(
            note_id=note.note_id,
            folder=note.folder,
            note_title=note.title,
            content=note.content,
            attachments=list(note.attachments),
        )
        return push(draft, draft.draft())

    @action("Detail", kind="write")
    def duplicate(self, app: NotesApp) -> Transition:
        """Make a copy of this note in the same folder and open the copy."""
        copy_id = app.duplicate_note(self.note_id).id
        return replace(NoteDetail(note_id=copy_id), app.require(copy_id))

    @action("List", kind="write")
    def move(self, app: NotesApp, folder: str) -> Transition:
        """Move this note to another folder and show that folder.

        Args:
            folder: the destination folder, e.g. "Personal".
        """
        note = app.move_note(self.note_id, folder)
        return back_to("List", note, NoteList(folder=note.folder))


class NoteEdit(Screen):
    """A new note or changes to a note, not saved yet."""

    name = "Edit"
    title = "Edit note"
    note_id: str | None = Field(default=None, description="the note being edited; None for a new one")
    folder: str = DEFAULT_FOLDER
    note_title: str = Field(default="", description="the title; the class attribute title names the screen")
    content: str = ""
    attachments: list[str] = Field(default_factory=list)

    def draft(self) -> NoteDraft:
        """Return the draft as the user sees it."""
        return NoteDraft(
            note_id=self.note_id,
            folder=self.folder,
            title=self.note_title,
            content=self.content,
            attachments=list(self.attachments),
        )

    def display(self, app: NotesApp) -> NoteDraft:
        """The draft as it stands."""
        return self.draft()

    @action()
    def set_title(self, app: NotesApp, title: str) -> NoteDraft:
        """Set the note's title.

        Args:
            title: the title, e.g. "Groceries", or "" for none.
        """
        self.note_title = title.strip()
        return self.draft()

    @action()
    def set_content(self, app: NotesApp, content: str) -> NoteDraft:
        """Replace the note's text.

        Args:
            content: the whole text of the note.
        """
        self.content = content
        return self.draft()

    @action(kind="read")
    def browse_files(self, app: NotesApp, directory: str = "/") -> list[DirectoryEntry]:
        """Look through the files on your phone to find one to attach.

        Args:
            directory: the folder to look in, e.g. "/Documents"; "/" is the top.
        """
        return browse(app, directory)

    @action()
    def attach_file(self, app: NotesApp, path: str) -> NoteDraft:
        """Attach a file from your files to the note.

        Args:
            path: the file's path, e.g. "/Documents/floor_plan.pdf".
        """
        stored = app.files().require(path)
        if stored in self.attachments:
            raise ToolError(f"{stored} is already attached.")
        self.attachments = [*self.attachments, stored]
        return self.draft()

    @action("Detail", kind="write")
    def save(self, app: NotesApp) -> Transition:
        """Save the note and show it: creates it if it is new, updates it otherwise."""
        app.check_not_empty(self.note_title, self.content)
        if self.attachments:  # every check before the first write: the files may have gone since
            files = app.files()
            for path in self.attachments:
                files.require(path)
        if self.note_id is None:
            app.folder_named(self.folder)
            note_id = app.create_note(title=self.note_title, content=self.content, folder=self.folder).id
            for path in self.attachments:
                app.add_attachment_to_note(note_id, path)
            return replace(NoteDetail(note_id=note_id), app.require(note_id))
        note = app.require(self.note_id)
        if (self.note_title, self.content) != (note.title, note.content):
            app.update_note(self.note_id, title=self.note_title, content=self.content)
        for path in self.attachments:
            if path not in note.attachments:
                app.add_attachment_to_note(self.note_id, path)
        return back_to("Detail", note, NoteDetail(note_id=self.note_id))

    @action(BACK)
    def discard(self, app: NotesApp) -> Transition:
        """Leave without saving; nothing changes."""
        return back("Draft discarded.")


NotesApp.set_screens(NoteList, FolderList, NoteDetail, NoteEdit)
