"""A small valid scenario for unit tests, and ways to break it."""

from __future__ import annotations

import copy
from typing import Any

import yaml

from pare.scenarios import Scenario, parse_scenario

BASE: dict[str, Any] = {
    "id": "tiny_reply",
    "title": "Reply to Ann",
    "story": "Ann asks whether Thursday works; the assistant should reply yes.",
    "tags": ["context_observation"],
    "difficulty": "easy",
    "apps": ["email", "calendar"],
    "start": "2025-03-03T09:00:00Z",
    "seed": {
        "email": {
            "user_email": "me@pare.example",
            "emails": [
                {
                    "email_id": "e1",
                    "sender": "bob@x.example",
                    "subject": "Lunch",
                    "content": "Lunch on Friday?",
                    "timestamp": "-1h",
                }
            ],
        },
        "calendar": {
            "events": [
                {
                    "event_id": "ev1",
                    "title": "Standup",
                    "start_datetime": "day+1 09:30",
                    "end_datetime": "day+1 09:45",
                }
            ]
        },
    },
    "events": [
        {
            "id": "ann_asks",
            "at": "+5m",
            "tool": "email__receive_email",
            "args": {
                "email_id": "e_ann",
                "sender": "ann@x.example",
                "subject": "Thursday?",
                "content": "Does Thursday work?",
            },
        }
    ],
    "oracle": {
        "user": [
            {"tool": "open_app", "args": {"app_name": "email"}, "when": {"event": "ann_asks"}},
            {"tool": "open_email", "args": {"email_id": "e_ann"}},
        ],
        "interventions": [
            {
                "when": {"action": {"actor": "user", "tool": "email__open_email"}},
                "proposal": "Reply to Ann that Thursday works.",
                "actions": [
                    {
                        "tool": "email__reply_to_email",
                        "args": {"email_id": "e_ann", "content": "Thursday works!"},
                    }
                ],
            }
        ],
    },
    "goals": [
        {
            "id": "replied",
            "description": "Ann has a yes.",
            "checks": [
                {
                    "action": {
                        "tool": "email__reply_to_email",
                        "args": {"email_id": "e_ann", "content": {"contains": "thursday"}},
                    }
                }
            ],
        }
    ],
}


def base() -> dict[str, Any]:
    return copy.deepcopy(BASE)


def to_yaml(data: dict[str, Any]) -> str:
    return yaml.safe_dump(data, sort_keys=False)


def parse(data: dict[str, Any]) -> Scenario:
    return parse_scenario(to_yaml(data), source="tiny.yaml")


THURSDAY = "day+3"  # the base scenario starts on Monday 3 March 2025

REPLY = {
    "tool": "email__reply_to_email",
    "args": {"email_id": "e_ann", "content": "Yes, Thursday works for me!"},
}


def intervention(*actions: dict[str, Any]) -> dict[str, Any]:
    return {
        "when": {"action": {"actor": "user", "tool": "email__open_email"}},
        "proposal": "Reply to Ann that Thursday works.",
        "actions": list(actions),
    }


def fair() -> dict[str, Any]:
    """The base scenario brought to the standard: attribution, a reactive branch, by-hand steps, variants."""
    data = base()
    data["events"].append(
        {
            "id": "ann_confirms",
            "when": {"tool": "email__reply_to_email", "args": {"email_id": "e_ann"}},
            "if_args": {"content": {"mentions_day": THURSDAY}},
            "delay": "5m",
            "tool": "email__receive_email",
            "args": {
                "email_id": "e_conf",
                "sender": "ann@x.example",
                "subject": "Re",
                "content": "Great, see you!",
            },
            "otherwise": {
                "tool": "email__receive_email",
                "args": {
                    "email_id": "e_what",
                    "sender": "ann@x.example",
                    "subject": "Re",
                    "content": "Which day?",
                },
            },
        }
    )
    data["oracle"]["interventions"] = [intervention(REPLY)]
    data["oracle"]["by_hand"] = [
        {"tool": "open_app", "args": {"app_name": "email"}, "when": {"event": "ann_asks"}},
        {"tool": "open_email", "args": {"email_id": "e_ann"}},
        {"tool": "reply", "args": {"content": "Thursday works!"}},
    ]
    data["goals"] = [
        {
            "id": "replied",
            "description": "The assistant told Ann that Thursday works.",
            "checks": [
                {
                    "state": {
                        "path": "email.emails",
                        "by": "assistant",
                        "where": {
                            "folder": "SENT",
                            "recipients": {"contains": "ann@x.example"},
                            "content": {"mentions_day": THURSDAY},
                        },
                    }
                },
                {
                    "state": {
                        "path": "email.emails",
                        "where": {"folder": "SENT", "recipients": {"contains": "bob"}},
                        "count": 0,
                    }
                },
            ],
        }
    ]
    data["variants"] = [
        {
            "id": "fresh_email",
            "expect": "pass",
            "why": "A new email instead of a reply, written differently.",
            "interventions": [
                intervention(
                    {
                        "tool": "email__send_email",
                        "args": {
                            "recipients": ["ann@x.example"],
                            "subject": "Thu",
                            "content": "Thu is fine by me.",
                        },
                    }
                )
            ],
        },
        {
            "id": "declines",
            "expect": "fail",
            "why": "Saying Thursday does not work is not a yes.",
            "fails": ["replied"],
            "interventions": [
                intervention(
                    {**REPLY, "args": {"email_id": "e_ann", "content": "Sorry, Thursday does not work."}}
                )
            ],
        },
        {
            "id": "wrong_person",
            "expect": "fail",
            "why": "Bob asked about Friday lunch, not Ann.",
            "fails": ["replied"],
            "interventions": [
                intervention({**REPLY, "args": {"email_id": "e1", "content": "Thursday works!"}})
            ],
        },
    ]
    return data


THANKS = {
    "email_id": "e_thanks",
    "sender": "ann@x.example",
    "subject": "Re: Thursday?",
    "content": "Thanks, see you Thursday!",
}


def replying(delay: str = "20m") -> dict[str, Any]:
    """The base scenario where Ann thanks the user ``delay`` after the reply, a note from her follows 5
    minutes after that, and the goal needs her thanks; a newsletter is due hours later.
    """
    data = base()
    data["events"] += [
        {
            "id": "ann_thanks",
            "when": {"tool": "email__reply_to_email", "args": {"email_id": "e_ann"}},
            "delay": delay,
            "tool": "email__receive_email",
            "args": THANKS,
        },
        {
            "id": "ann_ps",
            "after": "ann_thanks",
            "delay": "5m",
            "tool": "email__receive_email",
            "args": {**THANKS, "email_id": "e_ps", "content": "PS: bring the slides."},
        },
        {
            "id": "newsletter",
            "at": "+6h",
            "tool": "email__receive_email",
            "args": {**THANKS, "email_id": "e_news", "sender": "news@x.example", "content": "News."},
        },
    ]
    data["goals"][0]["checks"].append(
        {"action": {"actor": "env", "tool": "email__receive_email", "args": {"email_id": "e_thanks"}}}
    )
    return data


def sound() -> dict[str, Any]:
    """:func:`fair` with what the gate demands of a library scenario: what Ann is told is read by a judge
    check (a false text to her must not pass), and her reply reads the text by a judge criterion too.
    """
    data = fair()
    data["events"][-1]["judge"] = {"criterion": "The email tells Ann that Thursday works."}
    data["goals"][0]["checks"].append(
        {
            "judge": {
                "criterion": "The email tells Ann that Thursday works.",
                "action": {"actor": "assistant", "to": "ann@x.example"},
                "field": "content",
                "fallback": {"mentions_day": THURSDAY},
            }
        }
    )
    return data
