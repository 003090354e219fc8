"""Banking: every screen action with where it leads and what it changes, every agent tool with its result
and its errors (each error leaving the data as it was), the world's tools, money and the seed format."""

from __future__ import annotations

import random
from datetime import UTC, datetime, timedelta
from decimal import Decimal
from typing import Any

import pytest

from pare.apps.banking import BankingApp, fmt
from pare.apps.registry import get_app_class, phone_apps
from pare.env import Environment
from pare.env.random_walk import RandomAssistant, RandomUser
from pare.errors import UserInputError
from pare.scenarios.seed import prepare_seed
from tests.conftest import START, err, make_env, ok, screen_of

# The episode starts on Monday 2025-03-03 at 09:00 UTC. Two current accounts and a savings account;
# a fortnight of transactions with look-alikes (two Voltly charges, two FreshMart shops).
# fmt: off
TRANSACTIONS = [
    # id, account, amount, description, counterparty, kind, days ago
    ("t-cafe", "acc-main", "-4.20", "Card payment: Corner Cafe", "Corner Cafe", "card", 1),
    ("t-shop1", "acc-main", "-62.15", "Card payment: FreshMart", "FreshMart", "card", 2),
    ("t-volt1", "acc-main", "-74.99", "Card payment: Voltly Store", "Voltly Store", "card", 3),
    ("t-volt2", "acc-main", "-74.99", "Card payment: Voltly Store", "Voltly Store", "card", 3),
    ("t-salary", "acc-main", "3120.55", "Salary: Acme Analytics", "Acme Analytics", "deposit", 4),
    ("t-shop2", "acc-main", "-33.40", "Card payment: FreshMart", "FreshMart", "card", 6),
    ("t-rent", "acc-main", "-1450.00", "Standing order: Rent Feb", "Bob Okafor", "standing_order", 26),
    ("t-joint", "acc-joint", "-80.00", "Card payment: Garden Centre", "Garden Centre", "card", 2),
    ("t-interest", "acc-save", "4.12", "Interest", "", "interest", 20),
]
# fmt: on


def _seed() -> dict[str, Any]:
    return {
        "banking": {
            "accounts": [
                {
                    "account_id": "acc-main",
                    "name": "Everyday",
                    "number": "****4821",
                    "balance": 1000,
                    "overdraft_limit": "200.00",
                },
                {
                    "account_id": "acc-save",
                    "name": "Savings",
                    "kind": "savings",
                    "number": "****9930",
                    "balance": "5000.50",
                },
                {"account_id": "acc-joint", "name": "Joint", "number": "****1177", "balance": 40.1},
            ],
            "transactions": [
                {
                    "transaction_id": tid,
                    "account_id": acc,
                    "amount": amount,
                    "description": text,
                    "counterparty": who,
                    "kind": kind,
                    "booked_at": (START - timedelta(days=days)).isoformat(),
                    **({"card_id": "card-main"} if kind == "card" and acc == "acc-main" else {}),
                }
                for tid, acc, amount, text, who, kind, days in TRANSACTIONS
            ],
            "payees": [
                {"payee_id": "p-bob", "name": "Bob Okafor", "account_number": "GB29 NWBK 6016 1331 9268 19"},
                {
                    "payee_id": "p-jo",
                    "name": "Jo Park",
                    "account_number": "GB33 BUKB 2020 1555 5555 55",
                    "bank": "Monzo",
                },
                {
                    "payee_id": "p-old",
                    "name": "Old Landlord",
                    "account_number": "GB11 OLDL 0000 0000 0000 01",
                },
            ],
            "standing_orders": [
                {
                    "standing_order_id": "so-rent",
                    "account_id": "acc-main",
                    "payee_id": "p-bob",
                    "amount": "1450.00",
                    "next_payment": "2025-03-31T09:00:00Z",
                    "reference": "Rent",
                },
                {
                    "standing_order_id": "so-old",
                    "account_id": "acc-main",
                    "payee_id": "p-old",
                    "amount": "10.00",
                    "next_payment": "2025-02-01T09:00:00Z",
                    "status": "cancelled",
                    "cancelled_at": "2025-01-20T09:00:00Z",
                },
            ],
            "direct_debits": [
                {
                    "direct_debit_id": "dd-power",
                    "account_id": "acc-main",
                    "merchant": "City Power & Gas",
                    "reference": "CPG-558120",
                    "last_amount": 48,
                },
                {
                    "direct_debit_id": "dd-gym",
                    "account_id": "acc-main",
                    "merchant": "Studio 5 Gym",
                    "reference": "S5-3391",
                    "status": "cancelled",
                },
            ],
            "cards": [
                {"card_id": "card-main", "account_id": "acc-main", "last_four": "4821"},
                {"card_id": "card-joint", "account_id": "acc-joint", "last_four": "1177", "frozen": True},
            ],
        },
        "files": {"files": {"/Documents/notes.txt": {"content": "hello"}}},
    }


def bank_env(seed: dict[str, Any], start: datetime = START) -> Environment:
    """An environment with ``seed`` written as scenario files write it (lists by id, relative times)."""
    prepared = {app: prepare_seed(app, data, start)[0] for app, data in seed.items()}
    return make_env(["banking"], prepared, start_time=start)


@pytest.fixture
def env() -> Environment:
    env = bank_env(_seed())
    ok(env.call("user", "open_app", {"app_name": "banking"}))
    return env


def bank(env: Environment) -> dict[str, Any]:
    return env.snapshot()["banking"]


def user(env: Environment, action: str, **args: Any) -> Any:
    return ok(env.call("user", action, args))


def user_fails(env: Environment, action: str, *fragments: str, **args: Any) -> str:
    before = env.snapshot()
    message = err(env.call("user", action, args), *fragments)
    assert env.snapshot() == before
    return message


def agent(env: Environment, tool: str, **args: Any) -> Any:
    return ok(env.call("assistant", f"banking__{tool}", args, mode="execute"))


def agent_fails(env: Environment, tool: str, *fragments: str, **args: Any) -> str:
    before = env.snapshot()
    message = err(env.call("assistant", f"banking__{tool}", args, mode="execute"), *fragments)
    assert env.snapshot() == before, "a failed call changed the data"
    return message


def world(env: Environment, tool: str, **args: Any) -> Any:
    return ok(env.call("env", f"banking__{tool}", args))


def balance(env: Environment, account_id: str) -> str:
    value: str = bank(env)["accounts"][account_id]["balance"]
    return value


def stack(env: Environment) -> list[str]:
    return [s.screen_name() for s in env.system.stacks["banking"]]


def last_notice(env: Environment) -> Any:
    return env.notifications.inboxes["assistant"].items[-1]


# -- the app ---------------------------------------------------------------------------------------------


def test_banking_is_one_of_the_phone_s_apps() -> None:
    assert "banking" in phone_apps()
    assert get_app_class("banking") is BankingApp


def test_every_write_tool_has_a_harm_class_and_money_out_is_irreversible() -> None:
    writes = {name for name, spec in BankingApp.tools.items() if spec.kind == "write"}
    assert set(BankingApp.harm) == writes
    assert BankingApp.harm["pay_payee"] == BankingApp.harm["transfer_between_accounts"] == "irreversible"
    assert BankingApp.harm["freeze_card"] == "reversible"
    assert BankingApp.harm["cancel_standing_order"] == BankingApp.harm["dispute_transaction"] == "costly"


def test_models_read_amounts_as_numbers() -> None:
    spec = BankingApp.tools["pay_payee"]
    assert "amount: number (at most two decimals)" in spec.signature
    assert spec.parameters_schema["properties"]["amount"]["type"] == "number"


def test_amounts_are_exact_and_shown_with_two_decimals(env: Environment) -> None:
    state = bank(env)
    assert state["accounts"]["acc-main"]["balance"] == "1000.00"
    assert state["accounts"]["acc-joint"]["balance"] == "40.10"  # a YAML float is read as written
    assert state["direct_debits"]["dd-power"]["last_amount"] == "48.00"
    app = env.apps["banking"]
    assert isinstance(app.state.accounts["acc-main"].balance, Decimal)
    assert fmt(Decimal("-1234.5")) == "-$1,234.50"


@pytest.mark.parametrize(
    ("change", "message"),
    [
        ({"accounts": [{"account_id": "a", "name": "A", "balance": "1.005"}]}, "fractions of a cent"),
        ({"accounts": [{"account_id": "a", "name": "A", "balance": "1e12"}]}, "below"),
        ({"accounts": [{"account_id": "a", "name": "A", "balance": "NaN"}]}, "finite"),
        ({"accounts": [{"account_id": "a", "name": "A", "balance": -50}]}, "below the overdraft"),
        ({"accounts": {"x": {"account_id": "a", "name": "A", "balance": 1}}}, "stored under 'x'"),
        (
            {
                "transactions": [
                    {
                        "transaction_id": "t",
                        "account_id": "nope",
                        "amount": 1,
                        "description": "d",
                        "booked_at": "-1h",
                    }
                ]
            },
            "not an account",
        ),
        (
            {
                "accounts": [{"account_id": "a", "name": "A", "balance": 1}],
                "transactions": [
                    {
                        "transaction_id": "t",
                        "account_id": "a",
                        "amount": 0,
                        "description": "d",
                        "booked_at": "-1h",
                    }
                ],
            },
            "cannot be 0",
        ),
        (
            {
                "accounts": [{"account_id": "a", "name": "A", "balance": 1}],
                "standing_orders": [
                    {
                        "standing_order_id": "s",
                        "account_id": "a",
                        "payee_id": "p",
                        "amount": 5,
                        "next_payment": "+1d",
                    }
                ],
            },
            "not a payee",
        ),
        ({"cards": [{"card_id": "c", "account_id": "a", "last_four": "12"}]}, "last_four"),
        (
            {"disputes": [{"dispute_id": "d", "transaction_id": "t", "reason": "r", "opened_at": "-1h"}]},
            "not a transaction",
        ),
    ],
)
def test_seed_data_is_checked(change: dict[str, Any], message: str) -> None:
    with pytest.raises(UserInputError, match=message):
        bank_env({"banking": change})


def test_seed_records_cannot_be_dated_after_the_start() -> None:
    seed = _seed()
    seed["banking"]["transactions"][0]["booked_at"] = (START + timedelta(hours=1)).isoformat()
    with pytest.raises(UserInputError, match="transaction 't-cafe' booked"):
        bank_env(seed)


def test_a_monthly_standing_order_knows_its_day() -> None:
    env = bank_env(_seed())
    assert env.apps["banking"].state.standing_orders["so-rent"].day_of_month == 31


# -- Home ------------------------------------------------------------------------------------------------


def test_opens_on_home_showing_the_accounts(env: Environment) -> None:
    assert stack(env) == ["Home"]
    shown = env.apps["banking"].screens[0]().display(env.apps["banking"])
    assert [a["account_id"] for a in shown["accounts"]] == ["acc-main", "acc-save", "acc-joint"]
    assert shown["accounts"][0]["available"] == Decimal("1200.00")
    assert shown["frozen_cards"] == ["card-joint"]


def test_open_account_goes_to_the_account_with_its_latest_transactions(env: Environment) -> None:
    result = user(env, "open_account", account_id="acc-main")
    assert stack(env) == ["Home", "Account"]
    assert result["available"] == "1200.00"
    assert [t["transaction_id"] for t in result["recent"]["transactions"]] == [
        "t-cafe",
        "t-shop1",
        "t-volt2",  # of two booked at one time, the later added comes first
        "t-volt1",
        "t-salary",
    ]
    assert result["recent"]["showing"] == "1-5 of 7; offset=5 shows the next"
    assert [c["card_id"] for c in result["cards"]] == ["card-main"]


def test_open_unknown_account_is_an_error_and_stays(env: Environment) -> None:
    user_fails(env, "open_account", "no account", "acc-main", account_id="acc-nope")
    assert stack(env) == ["Home"]


def test_home_search_reads_every_account(env: Environment) -> None:
    found = user(env, "search_transactions", query="card payment")
    assert found["total"] == 6 and found["showing"] == "1-5 of 6; offset=5 shows the next"
    assert {t["account_id"] for t in found["transactions"]} == {"acc-main", "acc-joint"}
    assert user(env, "search_transactions", query="lottery")["total"] == 0  # no match is a result
    assert stack(env) == ["Home"]


def test_home_lists_disputes(env: Environment) -> None:
    assert user(env, "list_disputes") == []
    agent(env, "dispute_transaction", transaction_id="t-volt2", reason="Charged twice")
    assert [d["transaction_id"] for d in user(env, "list_disputes")] == ["t-volt2"]


def test_home_leads_to_payees_standing_orders_direct_debits_and_cards(env: Environment) -> None:
    assert [p["payee_id"] for p in user(env, "open_payees")] == ["p-bob", "p-jo", "p-old"]
    assert stack(env) == ["Home", "Payees"]
    user(env, "go_back")
    assert [o["standing_order_id"] for o in user(env, "open_standing_orders")] == ["so-rent"]
    assert screen_of(env) == "StandingOrders"
    user(env, "go_back")
    assert [d["direct_debit_id"] for d in user(env, "open_direct_debits")] == ["dd-power"]
    assert screen_of(env) == "DirectDebits"
    user(env, "go_back")
    assert [c["card_id"] for c in user(env, "open_cards")] == ["card-main", "card-joint"]
    assert screen_of(env) == "Cards"


# -- Account and Transaction -------------------------------------------------------------------------


def test_account_pages_searches_and_opens_transactions(env: Environment) -> None:
    user(env, "open_account", account_id="acc-main")
    page = user(env, "list_transactions", offset=5)
    assert [t["transaction_id"] for t in page["transactions"]] == ["t-shop2", "t-rent"]
    assert page["showing"] == "6-7 of 7 (the last)"
    found = user(env, "search_transactions", query="freshmart")
    assert [t["transaction_id"] for t in found["transactions"]] == ["t-shop1", "t-shop2"]
    shown = user(env, "open_transaction", transaction_id="t-volt2")
    assert shown["amount"] == "-74.99"
    assert stack(env) == ["Home", "Account", "Transaction"]
    assert user(env, "view_transaction")["description"] == "Card payment: Voltly Store"


def test_account_screen_says_when_it_shows_part_of_its_transactions(env: Environment) -> None:
    user(env, "open_account", account_id="acc-main")
    app = env.apps["banking"]
    shown = env.system.current_screen().display(app)  # type: ignore[union-attr]
    assert shown["total_transactions"] == 7 and len(shown["transactions"]) == 5
    assert shown["showing"] == "1-5 of 7; list_transactions(offset=5) shows the next"


def test_open_unknown_transaction_is_an_error(env: Environment) -> None:
    user(env, "open_account", account_id="acc-main")
    user_fails(env, "open_transaction", "no transaction", transaction_id="t-nope")
    assert screen_of(env) == "Account"


def test_dispute_from_the_transaction_screen(env: Environment) -> None:
    user(env, "open_account", account_id="acc-main")
    user(env, "open_transaction", transaction_id="t-volt2")
    done = user(env, "dispute", reason="Charged twice for one charger")
    dispute = bank(env)["disputes"][done["id"]]
    assert dispute["transaction_id"] == "t-volt2" and dispute["status"] == "open"
    assert screen_of(env) == "Transaction"
    shown = env.system.current_screen().display(env.apps["banking"])  # type: ignore[union-attr]
    assert [d["dispute_id"] for d in shown["disputes"]] == [done["id"]]
    user_fails(env, "dispute", "already disputed", reason="again")


def test_download_statement_from_the_account_screen_writes_a_file(env: Environment) -> None:
    user(env, "open_account", account_id="acc-main")
    done = user(env, "download_statement", month="2025-02")
    assert done["id"] == "/Documents/Statements/statement_acc-main_2025-02.txt"
    text = env.snapshot()["files"]["files"][done["id"]]["content"]
    # March so far holds the cafe and the first FreshMart shop; February the rest of the main account's
    closing = Decimal("1000.00") - (Decimal("-4.20") + Decimal("-62.15"))
    february = 2 * Decimal("-74.99") + Decimal("3120.55") + Decimal("-33.40") + Decimal("-1450.00")
    assert f"Closing balance: {fmt(closing)}" in text and fmt(closing) == "$1,066.35"
    assert f"Opening balance: {fmt(closing - february)}" in text and fmt(closing - february) == "-$420.82"
    assert "t-rent" in text and "t-volt2" in text and "t-cafe" not in text
    assert "Money in: $3,120.55\nMoney out: $1,633.38\n" in text


@pytest.mark.parametrize(
    ("month", "message"),
    [
        ("2025-13", "YYYY-MM"),
        ("March", "YYYY-MM"),
        ("2025-04", "has not started"),
        ("0999-01", "no statement"),
    ],
)
def test_download_statement_errors_change_nothing(env: Environment, month: str, message: str) -> None:
    agent_fails(env, "download_statement", message, account_id="acc-main", month=month)


def test_a_statement_cannot_replace_a_directory(env: Environment) -> None:
    agent_fails(
        env,
        "download_statement",
        "is a file",
        account_id="acc-main",
        month="2025-03",
        directory="/Documents/notes.txt",
    )


def test_the_current_month_s_statement_is_the_month_so_far(env: Environment) -> None:
    done = agent(env, "download_statement", account_id="acc-joint", month="2025-03", directory="/Bank")
    text = env.snapshot()["files"]["files"][done["id"]]["content"]
    assert done["id"] == "/Bank/statement_acc-joint_2025-03.txt"
    assert "Opening balance: $120.10" in text and "Closing balance: $40.10" in text


# -- Payees ----------------------------------------------------------------------------------------------


def test_payees_screen_adds_lists_and_deletes(env: Environment) -> None:
    user(env, "open_payees")
    done = user(
        env, "add_payee", name=" Dana Reyes ", account_number="GB44  DANA 0000 1111 2222 33", bank="Monzo"
    )
    payee = bank(env)["payees"][done["id"]]
    assert payee["name"] == "Dana Reyes" and payee["account_number"] == "GB44 DANA 0000 1111 2222 33"
    assert "Dana Reyes" in [p["name"] for p in user(env, "list_payees")]
    assert "Deleted" in user(env, "delete_payee", payee_id=done["id"])
    assert done["id"] not in bank(env)["payees"]
    assert screen_of(env) == "Payees"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"name": " ", "account_number": "X1"}, "needs a name"),
        ({"name": "Jo again", "account_number": "GB33BUKB20201555555555"}, "already has account number"),
    ],
)
def test_add_payee_errors_change_nothing(env: Environment, args: dict[str, str], message: str) -> None:
    agent_fails(env, "add_payee", message, **args)


def test_a_payee_named_by_a_standing_order_is_kept(env: Environment) -> None:
    agent_fails(env, "delete_payee", "cancel them first", payee_id="p-bob")
    agent_fails(env, "delete_payee", "is kept", payee_id="p-old")
    agent_fails(env, "delete_payee", "no payee", payee_id="p-nope")


# -- Pay -> Review -> confirm ------------------------------------------------------------------------------


def test_paying_a_payee_is_reviewed_then_confirmed(env: Environment) -> None:
    user(env, "open_payees")
    draft = user(env, "pay", payee_id="p-jo")
    assert stack(env) == ["Home", "Payees", "Pay"]
    assert draft["from_account_id"] == "acc-main" and draft["to"].startswith("Jo Park")
    user(env, "set_amount", amount=42.5)
    user(env, "set_reference", reference=" Pizza night ")
    review = user(env, "review")
    assert stack(env) == ["Home", "Payees", "Pay", "Review"]
    assert review["pay"] == "$42.50" and review["balance_after"] == "$957.50"
    assert bank(env)["transactions"].keys() == {t[0] for t in TRANSACTIONS}  # nothing sent yet
    done = user(env, "confirm")
    assert stack(env) == ["Home"]
    assert balance(env, "acc-main") == "957.50"
    paid = bank(env)["transactions"][done["id"]]
    assert paid["amount"] == "-42.50" and paid["payee_id"] == "p-jo" and paid["reference"] == "Pizza night"
    assert paid["kind"] == "payment" and paid["booked_at"] == "2025-03-03T09:00:00Z"


def test_a_transfer_is_reviewed_then_confirmed(env: Environment) -> None:
    user(env, "move_money")
    assert stack(env) == ["Home", "Pay"]
    user(env, "set_from_account", account_id="acc-save")
    user(env, "set_to_account", account_id="acc-joint")
    user(env, "set_amount", amount="100")
    assert user(env, "review")["to"] == "your Joint account (acc-joint)"
    user(env, "confirm")
    assert (balance(env, "acc-save"), balance(env, "acc-joint")) == ("4900.50", "140.10")


def test_the_form_switches_between_a_payee_and_an_account(env: Environment) -> None:
    user(env, "move_money")
    assert user(env, "set_payee", payee_id="p-bob")["payee_id"] == "p-bob"
    draft = user(env, "set_to_account", account_id="acc-save")
    assert draft["payee_id"] is None and draft["to_account_id"] == "acc-save"
    assert user(env, "set_payee", payee_id="p-jo")["to_account_id"] is None


def test_review_says_what_is_missing(env: Environment) -> None:
    user(env, "move_money")
    user_fails(env, "review", "who to pay", "the amount")
    assert screen_of(env) == "Pay"


@pytest.mark.parametrize(
    ("action", "args", "message"),
    [
        ("set_amount", {"amount": 0}, "above 0"),
        ("set_amount", {"amount": -5}, "above 0"),
        ("set_amount", {"amount": 1.234}, "fractions of a cent"),
        ("set_payee", {"payee_id": "p-nope"}, "no payee"),
        ("set_to_account", {"account_id": "acc-nope"}, "no account"),
        ("set_from_account", {"account_id": "acc-nope"}, "no account"),
    ],
)
def test_form_errors_leave_the_draft(
    env: Environment, action: str, args: dict[str, Any], message: str
) -> None:
    user(env, "move_money")
    before = env.system.current_screen()
    user_fails(env, action, message, **args)
    assert env.system.current_screen() == before


def test_review_refuses_more_than_is_available(env: Environment) -> None:
    user(env, "open_payees")
    user(env, "pay", payee_id="p-jo")
    user(env, "set_amount", amount=1200.01)
    user_fails(env, "review", "insufficient funds", "$1,200.00 available", "with its $200.00 overdraft")
    user(env, "set_amount", amount=1200)  # the overdraft may be used to the last cent
    user(env, "review")
    user(env, "confirm")
    assert balance(env, "acc-main") == "-200.00"


def test_review_refuses_a_transfer_to_the_same_account(env: Environment) -> None:
    user(env, "move_money")
    user(env, "set_to_account", account_id="acc-main")
    user(env, "set_amount", amount=5)
    user_fails(env, "review", "same")


def test_confirm_rechecks_the_balance(env: Environment) -> None:
    user(env, "open_payees")
    user(env, "pay", payee_id="p-jo")
    user(env, "set_amount", amount=1000)
    user(env, "review")
    agent(env, "transfer_between_accounts", from_account_id="acc-main", to_account_id="acc-save", amount=500)
    user_fails(env, "confirm", "insufficient funds", "nothing was paid")
    assert screen_of(env) == "Review"


def test_discard_goes_back_without_sending(env: Environment) -> None:
    user(env, "open_payees")
    user(env, "pay", payee_id="p-jo")
    user(env, "set_amount", amount=10)
    assert "nothing was sent" in user(env, "discard")
    assert stack(env) == ["Home", "Payees"]
    assert balance(env, "acc-main") == "1000.00"


def test_going_back_from_review_keeps_the_draft_and_discard_returns_home(env: Environment) -> None:
    user(env, "move_money")
    user(env, "set_payee", payee_id="p-bob")
    user(env, "set_amount", amount=12)
    user(env, "review")
    user(env, "go_back")
    assert stack(env) == ["Home", "Pay"]
    assert env.system.current_screen().amount == Decimal("12.00")  # type: ignore[union-attr]
    user(env, "discard")
    assert stack(env) == ["Home"] and balance(env, "acc-main") == "1000.00"


def test_review_shows_when_its_account_is_gone(env: Environment) -> None:
    user(env, "move_money")
    user(env, "set_payee", payee_id="p-jo")
    user(env, "set_amount", amount=1)
    user(env, "review")
    screen = env.system.current_screen()
    del env.apps["banking"].state.accounts["acc-main"]
    assert "no longer exists" in screen.display(env.apps["banking"])  # type: ignore[union-attr,operator]


# -- agent: payments and transfers ----------------------------------------------------------------------


def test_pay_payee_pays_exactly(env: Environment) -> None:
    for _ in range(3):  # 0.1 three times is 0.30 exactly
        agent(env, "pay_payee", payee_id="p-jo", amount=0.1, from_account_id="acc-joint")
    assert balance(env, "acc-joint") == "39.80"
    done = agent(
        env, "pay_payee", payee_id="p-jo", amount="39.80", from_account_id="acc-joint", reference="x"
    )
    assert done["done"] == "Paid $39.80 to Jo Park from Joint (acc-joint), reference 'x'. Balance now $0.00."
    assert balance(env, "acc-joint") == "0.00"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"payee_id": "p-jo", "amount": 40.11, "from_account_id": "acc-joint"}, "insufficient funds"),
        ({"payee_id": "p-jo", "amount": 0, "from_account_id": "acc-joint"}, "above 0"),
        ({"payee_id": "p-jo", "amount": 1.001, "from_account_id": "acc-joint"}, "fractions of a cent"),
        ({"payee_id": "p-jo", "amount": "1e15", "from_account_id": "acc-joint"}, "below"),
        ({"payee_id": "p-nope", "amount": 1, "from_account_id": "acc-joint"}, "no payee"),
        ({"payee_id": "p-jo", "amount": 1, "from_account_id": "acc-nope"}, "no account"),
        ({"payee_id": "p-jo", "amount": "ten", "from_account_id": "acc-joint"}, "amount"),
    ],
)
def test_pay_payee_errors_change_nothing(env: Environment, args: dict[str, Any], message: str) -> None:
    agent_fails(env, "pay_payee", message, **args)


def test_a_payment_above_the_balance_says_how_much_is_missing(env: Environment) -> None:
    message = agent_fails(env, "pay_payee", payee_id="p-jo", amount=50, from_account_id="acc-joint")
    assert (
        "Joint (acc-joint) has $40.10 available, $9.90 less than the $50.00 asked. Nothing was paid."
        in message
    )


def test_transfer_moves_both_legs_together(env: Environment) -> None:
    done = agent(
        env,
        "transfer_between_accounts",
        from_account_id="acc-save",
        to_account_id="acc-main",
        amount="0.50",
        reference="top up",
    )
    out = bank(env)["transactions"][done["id"]]
    back = bank(env)["transactions"][out["related_transaction_id"]]
    assert (out["amount"], back["amount"]) == ("-0.50", "0.50")
    assert back["related_transaction_id"] == done["id"] and back["account_id"] == "acc-main"
    assert (balance(env, "acc-save"), balance(env, "acc-main")) == ("5000.00", "1000.50")


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (
            {"from_account_id": "acc-joint", "to_account_id": "acc-main", "amount": 40.11},
            "insufficient funds",
        ),
        ({"from_account_id": "acc-main", "to_account_id": "acc-main", "amount": 1}, "same"),
        ({"from_account_id": "acc-main", "to_account_id": "acc-nope", "amount": 1}, "no account"),
        ({"from_account_id": "acc-main", "to_account_id": "acc-save", "amount": -1}, "above 0"),
    ],
)
def test_transfer_errors_change_nothing(env: Environment, args: dict[str, Any], message: str) -> None:
    agent_fails(env, "transfer_between_accounts", message, **args)


# -- agent: reads ----------------------------------------------------------------------------------------


def test_agent_reads(env: Environment) -> None:
    accounts = agent(env, "list_accounts")
    assert [(a["account_id"], a["available"]) for a in accounts] == [
        ("acc-main", "1200.00"),
        ("acc-save", "5000.50"),
        ("acc-joint", "40.10"),
    ]
    details = agent(env, "get_account", account_id="acc-save")
    assert details["recent"]["showing"] == "all 1" and details["cards"] == []
    page = agent(env, "list_transactions")
    assert page["total"] == 9 and len(page["transactions"]) == 5
    assert agent(env, "list_transactions", account_id="acc-joint", limit=10)["showing"] == "all 1"
    assert agent(env, "get_transaction", transaction_id="t-rent")["amount"] == "-1450.00"
    assert [p["name"] for p in agent(env, "list_payees")] == ["Bob Okafor", "Jo Park", "Old Landlord"]
    assert [o["standing_order_id"] for o in agent(env, "list_standing_orders", include_cancelled=True)] == [
        "so-rent",
        "so-old",
    ]
    assert [d["direct_debit_id"] for d in agent(env, "list_direct_debits", include_cancelled=True)] == [
        "dd-power",
        "dd-gym",
    ]
    assert [c["frozen"] for c in agent(env, "list_cards")] == [False, True]
    assert agent(env, "list_disputes") == []


def test_reads_of_an_empty_bank_are_results() -> None:
    env = make_env(["banking"])
    assert agent(env, "list_accounts") == []
    assert agent(env, "list_transactions")["showing"] == "all 0"
    assert agent(env, "search_transactions", query="rent")["transactions"] == []
    for tool in ("list_payees", "list_standing_orders", "list_direct_debits", "list_cards", "list_disputes"):
        assert agent(env, tool) == []


def test_search_transactions_by_words_amount_and_dates(env: Environment) -> None:
    assert [
        t["transaction_id"] for t in agent(env, "search_transactions", query="74.99")["transactions"]
    ] == ["t-volt2", "t-volt1"]
    assert agent(env, "search_transactions", query="fresh card")["total"] == 2  # parts of words, every word
    assert agent(env, "search_transactions", query="standing order")["total"] == 1  # the kind is searched
    recent = agent(env, "search_transactions", since="2025-03-01 00:00", until="2025-03-02 12:00")
    assert [t["transaction_id"] for t in recent["transactions"]] == ["t-cafe", "t-joint", "t-shop1"]
    joint = agent(env, "search_transactions", query="garden", account_id="acc-joint")
    assert joint["total"] == 1
    assert agent(env, "search_transactions", query="garden", account_id="acc-main")["total"] == 0


@pytest.mark.parametrize(
    ("tool", "args", "message"),
    [
        ("search_transactions", {"query": "  "}, "words to search for"),
        ("search_transactions", {"query": "x", "limit": 0}, "limit"),
        ("list_transactions", {"offset": -1}, "offset"),
        ("list_transactions", {"account_id": "acc-nope"}, "no account"),
        ("get_account", {"account_id": "acc-nope"}, "the accounts are: everyday (acc-main)"),
        ("get_transaction", {"transaction_id": "t-nope"}, "search_transactions"),
    ],
)
def test_read_errors(env: Environment, tool: str, args: dict[str, Any], message: str) -> None:
    agent_fails(env, tool, message, **args)


# -- standing orders ---------------------------------------------------------------------------------


def test_standing_orders_screen_creates_and_cancels(env: Environment) -> None:
    user(env, "open_standing_orders")
    done = user(
        env,
        "create_standing_order",
        payee_id="p-jo",
        amount=25,
        first_payment="2025-03-10 08:00",
        frequency="weekly",
        reference="Allotment",
    )
    order = bank(env)["standing_orders"][done["id"]]
    assert order["account_id"] == "acc-main" and order["amount"] == "25.00" and order["frequency"] == "weekly"
    assert [o["standing_order_id"] for o in user(env, "list_standing_orders")] == [done["id"], "so-rent"]
    cancelled = user(env, "cancel_standing_order", standing_order_id=done["id"])
    assert cancelled["status"] == "cancelled" and cancelled["cancelled_at"] == "2025-03-03T09:00:00Z"
    assert user(env, "list_standing_orders") == [bank(env)["standing_orders"]["so-rent"]]
    assert screen_of(env) == "StandingOrders"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"first_payment": "2025-03-02 09:00"}, "in the past"),
        ({"end_date": "2025-03-05 09:00"}, "before the first payment"),
        ({"amount": 0}, "above 0"),
        ({"payee_id": "p-nope"}, "no payee"),
        ({"from_account_id": "acc-nope"}, "no account"),
        ({"frequency": "daily"}, "frequency"),
    ],
)
def test_create_standing_order_errors_change_nothing(
    env: Environment, args: dict[str, Any], message: str
) -> None:
    base = {
        "payee_id": "p-bob",
        "amount": 1450,
        "first_payment": "2025-04-01 09:00",
        "from_account_id": "acc-main",
    }
    agent_fails(env, "create_standing_order", message, **(base | args))


def test_cancel_standing_order_errors(env: Environment) -> None:
    agent_fails(env, "cancel_standing_order", "already cancelled", standing_order_id="so-old")
    agent_fails(env, "cancel_standing_order", "no standing order", standing_order_id="so-nope")


def test_standing_orders_are_paid_when_due_and_move_on(env: Environment) -> None:
    app = env.apps["banking"]
    agent(
        env,
        "create_standing_order",
        payee_id="p-jo",
        amount=20,
        first_payment="2025-03-04 08:00",
        frequency="weekly",
        from_account_id="acc-joint",
        end_date="2025-03-12 00:00",
    )
    assert app.next_wakeup() == datetime(2025, 3, 4, 8, 0, tzinfo=UTC)
    env.advance(timedelta(days=1))  # Tue 09:00: the first 20.00 went
    assert balance(env, "acc-joint") == "20.10"
    env.advance(timedelta(days=7))  # the second 20.00
    assert balance(env, "acc-joint") == "0.10"
    notices = [n.kind for n in env.notifications.inboxes["user"].items]
    assert "standing_order_failed" not in notices
    env.advance(timedelta(days=7))  # past its end: finished, nothing more paid
    orders = [o for o in bank(env)["standing_orders"].values() if o["payee_id"] == "p-jo"]
    assert orders[0]["status"] == "cancelled" and balance(env, "acc-joint") == "0.10"


def test_a_standing_order_the_account_cannot_cover_is_skipped_and_told(env: Environment) -> None:
    agent(
        env,
        "create_standing_order",
        payee_id="p-jo",
        amount=50,
        first_payment="2025-03-04 08:00",
        from_account_id="acc-joint",
    )
    env.advance(timedelta(days=1))
    assert balance(env, "acc-joint") == "40.10"
    assert last_notice(env).kind == "standing_order_failed"
    order = next(o for o in bank(env)["standing_orders"].values() if o["payee_id"] == "p-jo")
    assert order["next_payment"] == "2025-04-04T08:00:00Z"


def test_monthly_orders_keep_their_day_through_short_months() -> None:
    seed = _seed()
    seed["banking"]["standing_orders"][0]["next_payment"] = "2025-01-31T09:00:00Z"
    seed["banking"]["transactions"] = []
    seed["banking"]["accounts"][0]["balance"] = "5000.00"
    env = bank_env(seed, start=datetime(2025, 1, 31, 8, 0, tzinfo=UTC))
    env.advance(timedelta(days=59))  # to 31 Mar 08:00: paid 31 Jan and 28 Feb, next 31 Mar
    rents = [t for t in bank(env)["transactions"].values() if t["kind"] == "standing_order"]
    assert [t["booked_at"][:10] for t in rents] == ["2025-01-31", "2025-02-28"]
    order = bank(env)["standing_orders"]["so-rent"]
    assert order["next_payment"] == "2025-03-31T09:00:00Z"
    assert order["first_payment"] == "2025-01-31T09:00:00Z"  # kept as set up, for checks to read


# -- direct debits ----------------------------------------------------------------------------------------


def test_direct_debits_screen_sets_up_and_cancels(env: Environment) -> None:
    user(env, "open_direct_debits")
    done = user(env, "set_up_direct_debit", merchant="Telco Mobile", reference="TM-1")
    assert bank(env)["direct_debits"][done["id"]]["account_id"] == "acc-main"
    assert len(user(env, "list_direct_debits")) == 2
    assert user(env, "cancel_direct_debit", direct_debit_id=done["id"])["status"] == "cancelled"
    assert screen_of(env) == "DirectDebits"


def test_direct_debit_errors_change_nothing(env: Environment) -> None:
    agent_fails(
        env,
        "set_up_direct_debit",
        "already has an active",
        merchant="city power & gas",
        reference="CPG-558120",
        account_id="acc-main",
    )
    agent_fails(env, "set_up_direct_debit", "merchant", merchant=" ", reference="x", account_id="acc-main")
    agent_fails(env, "set_up_direct_debit", "no account", merchant="X", reference="x", account_id="acc-nope")
    agent_fails(env, "cancel_direct_debit", "already cancelled", direct_debit_id="dd-gym")
    agent_fails(env, "cancel_direct_debit", "no direct debit", direct_debit_id="dd-nope")


def test_a_collection_is_booked_or_refused(env: Environment) -> None:
    booked = world(
        env, "collect_direct_debit", direct_debit_id="dd-power", amount=51.3, transaction_id="t-power"
    )
    assert booked["amount"] == "-51.30" and balance(env, "acc-main") == "948.70"
    assert bank(env)["direct_debits"]["dd-power"]["last_amount"] == "51.30"
    assert "collected by City Power & Gas" in last_notice(env).headline
    agent(env, "cancel_direct_debit", direct_debit_id="dd-power")
    assert world(env, "collect_direct_debit", direct_debit_id="dd-power", amount=51.3).startswith("Refused")
    assert balance(env, "acc-main") == "948.70" and last_notice(env).kind == "direct_debit_refused"
    agent(env, "set_up_direct_debit", merchant="Big Bill", reference="B1", account_id="acc-joint")
    debit = next(d for d in bank(env)["direct_debits"].values() if d["merchant"] == "Big Bill")
    refused = world(env, "collect_direct_debit", direct_debit_id=debit["direct_debit_id"], amount=100)
    assert "only $40.10 available" in refused and balance(env, "acc-joint") == "40.10"


# -- cards ------------------------------------------------------------------------------------------------


def test_cards_screen_freezes_and_unfreezes(env: Environment) -> None:
    user(env, "open_cards")
    assert user(env, "freeze_card", card_id="card-main")["frozen"] is True
    user_fails(env, "freeze_card", "already frozen", card_id="card-main")
    assert user(env, "unfreeze_card", card_id="card-main")["frozen"] is False
    user_fails(env, "unfreeze_card", "not frozen", card_id="card-main")
    assert [c["card_id"] for c in user(env, "list_cards")] == ["card-main", "card-joint"]
    agent_fails(env, "freeze_card", "no card", card_id="card-nope")


def test_a_frozen_card_declines_payments(env: Environment) -> None:
    agent(env, "freeze_card", card_id="card-main")
    declined = world(
        env,
        "receive_transaction",
        account_id="acc-main",
        amount=-19.99,
        description="Card payment: WebShop",
        counterparty="WebShop",
        card_id="card-main",
    )
    assert declined.startswith("Declined") and balance(env, "acc-main") == "1000.00"
    assert last_notice(env).kind == "card_declined"
    agent(env, "unfreeze_card", card_id="card-main")
    booked = world(
        env,
        "receive_transaction",
        account_id="acc-main",
        amount=-19.99,
        description="Card payment: WebShop",
        counterparty="WebShop",
        card_id="card-main",
        transaction_id="t-web",
    )
    assert booked["transaction_id"] == "t-web" and balance(env, "acc-main") == "980.01"


def test_a_card_payment_above_what_is_available_is_declined(env: Environment) -> None:
    declined = world(
        env,
        "receive_transaction",
        account_id="acc-joint",
        amount=-40.11,
        description="Shop",
        card_id="card-joint",
    )
    assert declined.startswith("Declined")  # frozen card
    agent(env, "unfreeze_card", card_id="card-joint")
    declined = world(
        env,
        "receive_transaction",
        account_id="acc-joint",
        amount=-40.11,
        description="Shop",
        card_id="card-joint",
    )
    assert "only $40.10 available" in declined and balance(env, "acc-joint") == "40.10"
    assert last_notice(env).kind == "card_declined"


def test_money_arriving_is_booked_and_told(env: Environment) -> None:
    world(
        env,
        "receive_transaction",
        account_id="acc-joint",
        amount="12.50",
        description="Jo paid back",
        counterparty="Jo Park",
        kind="deposit",
    )
    assert balance(env, "acc-joint") == "52.60"
    assert last_notice(env).headline == "$12.50 from Jo Park"


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"amount": 0}, "cannot be 0"),
        ({"amount": -1, "card_id": "card-joint"}, "belongs to account acc-joint"),
        ({"amount": 1, "transaction_id": "t-cafe"}, "already exists"),
    ],
)
def test_receive_transaction_errors_change_nothing(
    env: Environment, args: dict[str, Any], message: str
) -> None:
    before = env.snapshot()
    err(
        env.call(
            "env", "banking__receive_transaction", {"account_id": "acc-main", "description": "x", **args}
        ),
        message,
    )
    assert env.snapshot() == before


# -- disputes ---------------------------------------------------------------------------------------------


def test_dispute_then_refund(env: Environment) -> None:
    done = agent(env, "dispute_transaction", transaction_id="t-volt2", reason=" Charged twice ")
    assert "Disputed t-volt2 (Card payment: Voltly Store, -$74.99)" in done["done"]
    resolved = world(env, "resolve_dispute", dispute_id=done["id"], refund=True, outcome="A duplicate.")
    assert resolved["status"] == "refunded" and balance(env, "acc-main") == "1074.99"
    refund = next(t for t in bank(env)["transactions"].values() if t["kind"] == "refund")
    assert refund["amount"] == "74.99" and refund["related_transaction_id"] == "t-volt2"
    assert last_notice(env).kind == "dispute"
    err(env.call("env", "banking__resolve_dispute", {"dispute_id": done["id"], "refund": False}), "already")


def test_a_rejected_dispute_refunds_nothing(env: Environment) -> None:
    done = agent(env, "dispute_transaction", transaction_id="t-cafe", reason="Not me")
    assert world(env, "resolve_dispute", dispute_id=done["id"], refund=False)["status"] == "rejected"
    assert balance(env, "acc-main") == "1000.00"
    agent(env, "dispute_transaction", transaction_id="t-cafe", reason="Still not me")  # may be raised again


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ({"transaction_id": "t-salary", "reason": "x"}, "money in"),
        ({"transaction_id": "t-cafe", "reason": "  "}, "reason"),
        ({"transaction_id": "t-nope", "reason": "x"}, "no transaction"),
    ],
)
def test_dispute_errors_change_nothing(env: Environment, args: dict[str, str], message: str) -> None:
    agent_fails(env, "dispute_transaction", message, **args)


def test_unknown_dispute_cannot_be_resolved(env: Environment) -> None:
    err(env.call("env", "banking__resolve_dispute", {"dispute_id": "d-nope", "refund": True}), "no dispute")


# -- who may call what ------------------------------------------------------------------------------------


def test_writes_need_execute_mode_and_world_tools_are_the_world_s(env: Environment) -> None:
    before = env.snapshot()
    err(
        env.call(
            "assistant",
            "banking__pay_payee",
            {"payee_id": "p-jo", "amount": 1, "from_account_id": "acc-main"},
            mode="observe",
        )
    )
    err(env.call("assistant", "banking__pay_due_standing_orders", {}, mode="execute"))
    err(env.call("user", "pay_payee", {"payee_id": "p-jo", "amount": 1, "from_account_id": "acc-main"}))
    assert env.snapshot() == before
    assert world(env, "pay_due_standing_orders") == []  # nothing is due yet


# -- fuzzing ----------------------------------------------------------------------------------------------


def _unexplained(env: Environment) -> dict[str, Decimal]:
    """Each account's balance less the sum of its transactions: what no transaction explains."""
    state = env.apps["banking"].state
    return {
        key: account.balance
        - sum((t.amount for t in state.transactions.values() if t.account_id == key), Decimal(0))
        for key, account in state.accounts.items()
    }


def test_a_random_user_walks_every_screen() -> None:
    env = bank_env(_seed())
    user = RandomUser(random.Random(0))
    for _ in range(3000):
        user.step(env)  # raise_internal_errors: a crash or an undeclared transition fails the test
    screens = {e.app_screen[1] for e in env.log if e.app_screen}
    assert screens == {s.screen_name() for s in BankingApp.screens}
    assert sum(e.ok for e in env.log) / len(env.log) > 0.5


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_every_balance_change_is_a_transaction_through_a_random_walk(seed: int) -> None:
    """Random users, assistants and world events, the clock moving on: no money appears or vanishes
    without a transaction, and no account goes below its overdraft."""
    env = bank_env(_seed())
    ok(env.call("user", "open_app", {"app_name": "banking"}))
    rng = random.Random(seed)
    user, assistant = RandomUser(rng), RandomAssistant(rng)
    start = _unexplained(env)
    moved = 0
    for _ in range(600):
        roll = rng.random()
        if roll < 0.1:
            args = {
                "account_id": rng.choice(["acc-main", "acc-joint"]),
                "description": "x",
                "amount": round(rng.uniform(-300, 300), 2) or 1,
                "card_id": None,
            }
            env.call("env", "banking__receive_transaction", args)
        elif roll < 0.15:
            env.advance(timedelta(days=rng.choice([1, 7, 31])))
        else:
            result = (user if roll < 0.55 else assistant).step(env)
            moved += result.ok and result.entry is not None and result.entry.kind == "write"
        assert _unexplained(env) == start
        for account in env.apps["banking"].state.accounts.values():
            assert account.available >= 0, account
            assert account.balance == account.balance.quantize(Decimal("0.01"))
    assert moved > 10  # the walk did write
