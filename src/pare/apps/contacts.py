"""Contacts: the people the user knows, and the user themself."""

from __future__ import annotations

from typing import Any

from pydantic import BaseModel, ConfigDict, Field

from pare.apps.base import App
from pare.apps.done import Done
from pare.apps.paging import Paged, showing_screen
from pare.apps.screens import BACK, Screen, Transition, action, back, back_to, push
from pare.apps.text import PAGE
from pare.apps.tools import tool
from pare.errors import ToolError


class Contact(BaseModel):
    """A person in the address book."""

    model_config = ConfigDict(extra="forbid")

    contact_id: str
    first_name: str
    last_name: str = ""
    phone: str | None = None
    email: str | None = None
    address: str | None = None
    city: str | None = None
    job: str | None = None
    company: str | None = None
    birthday: str | None = Field(default=None, description="YYYY-MM-DD")
    relationship: str | None = Field(default=None, description="e.g. friend, colleague, family, landlord")
    notes: str | None = None
    is_user: bool = False

    @property
    def full_name(self) -> str:
        """First and last name."""
        return f"{self.first_name} {self.last_name}".strip()


class ContactUpdate(BaseModel):
    """Fields to change on a contact; fields left out are kept."""

    model_config = ConfigDict(extra="forbid")

    first_name: str | None = None
    last_name: str | None = None
    phone: str | None = None
    email: str | None = None
    address: str | None = None
    city: str | None = None
    job: str | None = None
    company: str | None = None
    birthday: str | None = None
    relationship: str | None = None
    notes: str | None = None


class ContactsState(BaseModel):
    """Every contact by id."""

    model_config = ConfigDict(extra="forbid")

    contacts: dict[str, Contact] = Field(default_factory=dict)


class ContactPage(Paged):
    """One page of contacts."""

    rows_field = "contacts"

    contacts: list[Contact]
    total: int
    offset: int


class ContactsApp(App):
    """The address book."""

    name = "contacts"
    title = "Contacts"
    description = "The user's address book: names, phone numbers, emails, addresses."
    State = ContactsState
    harm = {
        "add_new_contact": "reversible",
        "edit_contact": "reversible",
        "delete_contact": "irreversible",
    }
    state: ContactsState

    # -- helpers used by other apps and screens -----------------------------------------------------
    def require(self, contact_id: str) -> Contact:
        """The contact with ``contact_id``; :class:`ToolError` naming it otherwise."""
        contact = self.state.contacts.get(contact_id)
        if contact is None:
            raise ToolError(f"No contact with id '{contact_id}'. Use search_contacts to find contact ids.")
        return contact

    def current_user(self) -> Contact | None:
        """The phone's owner, if the address book has them."""
        return next((c for c in self.state.contacts.values() if c.is_user), None)

    # -- agent API -----------------------------------------------------------------------------------
    @tool("read")
    def get_contacts(self, offset: int = 0, limit: int = PAGE) -> ContactPage:
        """List contacts sorted by name, a page at a time.

        Args:
            offset: how many contacts to skip.
            limit: how many contacts to return (1-100).

        Returns:
            the page of contacts and the total number of contacts.
        """
        if offset < 0 or not 1 <= limit <= 100:
            raise ToolError("offset must be >= 0 and limit between 1 and 100.")
        ordered = sorted(self.state.contacts.values(), key=lambda c: (c.full_name.lower(), c.contact_id))
        return ContactPage(contacts=ordered[offset : offset + limit], total=len(ordered), offset=offset)

    @tool("read")
    def get_contact(self, contact_id: str) -> Contact:
        """Get one contact's details.

        Args:
            contact_id: the contact's id.

        Returns:
            the contact.
        """
        return self.require(contact_id)

    @tool("read")
    def search_contacts(self, query: str) -> list[Contact]:
        """Search contacts by name, phone, email, company, city or relationship (case-insensitive; every
        word of the query must match). It matches parts of words too: "Priya" finds "Priyanka".

        Args:
            query: words to look for, e.g. "alice" or "dentist".

        Returns:
            the matching contacts, sorted by name.
        """
        words = query.lower().split()
        if not words:
            raise ToolError("The search query is empty.")
        found = []
        for contact in self.state.contacts.values():
            haystack = " ".join(
                str(v) for v in contact.model_dump(exclude={"contact_id", "is_user"}).values() if v
            ).lower()
            if all(word in haystack for word in words):
                found.append(contact)
        return sorted(found, key=lambda c: (c.full_name.lower(), c.contact_id))

    @tool("read")
    def get_current_user_details(self) -> Contact:
        """Get the phone owner's own contact card.

        Returns:
            the user's contact.
        """
        user = self.current_user()
        if user is None:
            raise ToolError("The address book has no card for the phone's owner.")
        return user

    @tool("write")
    def add_new_contact(
        self,
        first_name: str,
        last_name: str = "",
        phone: str | None = None,
        email: str | None = None,
        address: str | None = None,
        city: str | None = None,
        job: str | None = None,
        company: str | None = None,
        relationship: str | None = None,
        notes: str | None = None,
    ) -> Done:
        """Add a contact to the address book.

        Args:
            first_name: first name (required).
            last_name: last name.
            phone: phone number.
            email: email address.
            address: postal address.
            city: city.
            job: job title.
            company: employer.
            relationship: how the user knows them, e.g. "colleague".
            notes: free-form notes.

        Returns:
            who was added, and the new contact's id.
        """
        if not first_name.strip():
            raise ToolError("A contact needs a first name.")
        contact_id = self.new_id("contact", self.state.contacts)
        self.state.contacts[contact_id] = Contact(
            contact_id=contact_id,
            first_name=first_name.strip(),
            last_name=last_name.strip(),
            phone=phone,
            email=email,
            address=address,
            city=city,
            job=job,
            company=company,
            relationship=relationship,
            notes=notes,
        )
        contact = self.state.contacts[contact_id]
        return Done(done=f"Added {contact.full_name} to the contacts as {contact_id}.", id=contact_id)

    @tool("write")
    def edit_contact(self, contact_id: str, updates: ContactUpdate) -> Contact:
        """Change some fields of a contact; fields not given are kept.

        Args:
            contact_id: the contact to change.
            updates: the fields to change, e.g. {"phone": "+1 555 0100"}.

        Returns:
            the contact as it is now.
        """
        contact = self.require(contact_id)
        changes = updates.model_dump(exclude_unset=True)
        if not changes:
            raise ToolError("No field to change was given.")
        if changes.get("first_name") is not None and not changes["first_name"].strip():
            raise ToolError("A contact's first name cannot be empty.")
        updated = contact.model_copy(update=changes)
        self.state.contacts[contact_id] = updated
        return updated

    @tool("write")
    def delete_contact(self, contact_id: str) -> str:
        """Delete a contact.

        Args:
            contact_id: the contact to delete.

        Returns:
            confirmation.
        """
        contact = self.require(contact_id)
        if contact.is_user:
            raise ToolError("The phone owner's own card cannot be deleted.")
        del self.state.contacts[contact_id]
        return f"Deleted contact {contact_id} ({contact.full_name})."


# -- screens -----------------------------------------------------------------------------------------


def _row(contact: Contact) -> dict[str, Any]:
    """A contact as the address book lists it: name, and the phone, email and relationship it has."""
    row: dict[str, Any] = {"contact_id": contact.contact_id, "name": contact.full_name}
    for field in ("phone", "email", "relationship"):
        value = getattr(contact, field)
        if value:
            row[field] = value
    if contact.is_user:
        row["me"] = True
    return row


def _contact_or_gone(app: ContactsApp, contact_id: str) -> Contact | str:
    contact = app.state.contacts.get(contact_id)
    return contact if contact is not None else f"Contact {contact_id} no longer exists."


class ContactList(Screen):
    """The address book."""

    name = "List"
    title = "All contacts"

    def display(self, app: ContactsApp) -> dict[str, Any]:
        """The first contacts by name, as list_contacts orders them, with the total; each row has the id
        open_contact takes and what an address book row shows.
        """
        page = app.get_contacts(limit=PAGE)
        return {
            "total": page.total,
            "contacts": [_row(contact) for contact in page.contacts],
            **showing_screen(page.contacts, page.total, "list_contacts(offset={offset})"),
        }

    @action(kind="read")
    def list_contacts(self, app: ContactsApp, offset: int = 0, limit: int = PAGE) -> ContactPage:
        """Show a page of contacts.

        Args:
            offset: how many contacts to skip.
            limit: how many to show.
        """
        return app.get_contacts(offset=offset, limit=limit)

    @action(kind="read")
    def search_contacts(self, app: ContactsApp, query: str) -> list[Contact]:
        """Search contacts by name, phone, email or company. It matches parts of words too: "Priya" finds
        "Priyanka".

        Args:
            query: what to look for.
        """
        return app.search_contacts(query)

    @action(kind="read")
    def view_current_user(self, app: ContactsApp) -> Contact:
        """Show your own contact card."""
        return app.get_current_user_details()

    @action("Detail")
    def open_contact(self, app: ContactsApp, contact_id: str) -> Transition:
        """Open a contact's page.

        Args:
            contact_id: the contact's id.
        """
        return push(ContactDetail(contact_id=contact_id), app.require(contact_id))

    @action("Detail", kind="write")
    def create_contact(
        self,
        app: ContactsApp,
        first_name: str,
        last_name: str = "",
        phone: str | None = None,
        email: str | None = None,
        relationship: str | None = None,
        notes: str | None = None,
    ) -> Transition:
        """Create a new contact and open it.

        Args:
            first_name: first name.
            last_name: last name.
            phone: phone number.
            email: email address.
            relationship: how you know them.
            notes: notes.
        """
        contact_id = app.add_new_contact(
            first_name=first_name,
            last_name=last_name,
            phone=phone,
            email=email,
            relationship=relationship,
            notes=notes,
        ).id
        return push(ContactDetail(contact_id=contact_id), app.require(contact_id))


class ContactDetail(Screen):
    """One contact's page."""

    name = "Detail"
    title = "Contact details"
    contact_id: str

    def display(self, app: ContactsApp) -> Contact | str:
        """The contact in full, as open_contact shows it (or a line saying it is gone)."""
        return _contact_or_gone(app, self.contact_id)

    @action(kind="read")
    def view_contact(self, app: ContactsApp) -> Contact:
        """Show this contact's details."""
        return app.require(self.contact_id)

    @action("Edit")
    def start_edit_contact(self, app: ContactsApp) -> Transition:
        """Edit this contact."""
        return push(ContactEdit(contact_id=self.contact_id), app.require(self.contact_id))

    @action("List", kind="write")
    def delete_contact(self, app: ContactsApp) -> Transition:
        """Delete this contact and return to the list."""
        return back_to("List", app.delete_contact(self.contact_id))


class ContactEdit(Screen):
    """Editing a contact."""

    name = "Edit"
    title = "Edit contact"
    contact_id: str

    def display(self, app: ContactsApp) -> Contact | str:
        """The contact being edited as it stands: the edit is one update_contact call, with no draft."""
        return _contact_or_gone(app, self.contact_id)

    @action(kind="read")
    def view_contact(self, app: ContactsApp) -> Contact:
        """Show the contact being edited."""
        return app.require(self.contact_id)

    @action(BACK, kind="write")
    def update_contact(self, app: ContactsApp, updates: ContactUpdate) -> Transition:
        """Save changes to the contact and return to its page.

        Args:
            updates: the fields to change, e.g. {"email": "new@example.com"}.
        """
        return back(app.edit_contact(self.contact_id, updates))


ContactsApp.set_screens(ContactList, ContactDetail, ContactEdit)
