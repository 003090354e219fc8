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


def _reminder() -> dict[str, Any]:
    plan = [
        ("Pay rent", 2, 9, 0, "Transfer March rent to Bob", "monthly"),
        ("Call Mum", 0, 18, 0, "Ask about Saturday dinner", "weekly"),
        ("Take vitamins", 0, 8, 0, "", "daily"),
        ("Renew passport", 10, 12, 0, "Photos are in /Documents", "none"),
        ("Water the plants", 1, 19, 0, "", "none"),
        ("Submit expense report", 3, 16, 0, "Receipts in email", "none"),
    ]
    reminders = {}
    for index, (title, day, hour, minute, description, repetition) in enumerate(plan, start=1):
        due = START.replace(hour=hour, minute=minute) + timedelta(days=day)
        reminders[f"reminder-{index}"] = {
            "reminder_id": f"reminder-{index}",
            "title": title,
            "description": description,
            "due_datetime": due.isoformat(),
            "repetition": repetition,
            "announced": due < START,
        }
    return {"reminders": reminders}


def _notes() -> dict[str, Any]:
    texts = [
        ("Groceries", "milk, eggs, spinach, coffee beans", "Personal"),
        ("Offsite ideas", "Lake venue? Ask George about budget.", "Work"),
        ("Gift ideas for Mum", "scarf, cookbook, concert tickets", "Personal"),
        ("1:1 talking points", "promotion timeline; conference budget", "Work"),
        ("Wifi password", "flat 4B: maple-river-42", "Notes"),
        ("Books to read", "The Tin Lantern; Driftwood Summer", "Personal"),
    ]
    notes = {}
    for index, (title, content, folder) in enumerate(texts, start=1):
        written = (START - timedelta(days=index, hours=index)).isoformat()
        notes[f"note-{index}"] = {
            "note_id": f"note-{index}",
            "title": title,
            "content": content,
            "folder": folder,
            "created_at": written,
            "updated_at": written,
            "attachments": ["/Documents/lease.txt"] if index == 5 else [],
        }
    return {"folders": ["Notes", "Personal", "Work"], "notes": notes}


def _cab() -> dict[str, Any]:
    home, office, airport = "14 Elm St", "Acme Analytics, 200 Market St", "City Airport, Terminal 2"
    rides = {}
    for index, (start, end, service, days_ago, status) in enumerate(
        [
            (home, office, "Default", 6, "completed"),
            (office, home, "Pool", 6, "completed"),
            (home, airport, "Van", 12, "completed"),
            (home, office, "Default", 3, "cancelled_by_driver"),
        ],
        start=1,
    ):
        pickup = START - timedelta(days=days_ago, hours=index)
        rides[f"ride-{index}"] = {
            "ride_id": f"ride-{index}",
            "start_location": start,
            "end_location": end,
            "service_type": service,
            "pickup_time": pickup.isoformat(),
            "booked_at": (pickup - timedelta(minutes=10)).isoformat(),
            "distance_km": 6.8 + index,
            "duration_minutes": 14 + 2 * index,
            "price": 14.5 + 3 * index,
            "status": status,
            "driver_name": "Marco",
            "vehicle": "grey Toyota Prius",
        }
    pickup = START + timedelta(minutes=20)
    rides["ride-5"] = {
        "ride_id": "ride-5",
        "start_location": home,
        "end_location": office,
        "service_type": "Default",
        "pickup_time": pickup.isoformat(),
        "booked_at": (START - timedelta(minutes=5)).isoformat(),
        "distance_km": 7.2,
        "duration_minutes": 15,
        "price": 21.4,
        "status": "driver_assigned",
        "driver_name": "Aisha",
        "vehicle": "white Kia Niro",
    }
    return {"rides": rides, "current_ride_id": "ride-5", "known_distances": {f"{home}|{office}": 7.2}}


def _apartment() -> dict[str, Any]:
    rows = [
        (
            "Sunny 2BR near the park",
            "Riverside",
            "12 Park Ave",
            3200,
            2,
            1.0,
            "Apartment",
            ["Laundry", "Balcony"],
        ),
        ("Riverside studio", "Riverside", "3 Quay St", 1900, 0, 1.0, "Studio", ["Gym"]),
        ("Family house with garden", "Northfield", "88 Oak Rd", 4800, 3, 2.5, "House", ["Garden", "Parking"]),
        ("Loft by the station", "Old Town", "5 Rail Yard", 2700, 1, 1.0, "Condo", ["Roof deck", "Laundry"]),
        ("Quiet 1BR", "Northfield", "41 Elm Ct", 2300, 1, 1.0, "Apartment", ["Parking"]),
        (
            "Townhouse near school",
            "Old Town",
            "9 Mill Ln",
            3900,
            3,
            2.0,
            "Townhouse",
            ["Garden", "Dishwasher"],
        ),
        (
            "Penthouse with views",
            "Riverside",
            "1 Tower Pl",
            6500,
            2,
            2.0,
            "Condo",
            ["Doorman", "Gym", "Pool"],
        ),
        ("Basement studio", "Old Town", "17 Cellar St", 1400, 0, 1.0, "Studio", []),
    ]
    apartments = {}
    for index, (name, location, address, price, bedrooms, bathrooms, kind, amenities) in enumerate(
        rows, start=1
    ):
        apartments[f"apt-{index}"] = {
            "apartment_id": f"apt-{index}",
            "name": name,
            "location": location,
            "address": address,
            "price": price,
            "bedrooms": bedrooms,
            "bathrooms": bathrooms,
            "property_type": kind,
            "amenities": amenities,
            "pet_policy": "Pets allowed" if index % 2 else "No pets",
            "lease_term": "1 year",
            "furnished_status": "Unfurnished",
            "square_footage": 500 + 150 * bedrooms,
        }
    return {"apartments": apartments, "saved": ["apt-1", "apt-4"]}


def _shopping() -> dict[str, Any]:
    catalogue = [
        ("prod-kettle", "Electric Kettle 1.7L", "Homely", "Kitchen", [("kettle-steel", "Steel", 39.99, 6)]),
        (
            "prod-mug",
            "Ceramic Mug",
            "Homely",
            "Kitchen",
            [("mug-blue", "Blue", 8.5, 20), ("mug-red", "Red", 8.5, 0)],
        ),
        (
            "prod-shoe",
            "Trail Runner 3",
            "Stride",
            "Shoes",
            [("shoe-42", "Blue / 42", 89.99, 4), ("shoe-43", "Blue / 43", 89.99, 1)],
        ),
        (
            "prod-hoodie",
            "Everyday Hoodie",
            "Northline",
            "Clothing",
            [("hoodie-m", "Grey / M", 45.0, 8), ("hoodie-l", "Grey / L", 45.0, 2)],
        ),
        (
            "prod-charger",
            "USB-C Charger 65W",
            "Voltly",
            "Electronics",
            [("charger-white", "White", 34.99, 12)],
        ),
        ("prod-mat", "Yoga Mat", "Northline", "Sports", [("mat-purple", "Purple", 29.99, 5)]),
    ]
    products = {
        product_id: {
            "product_id": product_id,
            "name": name,
            "brand": brand,
            "category": category,
            "description": f"{name} by {brand}.",
            "variants": {
                item: {"item_id": item, "name": label, "price": price, "stock": stock, "options": {}}
                for item, label, price, stock in variants
            },
        }
        for product_id, name, brand, category, variants in catalogue
    }
    codes = {
        "SPRING15": {
            "code": "SPRING15",
            "description": "Spring sale",
            "percent_off": 15,
            "min_subtotal": 50,
            "expires_at": (START + timedelta(days=20)).isoformat(),
        },
        "WELCOME10": {"code": "WELCOME10", "description": "Welcome gift", "amount_off": 10},
    }
    placed = (START - timedelta(days=2)).isoformat()
    orders = {
        "order-1": {
            "order_id": "order-1",
            "status": "shipped",
            "placed_at": placed,
            "subtotal": 17.0,
            "discount": 0,
            "total": 17.0,
            "items": [
                {
                    "item_id": "mug-blue",
                    "product_name": "Ceramic Mug",
                    "variant_name": "Blue",
                    "quantity": 2,
                    "unit_price": 8.5,
                }
            ],
        },
        "order-2": {
            "order_id": "order-2",
            "status": "placed",
            "placed_at": placed,
            "subtotal": 34.99,
            "discount": 0,
            "total": 34.99,
            "items": [
                {
                    "item_id": "charger-white",
                    "product_name": "USB-C Charger 65W",
                    "variant_name": "White",
                    "quantity": 1,
                    "unit_price": 34.99,
                }
            ],
        },
    }
    return {"products": products, "cart": {"hoodie-m": 1}, "discount_codes": codes, "orders": orders}


def _banking() -> dict[str, Any]:
    accounts = {
        "acc-everyday": {
            "account_id": "acc-everyday",
            "name": "Everyday",
            "number": "****4821",
            "balance": "1842.37",
            "overdraft_limit": "500.00",
        },
        "acc-savings": {
            "account_id": "acc-savings",
            "name": "Savings",
            "kind": "savings",
            "number": "****9930",
            "balance": "6250.00",
        },
    }
    rows = [
        # days ago, account, amount, description, counterparty, kind, category
        (1, "acc-everyday", "-4.20", "Card payment: Corner Cafe", "Corner Cafe", "card", "eating out"),
        (1, "acc-everyday", "-62.15", "Card payment: FreshMart", "FreshMart", "card", "groceries"),
        (2, "acc-everyday", "-15.99", "Card payment: StreamFlix", "StreamFlix", "card", "subscriptions"),
        (
            3,
            "acc-everyday",
            "-48.00",
            "Direct debit: City Power & Gas",
            "City Power & Gas",
            "direct_debit",
            "bills",
        ),
        (4, "acc-everyday", "25.00", "Payment from Emma Schulz: pizza", "Emma Schulz", "deposit", ""),
        (5, "acc-everyday", "-9.50", "Card payment: Metro Transit", "Metro Transit", "card", "transport"),
        (6, "acc-everyday", "-120.00", "Transfer to Savings", "Savings", "transfer", ""),
        (6, "acc-savings", "120.00", "Transfer from Everyday", "Everyday", "transfer", ""),
        (8, "acc-everyday", "-33.40", "Card payment: FreshMart", "FreshMart", "card", "groceries"),
        (
            10,
            "acc-everyday",
            "-1450.00",
            "Standing order to Bob Okafor: Rent Feb",
            "Bob Okafor",
            "standing_order",
            "rent",
        ),
        (11, "acc-everyday", "3120.55", "Salary: Acme Analytics", "Acme Analytics", "deposit", "salary"),
        (13, "acc-everyday", "-74.99", "Card payment: Voltly Store", "Voltly Store", "card", "shopping"),
        (14, "acc-everyday", "-74.99", "Card payment: Voltly Store", "Voltly Store", "card", "shopping"),
        (20, "acc-savings", "4.12", "Interest", "", "interest", ""),
    ]
    transactions = {}
    for index, (days, account, amount, description, who, kind, category) in enumerate(rows, start=1):
        transaction_id = f"txn-{index}"
        transactions[transaction_id] = {
            "transaction_id": transaction_id,
            "account_id": account,
            "amount": amount,
            "description": description,
            "counterparty": who,
            "kind": kind,
            "category": category,
            "booked_at": (START - timedelta(days=days, hours=index)).isoformat(),
            "card_id": "card-debit" if kind == "card" else None,
        }
    transactions["txn-7"]["related_transaction_id"] = "txn-8"
    transactions["txn-8"]["related_transaction_id"] = "txn-7"
    payees = {
        payee_id: {"payee_id": payee_id, "name": name, "account_number": number, "bank": bank}
        for payee_id, name, number, bank in [
            ("payee-bob", "Bob Okafor", "GB29 NWBK 6016 1331 9268 19", "NatWest"),
            ("payee-emma", "Emma Schulz", "DE89 3704 0044 0532 0130 00", "Commerzbank"),
            ("payee-ivan", "Petrov Plumbing", "GB94 BARC 1020 1530 0934 59", "Barclays"),
            ("payee-julia", "Julia Costa", "GB33 BUKB 2020 1555 5555 55", "Monzo"),
        ]
    }
    standing_orders = {
        "so-rent": {
            "standing_order_id": "so-rent",
            "account_id": "acc-everyday",
            "payee_id": "payee-bob",
            "amount": "1450.00",
            "frequency": "monthly",
            "next_payment": (START + timedelta(days=2)).isoformat(),
            "reference": "Rent flat 4B",
        },
        "so-savings": {
            "standing_order_id": "so-savings",
            "account_id": "acc-everyday",
            "payee_id": "payee-julia",
            "amount": "20.00",
            "frequency": "weekly",
            "next_payment": (START + timedelta(days=4)).isoformat(),
            "reference": "Allotment share",
        },
    }
    direct_debits = {
        debit_id: {
            "direct_debit_id": debit_id,
            "account_id": "acc-everyday",
            "merchant": merchant,
            "reference": reference,
            "last_amount": last,
        }
        for debit_id, merchant, reference, last in [
            ("dd-power", "City Power & Gas", "CPG-558120", "48.00"),
            ("dd-phone", "Telco Mobile", "TM-0098812", "22.50"),
            ("dd-gym", "Studio 5 Gym", "S5-3391", "39.00"),
        ]
    }
    cards = {
        "card-debit": {"card_id": "card-debit", "account_id": "acc-everyday", "last_four": "4821"},
        "card-spare": {
            "card_id": "card-spare",
            "account_id": "acc-everyday",
            "name": "Spare debit card",
            "last_four": "7730",
            "frozen": True,
        },
    }
    disputes = {
        "dispute-1": {
            "dispute_id": "dispute-1",
            "transaction_id": "txn-12",
            "reason": "Charged twice for one charger.",
            "opened_at": (START - timedelta(days=1)).isoformat(),
        }
    }
    return {
        "accounts": accounts,
        "transactions": transactions,
        "payees": payees,
        "standing_orders": standing_orders,
        "direct_debits": direct_debits,
        "cards": cards,
        "disputes": disputes,
    }


def sample_world() -> dict[str, dict[str, Any]]:
    """Seed data for every app."""
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
        "reminder": _reminder(),
        "notes": _notes(),
        "cab": _cab(),
        "apartment": _apartment(),
        "shopping": _shopping(),
        "banking": _banking(),
    }
