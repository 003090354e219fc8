from __future__ import annotations

from datetime import timedelta
from typing import Any

import pytest

from pare.apps.text import PAGE
from pare.env import Environment
from pare.errors import UserInputError
from tests.conftest import err, make_env, ok, screen_of

ME = "sam@rivera.example"
ALICE = "alice.chen@work.example"
BOB = "bob@okafor.example"
CAROL = "carol@chen.example"
LEASE = "/Documents/lease.pdf"
FOLDER_LIST = "'INBOX', 'SENT', 'DRAFT', 'TRASH' or 'ARCHIVE'"
LEASE_TEXT = "Residential lease, 12 Elm Street, renewal from April 1. Rent: 1,450 per month."


def mail(email_id: str, sender: str, subject: str, when: str, folder: str = "INBOX", **extra: Any) -> dict:
    data = {
        "email_id": email_id,
        "sender": sender,
        "recipients": extra.pop("recipients", [ME]),
        "subject": subject,
        "content": extra.pop("content", f"{subject}. Details inside."),
        "timestamp": when,
        "folder": folder,
    }
    data.update(extra)
    return data


EMAILS = [
    mail(
        "e-lease",
        BOB,
        "Lease renewal",
        "2025-03-02T18:00:00",
        content="Hi Sam, the renewed lease is attached. Please sign it by Friday.",
        attachments=[LEASE],
    ),
    mail(
        "e-lunch", ALICE, "Lunch on Thursday?", "2025-03-02T12:00:00", content="Noodles at the corner place?"
    ),
    mail("e-news", "news@citypaper.example", "Your weekly digest", "2025-03-01T08:00:00", is_read=True),
    mail("e-dentist", "reception@smiledental.example", "Appointment reminder", "2025-02-28T10:00:00"),
    mail("e-invoice", "billing@brightpower.example", "March invoice", "2025-02-27T09:00:00", is_read=True),
    mail(
        "e-party",
        CAROL,
        "Re: Birthday party",
        "2025-02-26T20:00:00",
        content="Count me in! I'll bring the cake.",
        in_reply_to="e-sent-party",
    ),
    mail("e-old-news", "news@citypaper.example", "Last week's digest", "2025-02-22T08:00:00", is_read=True),
    mail(
        "e-sent-party",
        ME,
        "Birthday party",
        "2025-02-26T19:00:00",
        folder="SENT",
        recipients=[CAROL],
        is_read=True,
        content="Party at mine on Saturday the 8th, 7pm. Can you come?",
    ),
    mail(
        "e-sent-report",
        ME,
        "Q1 report",
        "2025-02-25T16:00:00",
        folder="sent",
        recipients=[ALICE],
        cc=["dan@work.example"],
        is_read=True,
    ),
    mail("e-draft", ME, "Vacation plans", "2025-02-24T21:00:00", folder="DRAFT", recipients=[ALICE]),
    mail("e-spam", "winner@lucky-prize.example", "You won a cruise", "2025-02-20T03:00:00", folder="TRASH"),
    mail("e-agenda", ALICE, "Offsite agenda", "2025-01-15T09:30:00", folder="ARCHIVE", is_read=True),
    mail("e-checklist", BOB, "Move-in checklist", "2025-01-10T11:00:00", folder="ARCHIVE", is_read=True),
]

SEED = {
    "files": {"files": {LEASE: {"content": LEASE_TEXT}, "/Documents/notes.txt": {"content": "Notes."}}},
    "email": {"user_email": ME, "emails": {e["email_id"]: e for e in EMAILS}},
}

INBOX_ORDER = ["e-lease", "e-lunch", "e-news", "e-dentist", "e-invoice", "e-party", "e-old-news"]


@pytest.fixture
def env() -> Environment:
    env = make_env(["email"], SEED)
    ok(env.call("user", "open_app", {"app_name": "email"}))
    return env


def emails(env: Environment) -> dict:
    return env.snapshot()["email"]["emails"]


def files(env: Environment) -> dict:
    return env.snapshot()["files"]["files"]


def new_ids(env: Environment, before: dict) -> list[str]:
    return [email_id for email_id in emails(env) if email_id not in before]


def stack(env: Environment) -> list[str]:
    return [screen.label() for screen in env.system.stacks["email"]]


# -- seed data ---------------------------------------------------------------------------------------


def test_seed_is_validated() -> None:
    bad_folder = {"email": {"emails": {"x": mail("x", BOB, "Hi", "2025-03-01T08:00:00", folder="Spam")}}}
    with pytest.raises(UserInputError, match="folder"):
        make_env(["email"], bad_folder)
    wrong_key = {"email": {"emails": {"x": mail("y", BOB, "Hi", "2025-03-01T08:00:00")}}}
    with pytest.raises(UserInputError, match="email_id"):
        make_env(["email"], wrong_key)
    with pytest.raises(UserInputError, match="user_email"):
        make_env(["email"], {"email": {"user_email": "not an address"}})


def test_seed_folder_names_are_case_insensitive(env: Environment) -> None:
    assert emails(env)["e-sent-report"]["folder"] == "SENT"


# -- Mailbox -----------------------------------------------------------------------------------------


def test_opens_on_the_inbox(env: Environment) -> None:
    assert screen_of(env) == "Mailbox"
    assert stack(env) == ["Mailbox(folder='INBOX')"]


def test_list_emails_pages_newest_first(env: Environment) -> None:
    page = ok(env.call("user", "list_emails", {"limit": 3}))
    assert page["folder"] == "INBOX"
    assert [e["email_id"] for e in page["emails"]] == INBOX_ORDER[:3]
    assert page["total"] == 7
    page = ok(env.call("user", "list_emails", {"offset": 3, "limit": 10}))
    assert [e["email_id"] for e in page["emails"]] == INBOX_ORDER[3:]
    assert screen_of(env) == "Mailbox"
    assert env.log[-1].kind == "read"


def test_search_emails_searches_the_folder_shown(env: Environment) -> None:
    found = ok(env.call("user", "search_emails", {"query": "DIGEST"}))
    assert [e["email_id"] for e in found] == ["e-news", "e-old-news"]
    found = ok(env.call("user", "search_emails", {"query": "okafor lease"}))
    assert [e["email_id"] for e in found] == ["e-lease"]
    assert ok(env.call("user", "search_emails", {"query": "Q1 report"})) == []  # in SENT, not INBOX
    assert screen_of(env) == "Mailbox"


def test_open_email_goes_to_detail(env: Environment) -> None:
    shown = ok(env.call("user", "open_email", {"email_id": "e-lunch"}))
    assert shown["subject"] == "Lunch on Thursday?"
    assert screen_of(env) == "Detail"
    assert stack(env)[-1] == "Detail(email_id='e-lunch')"
    assert ok(env.call("user", "refresh"))["email_id"] == "e-lunch"
    assert screen_of(env) == "Detail"


def test_open_unknown_email_is_an_error_and_stays(env: Environment) -> None:
    err(env.call("user", "open_email", {"email_id": "nope"}), "no email with id 'nope'")
    assert screen_of(env) == "Mailbox"


def test_open_email_by_index_uses_the_folder_shown(env: Environment) -> None:
    assert ok(env.call("user", "open_email_by_index", {"index": 1}))["email_id"] == "e-lunch"
    assert stack(env)[-1] == "Detail(email_id='e-lunch')"
    ok(env.call("user", "go_back"))
    ok(env.call("user", "switch_folder", {"folder": "archive"}))
    assert ok(env.call("user", "open_email_by_index", {"index": 0}))["email_id"] == "e-agenda"


def test_open_email_by_index_out_of_range_stays(env: Environment) -> None:
    err(env.call("user", "open_email_by_index", {"index": 7}), "index 7", "7 email")
    assert screen_of(env) == "Mailbox"


def test_switch_folder_replaces_the_mailbox(env: Environment) -> None:
    page = ok(env.call("user", "switch_folder", {"folder": "sent"}))
    assert [e["email_id"] for e in page["emails"]] == ["e-sent-party", "e-sent-report"]
    assert stack(env) == ["Mailbox(folder='SENT')"]
    assert [e["email_id"] for e in ok(env.call("user", "list_emails"))["emails"]] == [
        "e-sent-party",
        "e-sent-report",
    ]
    ok(env.call("user", "switch_folder", {"folder": "Drafts"}))
    assert stack(env) == ["Mailbox(folder='DRAFT')"]


def test_switch_to_unknown_folder_lists_the_folders(env: Environment) -> None:
    err(env.call("user", "switch_folder", {"folder": "Spam"}), "got 'spam'", FOLDER_LIST)
    assert stack(env) == ["Mailbox(folder='INBOX')"]


# -- Detail ------------------------------------------------------------------------------------------


def open_detail(env: Environment, email_id: str) -> None:
    ok(env.call("user", "open_email", {"email_id": email_id}))


def test_reply_sends_and_stays(env: Environment) -> None:
    open_detail(env, "e-lease")
    before = emails(env)
    reply_id = ok(env.call("user", "reply", {"content": "Signed, attached.", "attachments": [LEASE]}))["id"]
    assert screen_of(env) == "Detail"
    assert env.log[-1].kind == "write"
    assert new_ids(env, before) == [reply_id]
    reply = emails(env)[reply_id]
    assert reply["sender"] == ME
    assert reply["recipients"] == [BOB]
    assert reply["subject"] == "Re: Lease renewal"
    assert reply["folder"] == "SENT"
    assert reply["in_reply_to"] == "e-lease"
    assert reply["attachments"] == [LEASE]


def test_reply_to_a_reply_does_not_double_re(env: Environment) -> None:
    open_detail(env, "e-party")
    reply_id = ok(env.call("user", "reply", {"content": "Great, see you!"}))["id"]
    assert emails(env)[reply_id]["subject"] == "Re: Birthday party"
    assert emails(env)[reply_id]["recipients"] == [CAROL]


def test_forward_keeps_attachments_and_stays(env: Environment) -> None:
    open_detail(env, "e-lease")
    forward_id = ok(env.call("user", "forward", {"recipients": [CAROL]}))["id"]
    assert screen_of(env) == "Detail"
    forward = emails(env)[forward_id]
    assert forward["subject"] == "Fwd: Lease renewal"
    assert forward["recipients"] == [CAROL]
    assert forward["attachments"] == [LEASE]
    assert "Please sign it by Friday" in forward["content"]
    assert f"From: {BOB}" in forward["content"]


def test_forward_to_a_malformed_address_changes_nothing(env: Environment) -> None:
    open_detail(env, "e-lease")
    before = env.snapshot()
    err(env.call("user", "forward", {"recipients": ["carol"]}), "'carol'", "not an email address")
    assert env.snapshot() == before
    assert screen_of(env) == "Detail"


def test_move_goes_back_to_the_mailbox(env: Environment) -> None:
    open_detail(env, "e-news")
    ok(env.call("user", "move", {"folder": "Archive"}))
    assert stack(env) == ["Mailbox(folder='INBOX')"]
    assert emails(env)["e-news"]["folder"] == "ARCHIVE"
    assert "e-news" not in [e["email_id"] for e in ok(env.call("user", "list_emails"))["emails"]]


def test_move_to_unknown_folder_stays(env: Environment) -> None:
    open_detail(env, "e-news")
    before = env.snapshot()
    err(env.call("user", "move", {"folder": "Promotions"}), "'promotions'", FOLDER_LIST)
    assert env.snapshot() == before
    assert screen_of(env) == "Detail"


def test_delete_moves_to_trash_then_deletes_for_good(env: Environment) -> None:
    open_detail(env, "e-invoice")
    ok(env.call("user", "delete"))
    assert stack(env) == ["Mailbox(folder='INBOX')"]
    assert emails(env)["e-invoice"]["folder"] == "TRASH"
    ok(env.call("user", "switch_folder", {"folder": "TRASH"}))
    open_detail(env, "e-invoice")
    ok(env.call("user", "delete"))
    assert stack(env) == ["Mailbox(folder='TRASH')"]
    assert "e-invoice" not in emails(env)


def test_download_attachments_copies_into_files_and_stays(env: Environment) -> None:
    open_detail(env, "e-lease")
    saved = ok(env.call("user", "download_attachments"))
    assert saved["paths"] == ["/Downloads/lease.pdf"] and saved["id"] == "/Downloads/lease.pdf"
    assert "lease.pdf" in saved["done"] and "/Downloads" in saved["done"]
    assert screen_of(env) == "Detail"
    assert env.log[-1].kind == "write"
    assert files(env)["/Downloads/lease.pdf"]["content"] == LEASE_TEXT
    assert files(env)[LEASE]["content"] == LEASE_TEXT


def test_download_without_attachments_changes_nothing(env: Environment) -> None:
    open_detail(env, "e-lunch")
    before = env.snapshot()
    err(env.call("user", "download_attachments"), "no attachments")
    assert env.snapshot() == before
    assert screen_of(env) == "Detail"


# -- Compose -----------------------------------------------------------------------------------------


def test_compose_a_new_email_and_send_it(env: Environment) -> None:
    draft = ok(env.call("user", "start_compose"))
    assert screen_of(env) == "Compose"
    assert draft["recipients"] == [] and draft["reply_to"] is None
    before = emails(env)
    ok(env.call("user", "set_recipients", {"recipients": [ALICE]}))
    ok(env.call("user", "add_recipient", {"recipient": f" {BOB} "}))
    ok(env.call("user", "add_recipient", {"recipient": ALICE.upper()}))  # already there
    ok(env.call("user", "set_cc", {"cc": [CAROL]}))
    ok(env.call("user", "set_subject", {"subject": "Lease"}))
    draft = ok(env.call("user", "set_body", {"body": "Here is the lease."}))
    assert draft["recipients"] == [ALICE, BOB]
    draft = ok(env.call("user", "attach_file", {"path": "Documents//lease.pdf"}))
    assert draft["attachments"] == [LEASE]
    assert screen_of(env) == "Compose"
    assert emails(env) == before  # nothing is stored while composing
    assert all(entry.kind == "ui" for entry in env.log if entry.tool.startswith(("set_", "add_", "attach_")))

    sent_id = ok(env.call("user", "send"))["id"]
    assert stack(env) == ["Mailbox(folder='INBOX')"]
    assert env.log[-1].kind == "write"
    sent = emails(env)[sent_id]
    assert (sent["sender"], sent["recipients"], sent["cc"]) == (ME, [ALICE, BOB], [CAROL])
    assert (sent["subject"], sent["content"], sent["attachments"]) == ("Lease", "Here is the lease.", [LEASE])
    assert sent["folder"] == "SENT"
    assert sent["timestamp"].startswith("2025-03-03T09:00:00")
    assert sent["in_reply_to"] is None


def test_compose_rejects_bad_addresses_and_missing_files(env: Environment) -> None:
    ok(env.call("user", "start_compose"))
    ok(env.call("user", "set_recipients", {"recipients": [ALICE]}))
    err(env.call("user", "set_recipients", {"recipients": [BOB, "bob at home"]}), "'bob at home'")
    err(env.call("user", "add_recipient", {"recipient": "bob@"}), "'bob@'")
    err(env.call("user", "set_cc", {"cc": ["@example.com"]}), "cc")
    err(
        env.call("user", "attach_file", {"path": "/Documents/missing.pdf"}),
        "no file at /Documents/missing.pdf",
    )
    draft = ok(env.call("user", "set_body", {"body": "x"}))
    assert draft["recipients"] == [ALICE]
    assert draft["cc"] == [] and draft["attachments"] == []
    assert screen_of(env) == "Compose"


def test_send_without_recipients_stays_and_changes_nothing(env: Environment) -> None:
    ok(env.call("user", "start_compose"))
    ok(env.call("user", "set_subject", {"subject": "Hello"}))
    ok(env.call("user", "set_body", {"body": "Who am I writing to?"}))
    before = env.snapshot()
    err(env.call("user", "send"), "at least one recipient")
    assert env.snapshot() == before
    assert screen_of(env) == "Compose"
    assert env.system.current_screen().label().startswith("Compose(")
    assert env.system.current_screen().model_dump()["subject"] == "Hello"
    ok(env.call("user", "set_recipients", {"recipients": [ALICE]}))
    sent_id = ok(env.call("user", "send"))["id"]
    assert emails(env)[sent_id]["content"] == "Who am I writing to?"


def test_save_draft_stores_in_draft_and_goes_back(env: Environment) -> None:
    ok(env.call("user", "start_compose"))
    ok(env.call("user", "set_subject", {"subject": "Ideas for the offsite"}))
    ok(env.call("user", "set_body", {"body": "1. Hiking"}))
    draft_id = ok(env.call("user", "save_draft"))["id"]
    assert stack(env) == ["Mailbox(folder='INBOX')"]
    assert env.log[-1].kind == "write"
    draft = emails(env)[draft_id]
    assert (draft["folder"], draft["recipients"], draft["subject"]) == ("DRAFT", [], "Ideas for the offsite")
    ok(env.call("user", "switch_folder", {"folder": "DRAFT"}))
    listed = ok(env.call("user", "list_emails"))["emails"]
    assert [e["email_id"] for e in listed] == [draft_id, "e-draft"]


def test_discard_leaves_no_trace(env: Environment) -> None:
    before = env.snapshot()
    ok(env.call("user", "start_compose"))
    ok(env.call("user", "set_recipients", {"recipients": [BOB]}))
    ok(env.call("user", "set_body", {"body": "Never mind"}))
    ok(env.call("user", "attach_file", {"path": LEASE}))
    ok(env.call("user", "discard"))
    assert stack(env) == ["Mailbox(folder='INBOX')"]
    assert env.snapshot() == before
    assert env.log[-1].kind == "ui"
    assert ok(env.call("user", "start_compose"))["body"] == ""  # a new draft starts empty


def test_compose_reply_is_prefilled_and_sent_as_a_reply(env: Environment) -> None:
    open_detail(env, "e-lunch")
    draft = ok(env.call("user", "start_compose_reply"))
    assert screen_of(env) == "Compose"
    assert draft["recipients"] == [ALICE]
    assert draft["subject"] == "Re: Lunch on Thursday?"
    assert draft["reply_to"] == "e-lunch"
    assert stack(env)[-1] == (
        "Compose(recipients=['alice.chen@work.exa…'], cc=[], subject='Re: Lunch on Thursday?', body='', "
        "attachments=[], reply_to='e-lunch')"
    )
    err(env.call("user", "set_recipients", {"recipients": [BOB]}), "reply", "start_compose")
    err(env.call("user", "set_subject", {"subject": "Other"}), "reply")
    ok(env.call("user", "set_body", {"body": "Yes, 12:30 works."}))
    ok(env.call("user", "attach_file", {"path": "/Documents/notes.txt"}))
    before = emails(env)
    reply_id = ok(env.call("user", "send"))["id"]
    assert screen_of(env) == "Detail"
    assert new_ids(env, before) == [reply_id]
    reply = emails(env)[reply_id]
    assert reply["in_reply_to"] == "e-lunch"
    assert reply["recipients"] == [ALICE]
    assert reply["subject"] == "Re: Lunch on Thursday?"
    assert reply["content"] == "Yes, 12:30 works."
    assert reply["attachments"] == ["/Documents/notes.txt"]


def test_compose_reply_to_own_sent_email_goes_to_its_recipients(env: Environment) -> None:
    ok(env.call("user", "switch_folder", {"folder": "SENT"}))
    open_detail(env, "e-sent-report")
    draft = ok(env.call("user", "start_compose_reply"))
    assert draft["recipients"] == [ALICE]
    assert draft["subject"] == "Re: Q1 report"


def test_drafts_cannot_be_replied_to(env: Environment) -> None:
    open_detail(env, "e-draft")
    err(env.call("user", "start_compose_reply"), "draft")
    assert screen_of(env) == "Detail"


# -- agent API ---------------------------------------------------------------------------------------


def test_agent_read_api(env: Environment) -> None:
    def call(tool: str, **args: object) -> Any:
        return ok(env.call("assistant", f"email__{tool}", args, mode="observe"))

    page = call("list_emails")
    assert [e["email_id"] for e in page["emails"]] == INBOX_ORDER[:PAGE]
    assert (page["total"], page["offset"], page["folder"]) == (7, 0, "INBOX")
    assert page["showing"] == "1-5 of 7; offset=5 shows the next"
    page = call("list_emails", offset=5)
    assert [e["email_id"] for e in page["emails"]] == INBOX_ORDER[PAGE:]
    assert page["showing"] == "6-7 of 7 (the last)"
    page = call("list_emails", folder="archive", offset=1, limit=1)
    assert [e["email_id"] for e in page["emails"]] == ["e-checklist"]
    assert page["total"] == 2
    lease = call("get_email_by_id", email_id="e-lease")
    assert lease["attachments"] == [LEASE]
    assert lease["timestamp"] == "2025-03-02T18:00:00Z"
    assert call("get_email_by_index", index=0)["email_id"] == "e-lease"
    assert call("get_email_by_index", index=1, folder="Sent")["email_id"] == "e-sent-report"
    assert [e["email_id"] for e in call("search_emails", query="alice")] == [
        "e-lunch",
        "e-sent-report",
        "e-draft",
        "e-agenda",
    ]
    assert [e["email_id"] for e in call("search_emails", query="dan@work")] == ["e-sent-report"]
    assert [e["email_id"] for e in call("search_emails", query="alice", folder="ARCHIVE")] == ["e-agenda"]
    assert [e["email_id"] for e in call("search_emails", query="CAKE birthday")] == ["e-party"]


def test_agent_write_api(env: Environment) -> None:
    def call(tool: str, **args: object) -> Any:
        return ok(env.call("assistant", f"email__{tool}", args, mode="execute"))

    sent_id = call(
        "send_email",
        recipients=[BOB],
        subject="Signed lease",
        content="Attached.",
        cc=[ALICE],
        attachments=[LEASE],
    )["id"]
    sent = emails(env)[sent_id]
    assert (sent["folder"], sent["sender"], sent["cc"], sent["attachments"]) == ("SENT", ME, [ALICE], [LEASE])
    assert sent["is_read"] is True

    reply_id = call("reply_to_email", email_id="e-party", content="Thanks!")["id"]
    assert emails(env)[reply_id]["subject"] == "Re: Birthday party"
    assert emails(env)[reply_id]["in_reply_to"] == "e-party"

    forward_id = call("forward_email", email_id="e-lease", recipients=[CAROL, CAROL])["id"]
    assert emails(env)[forward_id]["recipients"] == [CAROL]
    assert emails(env)[forward_id]["attachments"] == [LEASE]
    again = call("forward_email", email_id=forward_id, recipients=[ALICE])["id"]
    assert emails(env)[again]["subject"] == "Fwd: Lease renewal"

    assert "ARCHIVE" in call("move_email", email_id="e-dentist", folder="archive")
    assert emails(env)["e-dentist"]["folder"] == "ARCHIVE"
    call("move_email", email_id="e-spam", folder="INBOX")
    assert emails(env)["e-spam"]["folder"] == "INBOX"
    call("move_email", email_id="e-sent-party", folder="TRASH")
    call("move_email", email_id="e-sent-party", folder="SENT")  # restoring own sent email
    assert emails(env)["e-sent-party"]["folder"] == "SENT"

    assert "TRASH" in call("delete_email", email_id="e-news")
    assert emails(env)["e-news"]["folder"] == "TRASH"
    assert "permanently" in call("delete_email", email_id="e-news")
    assert "e-news" not in emails(env)

    assert call("download_attachments", email_id="e-lease", path="/Documents/Lease copy")["paths"] == [
        "/Documents/Lease copy/lease.pdf"
    ]
    assert call("download_attachments", email_id="e-lease", path="/Documents")["paths"] == [
        LEASE
    ]  # already there

    draft_id = call("save_draft", recipients=[BOB], subject="Rent", content="Half written", cc=None)["id"]
    assert emails(env)[draft_id]["folder"] == "DRAFT"


def test_download_attachments_never_overwrites_a_different_file(env: Environment) -> None:
    ok(
        env.call(
            "assistant",
            "files__write_file",
            {"path": "/Downloads/lease.pdf", "content": "old"},
            mode="execute",
        )
    )
    saved = ok(env.call("assistant", "email__download_attachments", {"email_id": "e-lease"}, mode="execute"))
    assert saved["paths"] == ["/Downloads/lease (2).pdf"]
    assert files(env)["/Downloads/lease.pdf"]["content"] == "old"
    assert files(env)["/Downloads/lease (2).pdf"]["content"] == LEASE_TEXT


def test_write_tools_are_not_offered_in_observe_mode(env: Environment) -> None:
    before = env.snapshot()
    err(
        env.call("assistant", "email__send_email", {"recipients": [BOB], "subject": "s", "content": "c"}),
        "execute mode",
    )
    assert env.snapshot() == before
    names = {tool.name for tool in env.assistant_tools("observe")}
    assert "email__list_emails" in names and "email__send_email" not in names
    assert "email__receive_email" not in {tool.name for tool in env.assistant_tools("execute")}


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("list_emails", {"folder": "Promotions"}, FOLDER_LIST),
        ("list_emails", {"limit": 0}, "limit"),
        ("list_emails", {"offset": -1}, "offset"),
        ("get_email_by_id", {"email_id": "ghost"}, "no email with id 'ghost'"),
        ("get_email_by_index", {"index": -1}, "index -1"),
        ("get_email_by_index", {"index": 2, "folder": "ARCHIVE"}, "index 2 in ARCHIVE"),
        ("search_emails", {"query": "   "}, "empty"),
        ("search_emails", {"query": "x", "folder": "junk"}, FOLDER_LIST),
        ("send_email", {"recipients": [], "subject": "s", "content": "c"}, "at least one recipient"),
        ("send_email", {"recipients": "bob@okafor.example", "subject": "s", "content": "c"}, "recipients"),
        ("send_email", {"recipients": [BOB, "alice"], "subject": "s", "content": "c"}, "'alice'"),
        ("send_email", {"recipients": [BOB], "subject": "s", "content": "c", "cc": ["x"]}, "in cc"),
        (
            "send_email",
            {"recipients": [BOB], "subject": "s", "content": "c", "attachments": ["/nope.pdf"]},
            "/nope",
        ),
        (
            "send_email",
            {"recipients": [BOB], "subject": "s", "content": "c", "attachments": ["/../x"]},
            "leaves",
        ),
        ("send_email", {"recipients": [BOB], "subject": "s"}, "missing required argument 'content'"),
        ("reply_to_email", {"email_id": "ghost", "content": "hi"}, "ghost"),
        ("reply_to_email", {"email_id": "e-draft", "content": "hi"}, "draft"),
        ("reply_to_email", {"email_id": "e-lunch", "content": "hi", "attachments": ["/x"]}, "no file at /x"),
        ("forward_email", {"email_id": "e-lunch", "recipients": []}, "at least one recipient"),
        ("forward_email", {"email_id": "e-lunch", "recipients": ["bob"]}, "'bob'"),
        ("forward_email", {"email_id": "ghost", "recipients": [BOB]}, "ghost"),
        ("forward_email", {"email_id": "e-draft", "recipients": [BOB]}, "draft"),
        ("move_email", {"email_id": "e-lunch", "folder": "Spam"}, "got 'spam'"),
        ("move_email", {"email_id": "e-lunch", "folder": "inbox"}, "already in INBOX"),
        ("move_email", {"email_id": "e-lunch", "folder": "DRAFT"}, "save_draft"),
        ("move_email", {"email_id": "e-lunch", "folder": "SENT"}, "only emails the user has sent"),
        ("move_email", {"email_id": "e-draft", "folder": "SENT"}, "send_email"),
        ("move_email", {"email_id": "ghost", "folder": "TRASH"}, "ghost"),
        ("delete_email", {"email_id": "ghost"}, "ghost"),
        ("download_attachments", {"email_id": "e-lunch"}, "no attachments"),
        ("download_attachments", {"email_id": "e-lease", "path": "/../../etc"}, "leaves"),
        ("download_attachments", {"email_id": "ghost"}, "ghost"),
        ("save_draft", {"recipients": ["nobody"], "subject": "s", "content": "c"}, "'nobody'"),
        ("save_draft", {"recipients": [], "subject": "s", "content": "c", "attachments": ["/x"]}, "/x"),
    ],
)
def test_agent_api_errors_change_nothing(env: Environment, tool: str, args: dict, message: str) -> None:
    before = env.snapshot()
    err(env.call("assistant", f"email__{tool}", args, mode="execute"), message)
    assert env.snapshot() == before


def test_missing_attachment_source_changes_nothing(env: Environment) -> None:
    ok(env.call("env", "email__receive_email", {
        "sender": BOB, "subject": "Two files", "content": "See both.",
        "attachments": ["/Documents/notes.txt", LEASE], "email_id": "e-two",
    }))  # fmt: skip
    del env.app("files").state.files[LEASE]  # the file went away since the email arrived
    before = env.snapshot()
    err(env.call("assistant", "email__download_attachments", {"email_id": "e-two"}, mode="execute"), LEASE)
    assert env.snapshot() == before


# -- the world ---------------------------------------------------------------------------------------


def test_receive_email_stores_it_and_notifies_both_actors(env: Environment) -> None:
    env.user_view()
    env.assistant_observation()
    body = (
        "Hi Sam, following our call I have rechecked the numbers for the apartment search and we should "
        "keep the monthly budget under 2,100 including utilities, parking and the building fees."
    )
    new_id = ok(
        env.call(
            "env",
            "email__receive_email",
            {
                "sender": "dana@realty.example",
                "subject": "Budget update",
                "content": body,
                "attachments": [LEASE],
            },
        )
    )
    stored = emails(env)[new_id]
    assert stored["recipients"] == [ME]
    assert stored["folder"] == "INBOX"
    assert stored["is_read"] is False
    assert stored["attachments"] == [LEASE]
    assert stored["timestamp"].startswith("2025-03-03T09:00:00")
    assert ok(env.call("user", "list_emails", {"limit": 1}))["emails"][0]["email_id"] == new_id

    user_notes = env.user_view().notifications
    assert len(user_notes) == 1
    assert "dana@realty.example" in user_notes[0] and "Budget update" in user_notes[0]
    assert "Hi Sam" in user_notes[0]
    assert "building fees" not in user_notes[0]

    assistant_notes = env.assistant_observation().notifications
    assert len(assistant_notes) == 1
    assert "building fees." in assistant_notes[0]
    assert new_id in assistant_notes[0] and LEASE in assistant_notes[0]


def test_receive_email_with_a_chosen_id_folder_and_thread(env: Environment) -> None:
    new_id = ok(
        env.call(
            "env",
            "email__receive_email",
            {
                "sender": CAROL,
                "subject": "Re: Birthday party",
                "content": "Also, can I bring a friend?",
                "recipients": [ME, ALICE],
                "cc": [BOB],
                "email_id": "e-carol-2",
                "folder": "archive",
                "in_reply_to": "e-sent-party",
            },
        )
    )
    assert new_id == "e-carol-2"
    stored = emails(env)["e-carol-2"]
    assert (stored["recipients"], stored["cc"], stored["folder"]) == ([ME, ALICE], [BOB], "ARCHIVE")
    assert stored["in_reply_to"] == "e-sent-party"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"email_id": "e-lease"}, "already exists"),
        ({"email_id": " "}, "cannot be empty"),
        ({"sender": "Dana from Realty"}, "not an email address"),
        ({"folder": "Promotions"}, FOLDER_LIST),
        ({"attachments": ["/Documents/missing.pdf"]}, "no file"),
        ({"recipients": ["me"]}, "'me'"),
    ],
)
def test_receive_email_errors_change_nothing(env: Environment, args: dict, message: str) -> None:
    env.user_view()
    before = env.snapshot()
    call = {"sender": "dana@realty.example", "subject": "Hello", "content": "Hi", **args}
    err(env.call("env", "email__receive_email", call), message)
    assert env.snapshot() == before
    assert env.user_view().notifications == []


def test_receive_email_is_not_for_the_assistant_or_user(env: Environment) -> None:
    args = {"sender": BOB, "subject": "s", "content": "c"}
    err(env.call("assistant", "email__receive_email", args, mode="execute"), "not available")
    err(env.call("user", "receive_email", args), "unknown action")


def test_noise_arrives_as_emails() -> None:
    env = make_env(["email"], SEED, noise_rate_per_minute=0.5, seed=3)
    env.advance(timedelta(hours=1))
    arrivals = [entry for entry in env.log if entry.actor == "env" and entry.app == "email"]
    assert arrivals, "expected some noise emails in an hour"
    assert all(entry.ok for entry in arrivals), [entry.error for entry in arrivals if not entry.ok]
    assert len(emails(env)) == len(EMAILS) + len(arrivals)


def test_compose_can_browse_files_to_attach(env: Environment) -> None:
    ok(env.call("user", "start_compose"))
    top = ok(env.call("user", "browse_files"))
    assert [(e["name"], e["type"]) for e in top] == [("Documents", "directory")]
    found = ok(env.call("user", "browse_files", {"directory": "/Documents"}))
    assert [e["path"] for e in found] == [LEASE, "/Documents/notes.txt"]
    assert screen_of(env) == "Compose"
    assert env.log[-1].kind == "read"


def test_a_sending_write_says_to_whom_it_went_and_carries_the_id(env: Environment) -> None:
    def call(tool: str, **args: object) -> Any:
        return ok(env.call("assistant", f"email__{tool}", args, mode="execute"))

    reply = call("reply_to_email", email_id="e-party", content="Thanks!")
    assert reply["done"] == f"Replied to e-party: sent {reply['id']} to {CAROL}: 'Re: Birthday party'."
    sent = call("send_email", recipients=[BOB, ALICE], subject="Rent", content="Paid.", cc=[CAROL])
    assert sent["done"] == f"Sent {sent['id']} to {BOB} and {ALICE} (cc {CAROL}): 'Rent'."
    forward = call("forward_email", email_id="e-lease", recipients=[CAROL])
    assert forward["done"] == (
        f"Forwarded e-lease: sent {forward['id']} to {CAROL}: 'Fwd: Lease renewal', with 1 attachment(s)."
    )
    draft = call("save_draft", recipients=[], subject="Ideas", content="")
    assert draft["done"] == f"Saved draft {draft['id']} (no recipient yet) in DRAFT: 'Ideas'."
    # the model is shown the sentence with the id, not a bare id
    assert env.log[-1].result == draft
