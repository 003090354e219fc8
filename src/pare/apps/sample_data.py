"""A small, realistic phone world for demos, the FSM sweep and the kernel benchmark.

Seed data for every app in the format each app's ``State`` accepts, built deterministically: a dozen
contacts, a month of email across folders, 1:1 and group conversations, a week of calendar events, and a
few files referenced as attachments. Scenarios bring their own data; this is for exercising the phone.
"""

from __future__ import annotations

from datetime import UTC, datetime, timedelta
from typing import Any

START = datetime(2025, 3, 3, 9, 0, tzinfo=UTC)
"""The sample world's "now": Monday 3 March 2025, 09:00."""

_PEOPLE = [
    ("alice", "Alice", "Chen", "colleague", "Acme Analytics"),
    ("bob", "Bob", "Okafor", "landlord", None),
    ("carol", "Carol", "Rivera", "sister", None),
    ("dmitri", "Dmitri", "Volkov", "colleague", "Acme Analytics"),
    ("emma", "Emma", "Schulz", "friend", None),
    ("farah", "Farah", "Haddad", "dentist", "Bright Smile Dental"),
    ("george", "George", "Mensah", "manager", "Acme Analytics"),
    ("hana", "Hana", "Sato", "friend", None),
    ("ivan", "Ivan", "Petrov", "plumber", "Petrov Plumbing"),
    ("julia", "Julia", "Costa", "neighbour", None),
    ("kofi", "Kofi", "Asante", "colleague", "Acme Analytics"),
    ("lena", "Lena", "Berg", "friend", None),
]

_SUBJECTS = [
    (
        "Quarterly report draft",
        "Here is the draft of the quarterly report. Comments welcome before Thursday.",
    ),
    ("Rent for March", "Friendly reminder that the rent for March is due on the 5th."),
    ("Mum's birthday", "Shall we book the Italian place for Mum's birthday on Saturday?"),
    ("Standup moved", "Tomorrow's standup moves to 10:30 because of the all-hands."),
    ("Hiking on Sunday?", "The weather looks great for Sunday. Up for the lake trail?"),
    ("Appointment reminder", "This is a reminder of your check-up appointment next week."),
    ("1:1 agenda", "Let's go over the roadmap and your goals in our 1:1."),
    ("Book recommendation", "You have to read the novel I mentioned; I left it with your neighbour."),
    ("Boiler service", "I can service the boiler on Wednesday morning if someone can let me in."),
    ("Parcel for you", "A parcel for you was delivered to my place, drop by anytime."),
    ("Offsite planning", "Can you share your availability for the offsite in April?"),
    ("Concert tickets", "I got two tickets for the concert on the 14th. Want one?"),
]


def _email(people: dict[str, str]) -> dict[str, Any]:
    emails: dict[str, Any] = {}
    keys = [p[0] for p in _PEOPLE]
    for index in range(36):
        who = keys[index % len(keys)]
        subject, content = _SUBJECTS[index % len(_SUBJECTS)]
        folder = "INBOX" if index % 6 else ("ARCHIVE" if index % 12 else "SENT")
        sent = folder == "SENT"
        email_id = f"email-{index + 1:03d}"
        emails[email_id] = {
            "email_id": email_id,
            "sender": "me@pare.example" if sent else people[who],
            "recipients": [people[who]] if sent else ["me@pare.example"],
            "subject": subject if index < 12 else f"{subject} ({index // 12 + 1})",
            "content": content,
            "timestamp": (START - timedelta(hours=5 * index + 1)).isoformat(),
            "is_read": index > 3,
            "attachments": ["/Documents/quarterly_report.txt"] if index == 0 else [],
            "folder": folder,
        }
    return {"user_email": "me@pare.example", "emails": emails}


def _messaging() -> dict[str, Any]:
    users = {"user-me": "Me"} | {f"user-{key}": f"{first} {last}" for key, first, last, _, _ in _PEOPLE}
    conversations: dict[str, Any] = {}
    lines = [
        "Are we still on for tonight?",
        "Running 10 minutes late",
        "Sounds good!",
        "Can you call me later?",
        "Just landed",
        "Did you see the email?",
        "Thanks a lot!",
        "See you there",
    ]
    for index, (key, *_rest) in enumerate(_PEOPLE[:8]):
        conversation_id = f"conv-{key}"
        messages = []
        for number in range(4):
            sender = f"user-{key}" if number % 2 == 0 else "user-me"
            messages.append(
                {
                    "message_id": f"msg-{key}-{number}",
                    "sender_id": sender,
                    "content": lines[(index + number) % len(lines)],
                    "timestamp": (START - timedelta(hours=index * 7 + (4 - number))).isoformat(),
                }
            )
        conversations[conversation_id] = {
            "conversation_id": conversation_id,
            "participant_ids": ["user-me", f"user-{key}"],
            "messages": messages,
            "last_updated": messages[-1]["timestamp"],
        }
    conversations["conv-family"] = {
        "conversation_id": "conv-family",
        "participant_ids": ["user-me", "user-carol", "user-julia", "user-hana"],
        "title": "Family",
        "is_group": True,
        "messages": [
            {
                "message_id": "msg-family-0",
                "sender_id": "user-carol",
                "content": "Who is bringing dessert?",
                "timestamp": (START - timedelta(hours=3)).isoformat(),
            },
            {
                "message_id": "msg-family-1",
                "sender_id": "user-hana",
                "content": "I can bake a cake",
                "timestamp": (START - timedelta(hours=2)).isoformat(),
                "attachment": "/Photos/cake.txt",
            },
        ],
        "last_updated": (START - timedelta(hours=2)).isoformat(),
    }
    return {
        "current_user_id": "user-me",
        "current_user_name": "Me",
        "users": users,
        "conversations": conversations,
    }


def _calendar() -> dict[str, Any]:
    events: dict[str, Any] = {}
    plan = [
        ("Team standup", 0, 9, 30, 15, "work", ["Alice Chen", "Dmitri Volkov", "Kofi Asante"]),
        ("1:1 with George", 0, 14, 0, 30, "work", ["George Mensah"]),
        ("Dentist check-up", 1, 8, 0, 45, "health", ["Farah Haddad"]),
        ("Team standup", 1, 9, 30, 15, "work", ["Alice Chen", "Dmitri Volkov", "Kofi Asante"]),
        ("Lunch with Emma", 1, 12, 30, 60, "personal", ["Emma Schulz"]),
        ("Boiler service", 2, 9, 0, 120, "home", ["Ivan Petrov"]),
        ("Roadmap review", 2, 15, 0, 90, "work", ["George Mensah", "Alice Chen"]),
        ("Team standup", 3, 9, 30, 15, "work", ["Alice Chen", "Dmitri Volkov", "Kofi Asante"]),
        ("Yoga", 3, 18, 30, 60, "health", []),
        ("Quarterly report deadline", 3, 17, 0, 30, "work", []),
        ("Team standup", 4, 9, 30, 15, "work", ["Alice Chen", "Dmitri Volkov", "Kofi Asante"]),
        ("Drinks with Lena", 4, 19, 0, 120, "personal", ["Lena Berg"]),
        ("Mum's birthday dinner", 5, 19, 30, 150, "family", ["Carol Rivera"]),
        ("Hiking at the lake", 6, 10, 0, 240, "personal", ["Emma Schulz", "Hana Sato"]),
    ]
    for index, (title, day, hour, minute, length, tag, attendees) in enumerate(plan):
        start = START.replace(hour=hour, minute=minute) + timedelta(days=day)
        event_id = f"event-{index + 1:02d}"
        events[event_id] = {
            "event_id": event_id,
            "title": title,
            "start_datetime": start.isoformat(),
            "end_datetime": (start + timedelta(minutes=length)).isoformat(),
            "tag": tag,
            "location": "Office" if tag == "work" else None,
            "attendees": attendees,
        }
    return {"events": events}


def sample_world() -> dict[str, dict[str, Any]]:
    """Seed data for files, contacts, email, messaging and calendar."""
    people = {
        key: f"{first}.{last}@{'acme.example' if company == 'Acme Analytics' else 'mail.example'}".lower()
        for key, first, last, _, company in _PEOPLE
    }
    contacts = {
        "contact-me": {
            "contact_id": "contact-me",
            "first_name": "Sam",
            "last_name": "Taylor",
            "is_user": True,
            "email": "me@pare.example",
            "phone": "+1 555 0100",
        },
    }
    for number, (key, first, last, relationship, company) in enumerate(_PEOPLE, start=1):
        contacts[f"contact-{key}"] = {
            "contact_id": f"contact-{key}",
            "first_name": first,
            "last_name": last,
            "email": people[key],
            "phone": f"+1 555 01{number:02d}",
            "relationship": relationship,
            "company": company,
        }
    files = {
        "/Documents/quarterly_report.txt": {"content": "Q1 revenue grew 12%. Costs flat. Hiring: 3 roles."},
        "/Documents/lease.txt": {"content": "Lease for flat 4B, rent due on the 5th of each month."},
        "/Photos/cake.txt": {"content": "(a photo of a chocolate cake)"},
    }
    return {
        "files": {"files": files},
        "contacts": {"contacts": contacts},
        "email": _email(people),
        "messaging": _messaging(),
        "calendar": _calendar(),
    }
