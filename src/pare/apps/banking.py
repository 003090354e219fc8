"""Banking: the user's accounts and their transactions, payees, payments and transfers, standing orders,
direct debits, cards, disputes and statements.

Money is exact: every amount is a :class:`decimal.Decimal` in whole cents (two decimal places), validated
wherever it enters (seed data, tool arguments, screen forms), and shown in results as text with two
decimals (``"1250.00"``), which checks compare as numbers. An amount leaving an account is negative on
its transaction. A payment or transfer checks everything before it changes anything: a call that fails
(an unknown payee, more than the account has available) leaves every balance and record as it was, and a
transfer's two legs are written together.

Time-driven changes: active standing orders are paid when their ``next_payment`` time comes (the
environment calls :meth:`BankingApp.pay_due_standing_orders`); direct debits are collected by the world
(:meth:`BankingApp.collect_direct_debit`), and a cancelled mandate refuses the collection.
"""

# Screen actions take the app as their second argument; the framework passes it and models never see it,
# so it is not described in their docstrings.

from __future__ import annotations

import calendar
import re
from collections.abc import Iterable, Mapping
from datetime import datetime, timedelta
from decimal import Decimal, InvalidOperation
from typing import Annotated, Any, ClassVar, Literal

from pydantic import AfterValidator, BaseModel, ConfigDict, Field, WithJsonSchema, model_validator

from pare.apps.base import App, DatedRecord
from pare.apps.done import Done
from pare.apps.files import files_of, normalize_path
from pare.apps.harm import Harm
from pare.apps.paging import Paged, showing_screen
from pare.apps.screens import BACK, Screen, Transition, action, back, back_to, push
from pare.apps.text import PAGE, short_time
from pare.apps.tools import tool
from pare.apps.types import SimTime
from pare.errors import ToolError
from pare.sim.clock import ensure_utc

# -- money ---------------------------------------------------------------------------------------------

CENT = Decimal("0.01")
LIMIT = Decimal("1000000000")
"""Amounts are below a billion: far above any story, and well inside what two-place decimals hold exactly."""


def _whole_cents(value: Decimal) -> Decimal:
    """``value`` with exactly two decimals; :class:`ValueError` for fractions of a cent or absurd sizes."""
    if not value.is_finite():
        raise ValueError(f"an amount must be a finite number (got {value})")
    if abs(value) >= LIMIT:
        raise ValueError(f"an amount must be below {LIMIT:,} (got {value})")
    try:
        cents = value.quantize(CENT)
    except InvalidOperation:  # pragma: no cover - the bound above keeps quantize inside its precision
        raise ValueError(f"{value} is not an amount of money") from None
    if cents != value:
        raise ValueError(f"{value} has fractions of a cent; amounts have at most two decimals")
    return cents


Money = Annotated[
    Decimal,
    AfterValidator(_whole_cents),
    WithJsonSchema({"type": "number", "description": "an amount of money with at most two decimals"}),
]
"""An amount in whole cents, e.g. ``12.5`` or ``"12.50"`` (stored and shown as ``12.50``)."""

ZERO = Decimal("0.00")


def fmt(amount: Decimal) -> str:
    """An amount for people: ``$1,234.50``, ``-$12.00``."""
    sign = "-" if amount < 0 else ""
    return f"{sign}${abs(amount):,.2f}"


def _positive(amount: Decimal, what: str = "amount") -> Decimal:
    """``amount`` checked as a positive amount of money; :class:`ToolError` saying what is wrong."""
    try:
        cents = _whole_cents(amount)
    except ValueError as error:
        raise ToolError(f"{what}: {error}.") from None
    if cents <= 0:
        raise ToolError(f"{what} must be above 0 (got {amount}).")
    return cents


# -- data ----------------------------------------------------------------------------------------------

AccountKind = Literal["current", "savings"]
TransactionKind = Literal[
    "card", "payment", "transfer", "standing_order", "direct_debit", "deposit", "refund", "fee", "interest"
]
Frequency = Literal["weekly", "monthly"]
MandateStatus = Literal["active", "cancelled"]
DisputeStatus = Literal["open", "refunded", "rejected"]


class Account(BaseModel):
    """One of the user's accounts."""

    model_config = ConfigDict(extra="forbid")

    account_id: str
    name: str = Field(description='what the user calls it, e.g. "Everyday" or "Savings"')
    kind: AccountKind = "current"
    number: str = Field(default="", description='the account number as the app shows it, e.g. "****4821"')
    balance: Money = Field(
        description="what the account holds, e.g. 1250.5; below 0 only within the overdraft"
    )
    overdraft_limit: Money = Field(
        default=0, validate_default=True, description="how far below zero the balance may go, >= 0"
    )

    @property
    def available(self) -> Decimal:
        """What can be paid out now: the balance and the overdraft."""
        return self.balance + self.overdraft_limit

    @model_validator(mode="after")
    def _within_overdraft(self) -> Account:
        if self.overdraft_limit < 0:
            raise ValueError(f"account '{self.account_id}': overdraft_limit cannot be negative")
        if self.available < 0:
            raise ValueError(f"account '{self.account_id}': the balance is below the overdraft limit")
        return self

    def label(self) -> str:
        """``Everyday (acc-1)``."""
        return f"{self.name} ({self.account_id})"


class Transaction(BaseModel):
    """Money in (a positive amount) or out (negative) of an account."""

    model_config = ConfigDict(extra="forbid")

    transaction_id: str
    account_id: str
    amount: Money = Field(description="positive for money in, negative for money out; never 0")
    description: str = Field(description='what the statement says, e.g. "Card payment: Corner Cafe"')
    counterparty: str = Field(default="", description="who paid or was paid, e.g. a shop or a person")
    category: str = Field(default="", description='e.g. "groceries", "rent", "salary"')
    kind: TransactionKind = "card"
    booked_at: SimTime
    reference: str = ""
    card_id: str | None = Field(default=None, description="the card used, for card payments")
    payee_id: str | None = Field(default=None, description="the payee paid, for payments and standing orders")
    related_transaction_id: str | None = Field(
        default=None, description="the other half of a transfer between the user's own accounts"
    )

    @model_validator(mode="after")
    def _not_zero(self) -> Transaction:
        if self.amount == 0:
            raise ValueError(f"transaction '{self.transaction_id}': the amount cannot be 0")
        return self


class Payee(BaseModel):
    """Someone the user pays: a person or a company, with their account details."""

    model_config = ConfigDict(extra="forbid")

    payee_id: str
    name: str
    account_number: str = Field(description='the account paid into, e.g. "GB33 BUKB 2020 1555 5555 55"')
    bank: str = ""


class StandingOrder(BaseModel):
    """A fixed amount the bank pays to a payee every week or month until cancelled (or its end)."""

    model_config = ConfigDict(extra="forbid")

    standing_order_id: str
    account_id: str = Field(description="the account it is paid from")
    payee_id: str
    amount: Money = Field(description="what each payment is, > 0")
    frequency: Frequency = "monthly"
    next_payment: SimTime = Field(description="when it is next paid; it moves on each time it is paid")
    first_payment: SimTime | None = Field(
        default=None,
        description="when its first payment was set to go, kept as set up (checks read this, since "
        "next_payment moves on as the order is paid); next_payment when left out",
    )
    day_of_month: int | None = Field(
        default=None,
        ge=1,
        le=31,
        description="for monthly orders, the day they are paid on (the next payment's day when left out); "
        "in shorter months, the month's last day",
    )
    end_date: SimTime | None = Field(default=None, description="no payment after this time; null for never")
    reference: str = ""
    status: MandateStatus = "active"
    cancelled_at: SimTime | None = None

    @model_validator(mode="after")
    def _day_of_month(self) -> StandingOrder:
        if self.first_payment is None:
            self.first_payment = self.next_payment
        if self.frequency == "monthly" and self.day_of_month is None:
            self.day_of_month = self.next_payment.day
        if self.amount <= 0:
            raise ValueError(f"standing order '{self.standing_order_id}': the amount must be above 0")
        return self


class DirectDebit(BaseModel):
    """A mandate letting a company collect what the user owes it from an account."""

    model_config = ConfigDict(extra="forbid")

    direct_debit_id: str
    account_id: str = Field(description="the account it is collected from")
    merchant: str = Field(description='who collects, e.g. "City Power & Gas"')
    reference: str = Field(default="", description="the customer or contract number the merchant gave")
    status: MandateStatus = "active"
    last_amount: Money | None = Field(default=None, description="what was last collected")
    last_collected: SimTime | None = None
    cancelled_at: SimTime | None = None


class Card(BaseModel):
    """A payment card of an account; a frozen card declines every payment until unfrozen."""

    model_config = ConfigDict(extra="forbid")

    card_id: str
    account_id: str
    name: str = "Debit card"
    last_four: str = Field(pattern=r"^\d{4}$", description='the last four digits, e.g. "4821"')
    frozen: bool = False


class Dispute(BaseModel):
    """The user's claim that a transaction is wrong (not theirs, not received, charged twice)."""

    model_config = ConfigDict(extra="forbid")

    dispute_id: str
    transaction_id: str
    reason: str
    status: DisputeStatus = "open"
    opened_at: SimTime
    resolved_at: SimTime | None = None
    outcome: str = ""


class BankingState(BaseModel):
    """Every account, transaction, payee, standing order, direct debit, card and dispute, by id."""

    model_config = ConfigDict(extra="forbid")

    accounts: dict[str, Account] = Field(default_factory=dict)
    transactions: dict[str, Transaction] = Field(default_factory=dict)
    payees: dict[str, Payee] = Field(default_factory=dict)
    standing_orders: dict[str, StandingOrder] = Field(default_factory=dict)
    direct_debits: dict[str, DirectDebit] = Field(default_factory=dict)
    cards: dict[str, Card] = Field(default_factory=dict)
    disputes: dict[str, Dispute] = Field(default_factory=dict)

    @model_validator(mode="after")
    def _consistent(self) -> BankingState:
        collections: list[tuple[str, Mapping[str, BaseModel], str]] = [
            ("account", self.accounts, "account_id"),
            ("transaction", self.transactions, "transaction_id"),
            ("payee", self.payees, "payee_id"),
            ("standing order", self.standing_orders, "standing_order_id"),
            ("direct debit", self.direct_debits, "direct_debit_id"),
            ("card", self.cards, "card_id"),
            ("dispute", self.disputes, "dispute_id"),
        ]
        for what, records, id_field in collections:
            for key, record in records.items():
                if getattr(record, id_field) != key:
                    raise ValueError(
                        f"{what} stored under '{key}' has {id_field} '{getattr(record, id_field)}'"
                    )
        owned: tuple[tuple[str, Mapping[str, Transaction | StandingOrder | DirectDebit | Card]], ...] = (
            ("transaction", self.transactions),
            ("standing order", self.standing_orders),
            ("direct debit", self.direct_debits),
            ("card", self.cards),
        )
        for what, records in owned:
            for key, record in records.items():
                account = record.account_id
                if account not in self.accounts:
                    raise ValueError(f"{what} '{key}' is of account '{account}', which is not an account")
        for key, order in self.standing_orders.items():
            if order.payee_id not in self.payees:
                raise ValueError(f"standing order '{key}' pays '{order.payee_id}', which is not a payee")
        open_disputes: set[str] = set()
        for key, dispute in self.disputes.items():
            if dispute.transaction_id not in self.transactions:
                raise ValueError(
                    f"dispute '{key}' is about '{dispute.transaction_id}', which is not a transaction"
                )
            if dispute.status == "open":
                if dispute.transaction_id in open_disputes:
                    raise ValueError(f"transaction '{dispute.transaction_id}' has two open disputes")
                open_disputes.add(dispute.transaction_id)
        return self


# -- what the tools return -------------------------------------------------------------------------------


class AccountSummary(BaseModel):
    """An account with what can be paid out of it now."""

    account_id: str
    name: str
    kind: AccountKind
    number: str
    balance: Decimal
    available: Decimal = Field(description="the balance plus the overdraft: the most a payment can be")


class TransactionPage(Paged):
    """One page of transactions, the most recent first."""

    rows_field = "transactions"

    transactions: list[Transaction]
    total: int
    offset: int


class AccountDetails(AccountSummary):
    """An account, its cards and its most recent transactions."""

    overdraft_limit: Decimal
    cards: list[Card]
    recent: TransactionPage = Field(description="its most recent transactions; list_transactions pages on")


def _summary(account: Account) -> AccountSummary:
    return AccountSummary(
        account_id=account.account_id,
        name=account.name,
        kind=account.kind,
        number=account.number,
        balance=account.balance,
        available=account.available,
    )


def _newest_first(transactions: Iterable[Transaction]) -> list[Transaction]:
    indexed = sorted(enumerate(transactions), key=lambda pair: (pair[1].booked_at, pair[0]), reverse=True)
    return [transaction for _, transaction in indexed]


def _page(rows: list[Transaction], offset: int, limit: int) -> TransactionPage:
    if offset < 0 or not 1 <= limit <= 100:
        raise ToolError("offset must be >= 0 and limit between 1 and 100.")
    return TransactionPage(transactions=rows[offset : offset + limit], total=len(rows), offset=offset)


def _add_month(moment: datetime, day: int) -> datetime:
    """The same clock time on ``day`` of the month after ``moment``'s (its last day when shorter)."""
    year, month = (moment.year + 1, 1) if moment.month == 12 else (moment.year, moment.month + 1)
    return moment.replace(year=year, month=month, day=min(day, calendar.monthrange(year, month)[1]))


_MONTH = re.compile(r"^(\d{4})-(\d{2})$")


class BankingApp(App):
    """The user's bank."""

    name = "banking"
    title = "Banking"
    description = (
        "The user's bank: accounts and balances, transactions, payees, payments and transfers, standing "
        "orders, direct debits, cards, disputes and statements."
    )
    State = BankingState
    state: BankingState
    also_writes = ("files",)
    wakeup_tool = "pay_due_standing_orders"

    harm: ClassVar[Mapping[str, Harm]] = {
        "pay_payee": "irreversible",
        "transfer_between_accounts": "irreversible",
        "add_payee": "reversible",
        "delete_payee": "costly",
        "create_standing_order": "costly",
        "cancel_standing_order": "costly",
        "set_up_direct_debit": "costly",
        "cancel_direct_debit": "costly",
        "freeze_card": "reversible",
        "unfreeze_card": "reversible",
        "dispute_transaction": "costly",
        "download_statement": "reversible",
    }
    """How bad a wrong call of each write tool is: money sent cannot be called back; a cancelled standing
    order or direct debit, or a dispute, takes the payee or the bank to put right; a freeze is one tap."""

    # -- helpers used by screens and the environment ------------------------------------------------
    def records_dated_after(self, now: datetime) -> list[DatedRecord]:
        """See :meth:`App.records_dated_after`."""
        late = [
            DatedRecord(
                ("transactions", key, "booked_at"),
                f"transaction '{key}' booked {transaction.booked_at:%Y-%m-%d %H:%M}",
            )
            for key, transaction in self.state.transactions.items()
            if transaction.booked_at > now
        ]
        late += [
            DatedRecord(
                ("disputes", key, "opened_at"), f"dispute '{key}' opened {dispute.opened_at:%Y-%m-%d %H:%M}"
            )
            for key, dispute in self.state.disputes.items()
            if dispute.opened_at > now
        ]
        return late

    def next_wakeup(self) -> datetime | None:
        """When the next active standing order is due."""
        return min(
            (o.next_payment for o in self.state.standing_orders.values() if o.status == "active"),
            default=None,
        )

    def require_account(self, account_id: str) -> Account:
        """The account with ``account_id``; :class:`ToolError` naming it otherwise."""
        account = self.state.accounts.get(account_id)
        if account is None:
            known = ", ".join(a.label() for a in self.state.accounts.values()) or "none"
            raise ToolError(f"No account with id '{account_id}'. The accounts are: {known}.")
        return account

    def require_transaction(self, transaction_id: str) -> Transaction:
        """The transaction with ``transaction_id``; :class:`ToolError` naming it otherwise."""
        transaction = self.state.transactions.get(transaction_id)
        if transaction is None:
            raise ToolError(
                f"No transaction with id '{transaction_id}'. Use search_transactions or list_transactions "
                "to find transaction ids."
            )
        return transaction

    def require_payee(self, payee_id: str) -> Payee:
        """The payee with ``payee_id``; :class:`ToolError` naming it otherwise."""
        payee = self.state.payees.get(payee_id)
        if payee is None:
            raise ToolError(f"No payee with id '{payee_id}'. Use list_payees to find payee ids.")
        return payee

    def require_standing_order(self, standing_order_id: str) -> StandingOrder:
        """The standing order with ``standing_order_id``; :class:`ToolError` naming it otherwise."""
        order = self.state.standing_orders.get(standing_order_id)
        if order is None:
            raise ToolError(
                f"No standing order with id '{standing_order_id}'. Use list_standing_orders to find ids."
            )
        return order

    def require_direct_debit(self, direct_debit_id: str) -> DirectDebit:
        """The direct debit with ``direct_debit_id``; :class:`ToolError` naming it otherwise."""
        debit = self.state.direct_debits.get(direct_debit_id)
        if debit is None:
            raise ToolError(
                f"No direct debit with id '{direct_debit_id}'. Use list_direct_debits to find ids."
            )
        return debit

    def require_card(self, card_id: str) -> Card:
        """The card with ``card_id``; :class:`ToolError` naming it otherwise."""
        card = self.state.cards.get(card_id)
        if card is None:
            raise ToolError(f"No card with id '{card_id}'. Use list_cards to find card ids.")
        return card

    def require_dispute(self, dispute_id: str) -> Dispute:
        """The dispute with ``dispute_id``; :class:`ToolError` naming it otherwise."""
        dispute = self.state.disputes.get(dispute_id)
        if dispute is None:
            raise ToolError(f"No dispute with id '{dispute_id}'. Use list_disputes to find ids.")
        return dispute

    def default_account_id(self) -> str:
        """The account money goes out of unless the user picks another: the first current account ("" when
        there is no account).
        """
        accounts = list(self.state.accounts.values())
        chosen = next((a for a in accounts if a.kind == "current"), accounts[0] if accounts else None)
        return chosen.account_id if chosen is not None else ""

    def transactions_of(self, account_id: str | None) -> list[Transaction]:
        """The transactions of one account (or of all), the most recent first."""
        chosen: Iterable[Transaction] = self.state.transactions.values()
        if account_id is not None:
            self.require_account(account_id)
            chosen = [t for t in chosen if t.account_id == account_id]
        return _newest_first(chosen)

    def check_payment(self, account: Account, amount: Decimal) -> None:
        """Raise :class:`ToolError` when ``amount`` is more than ``account`` can pay out now."""
        if amount > account.available:
            overdraft = (
                f" (with its {fmt(account.overdraft_limit)} overdraft)" if account.overdraft_limit else ""
            )
            raise ToolError(
                f"Insufficient funds: {account.label()} has {fmt(account.available)} available{overdraft}, "
                f"{fmt(amount - account.available)} less than the {fmt(amount)} asked. Nothing was paid."
            )

    def _book(
        self,
        account: Account,
        amount: Decimal,
        description: str,
        kind: TransactionKind,
        *,
        transaction_id: str | None = None,
        **fields: Any,
    ) -> Transaction:
        """Post ``amount`` to ``account`` (every check already made)."""
        new_id = transaction_id or self.new_id("txn", self.state.transactions)
        transaction = Transaction(
            transaction_id=new_id,
            account_id=account.account_id,
            amount=amount,
            description=description,
            kind=kind,
            booked_at=self.ctx.now(),
            **fields,
        )
        account.balance += amount
        self.state.transactions[new_id] = transaction
        return transaction

    def _mandates(self, records: Iterable[Any], include_cancelled: bool) -> list[Any]:
        return [r for r in records if include_cancelled or r.status == "active"]

    # -- agent API: accounts and transactions ------------------------------------------------------
    @tool("read")
    def list_accounts(self) -> list[AccountSummary]:
        """List the user's accounts with their balances.

        Returns:
            every account with its id, name, kind, number, balance and available amount (balance plus
            overdraft); [] when there is none.
        """
        return [_summary(account) for account in self.state.accounts.values()]

    @tool("read")
    def get_account(self, account_id: str) -> AccountDetails:
        """Get one account: its balance, available amount, cards and most recent transactions.

        Args:
            account_id: the account's id, e.g. "acc-everyday" (see list_accounts).

        Returns:
            the account with its cards and the first page of its transactions, the most recent first.
        """
        account = self.require_account(account_id)
        return AccountDetails(
            **_summary(account).model_dump(),
            overdraft_limit=account.overdraft_limit,
            cards=[c for c in self.state.cards.values() if c.account_id == account_id],
            recent=_page(self.transactions_of(account_id), 0, PAGE),
        )

    @tool("read")
    def list_transactions(
        self, account_id: str | None = None, offset: int = 0, limit: int = PAGE
    ) -> TransactionPage:
        """List transactions, the most recent first, a page at a time.

        Args:
            account_id: only this account's transactions; all accounts' when left out.
            offset: how many transactions to skip.
            limit: how many transactions to return (1-100).

        Returns:
            the page of transactions (amounts negative for money out) and how many there are.
        """
        return _page(self.transactions_of(account_id), offset, limit)

    @tool("read")
    def search_transactions(
        self,
        query: str = "",
        account_id: str | None = None,
        since: SimTime | None = None,
        until: SimTime | None = None,
        offset: int = 0,
        limit: int = PAGE,
    ) -> TransactionPage:
        """Search transactions by description, counterparty, category, reference or amount, and by date.

        The search is case-insensitive and every word of the query must match. It matches parts of words
        too: "Priya" finds "Priyanka". An amount is matched as written on the transaction ("42.50").

        Args:
            query: words to look for, e.g. "netflix" or "rent march"; "" to filter by dates only.
            account_id: only this account's transactions; all accounts' when left out.
            since: only transactions booked at or after this time, e.g. "2025-03-01 00:00".
            until: only transactions booked before this time.
            offset: how many matches to skip.
            limit: how many matches to return (1-100).

        Returns:
            the page of matching transactions, the most recent first, and how many match; none matching
            is an empty page.
        """
        words = query.lower().split()
        if not words and since is None and until is None:
            raise ToolError("Give words to search for, or a time range (since, until).")
        start = ensure_utc(since) if since is not None else None
        end = ensure_utc(until) if until is not None else None
        found = []
        for transaction in self.transactions_of(account_id):
            if start is not None and transaction.booked_at < start:
                continue
            if end is not None and transaction.booked_at >= end:
                continue
            haystack = " ".join(
                [
                    transaction.description,
                    transaction.counterparty,
                    transaction.category,
                    transaction.reference,
                    transaction.kind.replace("_", " "),
                    f"{abs(transaction.amount)}",
                ]
            ).lower()
            if all(word in haystack for word in words):
                found.append(transaction)
        return _page(found, offset, limit)

    @tool("read")
    def get_transaction(self, transaction_id: str) -> Transaction:
        """Get one transaction in full.

        Args:
            transaction_id: the transaction's id, e.g. "txn-12".

        Returns:
            the transaction.
        """
        return self.require_transaction(transaction_id)

    # -- agent API: payees, payments and transfers ----------------------------------------------------
    @tool("read")
    def list_payees(self) -> list[Payee]:
        """List the payees the user can pay, by name.

        Returns:
            every payee with its id, name, account number and bank; [] when there is none.
        """
        return sorted(self.state.payees.values(), key=lambda p: (p.name.lower(), p.payee_id))

    @tool("write")
    def add_payee(self, name: str, account_number: str, bank: str = "") -> Done:
        """Add a payee, so that they can be paid.

        Args:
            name: the person or company, e.g. "Jo Park".
            account_number: the account to pay into, as they gave it.
            bank: their bank, if known.

        Returns:
            who was added, and the new payee's id.
        """
        clean_name, number = name.strip(), " ".join(account_number.split())
        if not clean_name or not number:
            raise ToolError("A payee needs a name and an account number.")
        for payee in self.state.payees.values():
            if payee.account_number.replace(" ", "") == number.replace(" ", ""):
                raise ToolError(
                    f"{payee.name} ({payee.payee_id}) already has account number {payee.account_number}."
                )
        payee_id = self.new_id("payee", self.state.payees)
        self.state.payees[payee_id] = Payee(
            payee_id=payee_id, name=clean_name, account_number=number, bank=bank.strip()
        )
        return Done(done=f"Added payee {clean_name} ({number}) as {payee_id}.", id=payee_id)

    @tool("write")
    def delete_payee(self, payee_id: str) -> str:
        """Delete a payee. A payee that an active standing order pays cannot be deleted.

        Args:
            payee_id: the payee to delete.

        Returns:
            what was deleted.
        """
        payee = self.require_payee(payee_id)
        paying = [o.standing_order_id for o in self.state.standing_orders.values() if o.payee_id == payee_id]
        active = [i for i in paying if self.state.standing_orders[i].status == "active"]
        if active:
            raise ToolError(
                f"{payee.name} is paid by the active standing order(s) {', '.join(active)}; cancel them "
                "first."
            )
        if paying:
            raise ToolError(
                f"{payee.name} is named by the standing order(s) {', '.join(paying)} in the records, so it "
                "is kept."
            )
        del self.state.payees[payee_id]
        return f"Deleted payee {payee_id} ({payee.name})."

    @tool("write")
    def pay_payee(self, payee_id: str, amount: Money, from_account_id: str, reference: str = "") -> Done:
        """Pay money to a payee now. It cannot be called back once sent.

        Args:
            payee_id: who to pay (see list_payees).
            amount: how much, above 0, at most two decimals, e.g. 42.5.
            from_account_id: the account to pay from (see list_accounts); it must have the amount available.
            reference: what the payee sees, e.g. "Rent March" or an invoice number.

        Returns:
            what was paid to whom from where, and the payment's transaction id.
        """
        payee = self.require_payee(payee_id)
        account = self.require_account(from_account_id)
        cents = _positive(amount)
        self.check_payment(account, cents)
        text = reference.strip()
        transaction = self._book(
            account,
            -cents,
            f"Payment to {payee.name}" + (f": {text}" if text else ""),
            "payment",
            counterparty=payee.name,
            payee_id=payee_id,
            reference=text,
        )
        return Done(
            done=f"Paid {fmt(cents)} to {payee.name} from {account.label()}"
            + (f", reference '{text}'" if text else "")
            + f". Balance now {fmt(account.balance)}.",
            id=transaction.transaction_id,
        )

    @tool("write")
    def transfer_between_accounts(
        self, from_account_id: str, to_account_id: str, amount: Money, reference: str = ""
    ) -> Done:
        """Move money between two of the user's own accounts, at once.

        Args:
            from_account_id: the account the money leaves; it must have the amount available.
            to_account_id: the account it goes to.
            amount: how much, above 0, at most two decimals.
            reference: a note on both transactions, e.g. "Holiday savings".

        Returns:
            what moved where, and the id of the transaction on the account the money left.
        """
        source = self.require_account(from_account_id)
        target = self.require_account(to_account_id)
        if source.account_id == target.account_id:
            raise ToolError("The two accounts are the same; choose another account to transfer to.")
        cents = _positive(amount)
        self.check_payment(source, cents)
        text = reference.strip()
        out_id = self.new_id("txn", self.state.transactions)
        in_id = self.new_id("txn", {*self.state.transactions, out_id})
        self._book(
            source,
            -cents,
            f"Transfer to {target.name}",
            "transfer",
            transaction_id=out_id,
            counterparty=target.name,
            reference=text,
            related_transaction_id=in_id,
        )
        self._book(
            target,
            cents,
            f"Transfer from {source.name}",
            "transfer",
            transaction_id=in_id,
            counterparty=source.name,
            reference=text,
            related_transaction_id=out_id,
        )
        return Done(
            done=f"Moved {fmt(cents)} from {source.label()} to {target.label()}. Balances now "
            f"{fmt(source.balance)} and {fmt(target.balance)}.",
            id=out_id,
        )

    # -- agent API: standing orders and direct debits -----------------------------------------------
    @tool("read")
    def list_standing_orders(self, include_cancelled: bool = False) -> list[StandingOrder]:
        """List standing orders, the next due first.

        Args:
            include_cancelled: also list cancelled ones.

        Returns:
            the standing orders with their payee, amount, frequency and next payment; [] when there is none.
        """
        orders = self._mandates(self.state.standing_orders.values(), include_cancelled)
        return sorted(orders, key=lambda o: (o.status != "active", o.next_payment, o.standing_order_id))

    @tool("write")
    def create_standing_order(
        self,
        payee_id: str,
        amount: Money,
        first_payment: SimTime,
        from_account_id: str,
        frequency: Frequency = "monthly",
        reference: str = "",
        end_date: SimTime | None = None,
    ) -> Done:
        """Set up a standing order: a fixed amount paid to a payee every week or month, from a date.

        Args:
            payee_id: who to pay (see list_payees).
            amount: each payment, above 0, at most two decimals.
            first_payment: when the first payment goes, e.g. "2025-04-01 09:00"; not in the past. Monthly
                orders are then paid on that day of each month.
            from_account_id: the account to pay from.
            frequency: "weekly" or "monthly".
            reference: what the payee sees, e.g. "Rent flat 4B".
            end_date: no payment after this time; leave out for no end.

        Returns:
            what was set up, and the new standing order's id.
        """
        payee = self.require_payee(payee_id)
        account = self.require_account(from_account_id)
        cents = _positive(amount)
        first = ensure_utc(first_payment)
        now = self.ctx.now()
        if first < now:
            raise ToolError(
                f"first_payment {first:%Y-%m-%d %H:%M} is in the past (it is now {now:%Y-%m-%d %H:%M})."
            )
        end = ensure_utc(end_date) if end_date is not None else None
        if end is not None and end < first:
            raise ToolError(f"end_date {end:%Y-%m-%d %H:%M} is before the first payment.")
        order_id = self.new_id("so", self.state.standing_orders)
        self.state.standing_orders[order_id] = StandingOrder(
            standing_order_id=order_id,
            account_id=account.account_id,
            payee_id=payee_id,
            amount=cents,
            frequency=frequency,
            next_payment=first,
            first_payment=first,
            end_date=end,
            reference=reference.strip(),
        )
        return Done(
            done=f"Set up a {frequency} standing order of {fmt(cents)} to {payee.name} from "
            f"{account.label()}, first paid {first:%Y-%m-%d %H:%M}.",
            id=order_id,
        )

    @tool("write")
    def cancel_standing_order(self, standing_order_id: str) -> StandingOrder:
        """Cancel a standing order: no further payment is made.

        Args:
            standing_order_id: the standing order to cancel (see list_standing_orders).

        Returns:
            the standing order, now cancelled.
        """
        order = self.require_standing_order(standing_order_id)
        if order.status == "cancelled":
            raise ToolError(f"Standing order {standing_order_id} is already cancelled.")
        order.status = "cancelled"
        order.cancelled_at = self.ctx.now()
        return order

    @tool("read")
    def list_direct_debits(self, include_cancelled: bool = False) -> list[DirectDebit]:
        """List direct debits: the companies allowed to collect from the user's accounts.

        Args:
            include_cancelled: also list cancelled ones.

        Returns:
            the direct debits with who collects, the reference and what was last collected; [] when there
            is none.
        """
        debits = self._mandates(self.state.direct_debits.values(), include_cancelled)
        return sorted(debits, key=lambda d: (d.status != "active", d.merchant.lower(), d.direct_debit_id))

    @tool("write")
    def set_up_direct_debit(self, merchant: str, reference: str, account_id: str) -> Done:
        """Allow a company to collect what the user owes it from an account (a direct debit mandate).

        Args:
            merchant: who will collect, e.g. "City Power & Gas".
            reference: the customer or contract number they gave, e.g. "CPG-558120".
            account_id: the account they collect from.

        Returns:
            what was set up, and the new direct debit's id.
        """
        account = self.require_account(account_id)
        who, ref = merchant.strip(), reference.strip()
        if not who:
            raise ToolError("A direct debit needs the merchant who collects.")
        for debit in self.state.direct_debits.values():
            same = debit.merchant.casefold() == who.casefold() and debit.reference == ref
            if same and debit.status == "active":
                raise ToolError(
                    f"{debit.merchant} already has an active direct debit ({debit.direct_debit_id})."
                )
        debit_id = self.new_id("dd", self.state.direct_debits)
        self.state.direct_debits[debit_id] = DirectDebit(
            direct_debit_id=debit_id, account_id=account.account_id, merchant=who, reference=ref
        )
        return Done(done=f"Set up a direct debit for {who} on {account.label()}.", id=debit_id)

    @tool("write")
    def cancel_direct_debit(self, direct_debit_id: str) -> DirectDebit:
        """Cancel a direct debit: the company can no longer collect from the account.

        Args:
            direct_debit_id: the direct debit to cancel (see list_direct_debits).

        Returns:
            the direct debit, now cancelled.
        """
        debit = self.require_direct_debit(direct_debit_id)
        if debit.status == "cancelled":
            raise ToolError(f"Direct debit {direct_debit_id} is already cancelled.")
        debit.status = "cancelled"
        debit.cancelled_at = self.ctx.now()
        return debit

    # -- agent API: cards, disputes, statements ------------------------------------------------------
    @tool("read")
    def list_cards(self) -> list[Card]:
        """List the user's cards and whether each is frozen.

        Returns:
            every card with its id, account, last four digits and frozen state; [] when there is none.
        """
        return list(self.state.cards.values())

    @tool("write")
    def freeze_card(self, card_id: str) -> Card:
        """Freeze a card: every payment with it is declined until it is unfrozen.

        Args:
            card_id: the card (see list_cards).

        Returns:
            the card, now frozen.
        """
        card = self.require_card(card_id)
        if card.frozen:
            raise ToolError(f"Card {card_id} (ending {card.last_four}) is already frozen.")
        card.frozen = True
        return card

    @tool("write")
    def unfreeze_card(self, card_id: str) -> Card:
        """Unfreeze a frozen card, so that it can pay again.

        Args:
            card_id: the card (see list_cards).

        Returns:
            the card, no longer frozen.
        """
        card = self.require_card(card_id)
        if not card.frozen:
            raise ToolError(f"Card {card_id} (ending {card.last_four}) is not frozen.")
        card.frozen = False
        return card

    @tool("read")
    def list_disputes(self) -> list[Dispute]:
        """List the user's disputes of transactions, the most recent first.

        Returns:
            every dispute with its transaction, reason and status (open, refunded, rejected); [] when
            there is none.
        """
        return sorted(self.state.disputes.values(), key=lambda d: (d.opened_at, d.dispute_id), reverse=True)

    @tool("write")
    def dispute_transaction(self, transaction_id: str, reason: str) -> Done:
        """Dispute a payment out of an account that is wrong: not made by the user, charged twice, or paid
        for something never received. The bank looks into it; a refund comes if it agrees.

        Args:
            transaction_id: the transaction to dispute (money out).
            reason: what is wrong, e.g. "I did not make this payment; my card was in my wallet".

        Returns:
            what was disputed, and the new dispute's id.
        """
        transaction = self.require_transaction(transaction_id)
        why = reason.strip()
        if not why:
            raise ToolError("Say what is wrong with the transaction (reason).")
        if transaction.amount > 0:
            raise ToolError(
                f"Transaction {transaction_id} is money in ({fmt(transaction.amount)}); only payments out "
                "can be disputed."
            )
        for dispute in self.state.disputes.values():
            if dispute.transaction_id == transaction_id and dispute.status == "open":
                raise ToolError(
                    f"Transaction {transaction_id} is already disputed ({dispute.dispute_id}, open)."
                )
        dispute_id = self.new_id("dispute", self.state.disputes)
        self.state.disputes[dispute_id] = Dispute(
            dispute_id=dispute_id, transaction_id=transaction_id, reason=why, opened_at=self.ctx.now()
        )
        return Done(
            done=f"Disputed {transaction_id} ({transaction.description}, {fmt(transaction.amount)}) as "
            f"{dispute_id}.",
            id=dispute_id,
        )

    @tool("write")
    def download_statement(
        self, account_id: str, month: str, directory: str = "/Documents/Statements"
    ) -> Done:
        """Save an account's statement for a month as a text file in the Files app.

        Args:
            account_id: the account.
            month: the month, "YYYY-MM", e.g. "2025-02"; the current month gives the statement so far.
            directory: the folder to save it in.

        Returns:
            what was saved, and the file's path as its id.
        """
        account = self.require_account(account_id)
        matched = _MONTH.match(month.strip())
        if matched is None or not 1 <= int(matched.group(2)) <= 12:
            raise ToolError(f"month must be written YYYY-MM, e.g. '2025-02' (got {month!r}).")
        year, number = int(matched.group(1)), int(matched.group(2))
        now = self.ctx.now()
        if (year, number) > (now.year, now.month):
            raise ToolError(f"{month.strip()} has not started yet; it is now {now:%Y-%m}.")
        if year < 1900:
            raise ToolError(f"There is no statement for {month.strip()}.")
        start = now.replace(year=year, month=number, day=1, hour=0, minute=0, second=0, microsecond=0)
        end = _add_month(start, 1)
        files = files_of(self)
        path = normalize_path(f"{directory}/statement_{account.account_id}_{year:04d}-{number:02d}.txt")
        files.check_can_store(path)
        content = self._statement(account, start, end)
        files.store(path, content)
        return Done(done=f"Saved the {start:%B %Y} statement of {account.label()} at {path}.", id=path)

    def _statement(self, account: Account, start: datetime, end: datetime) -> str:
        """The statement text: opening balance, the month's transactions oldest first, closing balance."""
        mine = self.transactions_of(account.account_id)
        later = sum((t.amount for t in mine if t.booked_at >= end), ZERO)
        month = [t for t in reversed(mine) if start <= t.booked_at < end]
        closing = account.balance - later
        opening = closing - sum((t.amount for t in month), ZERO)
        lines = [
            f"Statement: {account.name} {account.number}".rstrip(),
            f"Period: {start:%Y-%m-%d} to {(end - timedelta(days=1)):%Y-%m-%d}",
            f"Opening balance: {fmt(opening)}",
            "",
        ]
        lines += [
            f"{t.booked_at:%Y-%m-%d}  {t.transaction_id}  {t.description}  {fmt(t.amount)}" for t in month
        ] or ["No transactions."]
        money_in = sum((t.amount for t in month if t.amount > 0), ZERO)
        money_out = sum((t.amount for t in month if t.amount < 0), ZERO)
        lines += [
            "",
            f"Money in: {fmt(money_in)}",
            f"Money out: {fmt(-money_out)}",
            f"Closing balance: {fmt(closing)}",
        ]
        return "\n".join(lines) + "\n"

    # -- the world -----------------------------------------------------------------------------------
    @tool("env", actors=())
    def receive_transaction(
        self,
        account_id: str,
        amount: Money,
        description: str,
        counterparty: str = "",
        kind: TransactionKind = "card",
        category: str = "",
        card_id: str | None = None,
        transaction_id: str | None = None,
    ) -> Transaction | str:
        """Book a transaction made outside the app: money arriving (a salary, a friend paying back) or a
        card payment at a shop. The user is notified. A card payment with a frozen card, or one above what
        the account has available, is declined (the user is told) and nothing is booked.

        Args:
            account_id: the account.
            amount: positive for money in, negative for money out.
            description: what the statement says, e.g. "Card payment: Corner Cafe".
            counterparty: who paid or was paid.
            kind: what it is, e.g. "card", "deposit", "refund", "fee".
            category: e.g. "groceries".
            card_id: the card used, for card payments.
            transaction_id: the id to give it (scenarios refer to it); a new id when left out.

        Returns:
            the booked transaction, or a sentence saying it was declined.
        """
        account = self.require_account(account_id)
        if amount == 0:
            raise ToolError("amount cannot be 0.")
        card = self.require_card(card_id) if card_id is not None else None
        if card is not None and card.account_id != account_id:
            raise ToolError(f"Card {card.card_id} belongs to account {card.account_id}, not {account_id}.")
        if transaction_id is not None and transaction_id in self.state.transactions:
            raise ToolError(f"A transaction with id '{transaction_id}' already exists.")
        who = counterparty.strip() or description.strip()
        if card is not None and card.frozen:
            self.notify(
                "card_declined",
                f"Declined: {fmt(abs(amount))} at {who}",
                body=f"Your {card.name} ending {card.last_four} is frozen, so the payment was declined.",
                data={"card_id": card.card_id, "amount": str(amount)},
            )
            return f"Declined: card {card.card_id} is frozen; nothing was booked."
        if amount < 0 and -amount > account.available:
            self.notify(
                "card_declined" if card is not None else "payment_refused",
                f"Declined: {fmt(-amount)} at {who}",
                body=f"{account.name} has only {fmt(account.available)} available.",
                data={"account_id": account_id, "amount": str(amount)},
            )
            return (
                f"Declined: {account.label()} has only {fmt(account.available)} available; nothing was "
                "booked."
            )
        transaction = self._book(
            account,
            amount,
            description.strip(),
            kind,
            transaction_id=transaction_id,
            counterparty=counterparty.strip(),
            category=category.strip(),
            card_id=card_id,
        )
        headline = f"{fmt(amount)} from {who}" if amount > 0 else f"{fmt(-amount)} paid to {who}"
        self.notify(
            "transaction",
            headline,
            body=f"{transaction.description} on {account.name}: {fmt(amount)}. "
            f"Balance {fmt(account.balance)}.",
            data={"transaction_id": transaction.transaction_id, "account_id": account_id},
        )
        return transaction

    @tool("env", actors=())
    def collect_direct_debit(
        self, direct_debit_id: str, amount: Money, description: str = "", transaction_id: str | None = None
    ) -> Transaction | str:
        """The company of a direct debit collects an amount. The user is notified. A cancelled direct debit,
        or too little money available, refuses the collection and nothing is booked.

        Args:
            direct_debit_id: the direct debit.
            amount: what is collected, above 0.
            description: what the statement says; "Direct debit: <merchant>" when left out.
            transaction_id: the id to give the transaction; a new id when left out.

        Returns:
            the booked transaction, or a sentence saying why the collection was refused.
        """
        debit = self.require_direct_debit(direct_debit_id)
        cents = _positive(amount)
        if transaction_id is not None and transaction_id in self.state.transactions:
            raise ToolError(f"A transaction with id '{transaction_id}' already exists.")
        account = self.require_account(debit.account_id)
        if debit.status == "cancelled":
            self.notify(
                "direct_debit_refused",
                f"Refused a {fmt(cents)} collection by {debit.merchant}",
                body="The direct debit was cancelled, so the collection was refused.",
                data={"direct_debit_id": direct_debit_id},
            )
            return f"Refused: direct debit {direct_debit_id} is cancelled; nothing was collected."
        if cents > account.available:
            self.notify(
                "direct_debit_refused",
                f"Refused a {fmt(cents)} collection by {debit.merchant}",
                body=f"{account.name} has only {fmt(account.available)} available.",
                data={"direct_debit_id": direct_debit_id},
            )
            return f"Refused: {account.label()} has only {fmt(account.available)} available."
        transaction = self._book(
            account,
            -cents,
            description.strip() or f"Direct debit: {debit.merchant}",
            "direct_debit",
            transaction_id=transaction_id,
            counterparty=debit.merchant,
            reference=debit.reference,
        )
        debit.last_amount, debit.last_collected = cents, self.ctx.now()
        self.notify(
            "transaction",
            f"{fmt(cents)} collected by {debit.merchant}",
            body=f"Direct debit from {account.name}. Balance {fmt(account.balance)}.",
            data={"transaction_id": transaction.transaction_id, "direct_debit_id": direct_debit_id},
        )
        return transaction

    @tool("env", actors=())
    def resolve_dispute(self, dispute_id: str, refund: bool, outcome: str = "") -> Dispute:
        """The bank decides an open dispute: refunds the amount to the account, or rejects the claim. The
        user is notified.

        Args:
            dispute_id: the dispute.
            refund: true to refund the transaction's amount, false to reject the dispute.
            outcome: what the bank says, e.g. "The merchant agreed the charge was a duplicate."

        Returns:
            the dispute as it is now.
        """
        dispute = self.require_dispute(dispute_id)
        if dispute.status != "open":
            raise ToolError(f"Dispute {dispute_id} is already {dispute.status}.")
        transaction = self.require_transaction(dispute.transaction_id)
        if refund:
            account = self.require_account(transaction.account_id)
            self._book(
                account,
                -transaction.amount,
                f"Refund: {transaction.description}",
                "refund",
                counterparty=transaction.counterparty,
                related_transaction_id=transaction.transaction_id,
            )
        dispute.status = "refunded" if refund else "rejected"
        dispute.resolved_at = self.ctx.now()
        dispute.outcome = outcome.strip()
        self.notify(
            "dispute",
            f"Dispute {'refunded' if refund else 'rejected'}: {transaction.description}",
            body=dispute.outcome
            or ("The amount is back in your account." if refund else "The charge stands."),
            data={"dispute_id": dispute_id},
        )
        return dispute

    @tool("env", actors=())
    def pay_due_standing_orders(self) -> list[str]:
        """Pay every active standing order whose next payment has come, and move it to its next date.

        A payment the account cannot cover is skipped (the user is told); an order past its end date is
        finished.

        Returns:
            one line per standing order handled.
        """
        now = self.ctx.now()
        done: list[str] = []
        for order in list(self.state.standing_orders.values()):
            while order.status == "active" and order.next_payment <= now:
                payee = self.state.payees.get(order.payee_id)
                account = self.state.accounts[order.account_id]
                name = payee.name if payee is not None else order.payee_id
                if order.end_date is not None and order.next_payment > order.end_date:
                    order.status = "cancelled"
                    order.cancelled_at = now
                    done.append(f"{order.standing_order_id} ended.")
                    break
                if order.amount <= account.available:
                    self._book(
                        account,
                        -order.amount,
                        f"Standing order to {name}" + (f": {order.reference}" if order.reference else ""),
                        "standing_order",
                        counterparty=name,
                        payee_id=order.payee_id,
                        reference=order.reference,
                    )
                    done.append(f"{order.standing_order_id}: paid {fmt(order.amount)} to {name}.")
                else:
                    self.notify(
                        "standing_order_failed",
                        f"Standing order to {name} not paid",
                        body=f"{account.name} had {fmt(account.available)} available; "
                        f"{fmt(order.amount)} was due.",
                        data={"standing_order_id": order.standing_order_id},
                    )
                    done.append(f"{order.standing_order_id}: not paid, insufficient funds.")
                if order.frequency == "weekly":
                    order.next_payment = order.next_payment + timedelta(days=7)
                else:
                    order.next_payment = _add_month(
                        order.next_payment, order.day_of_month or order.next_payment.day
                    )
        return done


# -- screens -----------------------------------------------------------------------------------------


def _transaction_row(transaction: Transaction) -> dict[str, Any]:
    """A transaction as a list shows it: id, when, what, how much."""
    return {
        "transaction_id": transaction.transaction_id,
        "booked": short_time(transaction.booked_at),
        "description": transaction.description,
        "amount": transaction.amount,
    }


class BankHome(Screen):
    """The accounts at a glance; the way to payments, payees, standing orders, direct debits and cards."""

    name = "Home"
    title = "Your accounts"

    def display(self, app: BankingApp) -> dict[str, Any]:
        """Every account with its balance and available amount, and how many disputes are open."""
        return {
            "accounts": [summary.model_dump() for summary in app.list_accounts()][:PAGE],
            "frozen_cards": [c.card_id for c in app.state.cards.values() if c.frozen][:PAGE],
            "open_disputes": sum(d.status == "open" for d in app.state.disputes.values()),
        }

    @action("Account")
    def open_account(self, app: BankingApp, account_id: str) -> Transition:
        """Open an account with its transactions.

        Args:
            account_id: the account's id.
        """
        return push(AccountScreen(account_id=account_id), app.get_account(account_id))

    @action(kind="read")
    def search_transactions(self, app: BankingApp, query: str) -> TransactionPage:
        """Search every account's transactions by description, who was paid, category or amount. It matches
        parts of words too: "Priya" finds "Priyanka".

        Args:
            query: what to look for, e.g. "netflix".
        """
        return app.search_transactions(query=query)

    @action(kind="read")
    def list_disputes(self, app: BankingApp) -> list[Dispute]:
        """Show your disputes and where they stand."""
        return app.list_disputes()

    @action("Payees")
    def open_payees(self, app: BankingApp) -> Transition:
        """Open your payees, to pay one or add one."""
        return push(PayeesScreen(), app.list_payees())

    @action("Pay")
    def move_money(self, app: BankingApp) -> Transition:
        """Start a payment or a transfer between your own accounts."""
        form = PayScreen(from_account_id=app.default_account_id() or None)
        return push(form, form.draft(app))

    @action("StandingOrders")
    def open_standing_orders(self, app: BankingApp) -> Transition:
        """Open your standing orders."""
        return push(StandingOrdersScreen(), app.list_standing_orders())

    @action("DirectDebits")
    def open_direct_debits(self, app: BankingApp) -> Transition:
        """Open your direct debits."""
        return push(DirectDebitsScreen(), app.list_direct_debits())

    @action("Cards")
    def open_cards(self, app: BankingApp) -> Transition:
        """Open your cards, to freeze or unfreeze one."""
        return push(CardsScreen(), app.list_cards())


class AccountScreen(Screen):
    """One account: balance and transactions."""

    name = "Account"
    title = "Account"
    account_id: str

    def display(self, app: BankingApp) -> dict[str, Any] | str:
        """The account's balance and available amount, and its most recent transactions."""
        account = app.state.accounts.get(self.account_id)
        if account is None:
            return f"Account {self.account_id} no longer exists."
        rows = app.transactions_of(self.account_id)
        return {
            **_summary(account).model_dump(),
            "total_transactions": len(rows),
            "transactions": [_transaction_row(t) for t in rows[:PAGE]],
            **showing_screen(rows[:PAGE], len(rows), "list_transactions(offset={offset})"),
        }

    @action(kind="read")
    def list_transactions(self, app: BankingApp, offset: int = 0, limit: int = PAGE) -> TransactionPage:
        """Show a page of this account's transactions, the most recent first.

        Args:
            offset: how many transactions to skip.
            limit: how many to show (1-100).
        """
        return app.list_transactions(account_id=self.account_id, offset=offset, limit=limit)

    @action(kind="read")
    def search_transactions(self, app: BankingApp, query: str) -> TransactionPage:
        """Search this account's transactions.

        Args:
            query: what to look for, e.g. "rent".
        """
        return app.search_transactions(query=query, account_id=self.account_id)

    @action("Transaction")
    def open_transaction(self, app: BankingApp, transaction_id: str) -> Transition:
        """Open a transaction.

        Args:
            transaction_id: the transaction's id.
        """
        transaction = app.require_transaction(transaction_id)
        return push(TransactionScreen(transaction_id=transaction_id), transaction)

    @action(kind="write")
    def download_statement(self, app: BankingApp, month: str) -> Done:
        """Save this account's statement for a month in your files (/Documents/Statements).

        Args:
            month: the month, "YYYY-MM".
        """
        return app.download_statement(self.account_id, month)


class TransactionScreen(Screen):
    """One transaction, with the way to dispute it."""

    name = "Transaction"
    title = "Transaction"
    transaction_id: str

    def display(self, app: BankingApp) -> dict[str, Any] | str:
        """The transaction in full, and its dispute if there is one."""
        transaction = app.state.transactions.get(self.transaction_id)
        if transaction is None:
            return f"Transaction {self.transaction_id} no longer exists."
        disputes = [d for d in app.state.disputes.values() if d.transaction_id == self.transaction_id]
        return {
            **transaction.model_dump(mode="json"),
            "disputes": [d.model_dump(mode="json") for d in disputes],
        }

    @action(kind="read")
    def view_transaction(self, app: BankingApp) -> Transaction:
        """Show this transaction in full."""
        return app.require_transaction(self.transaction_id)

    @action(kind="write")
    def dispute(self, app: BankingApp, reason: str) -> Done:
        """Dispute this payment: tell the bank it is wrong and why.

        Args:
            reason: what is wrong, e.g. "I did not make this payment".
        """
        return app.dispute_transaction(self.transaction_id, reason)


class PayeesScreen(Screen):
    """The people and companies the user pays."""

    name = "Payees"
    title = "Payees"

    def display(self, app: BankingApp) -> dict[str, Any]:
        """The first payees by name, with their ids and account numbers."""
        payees = app.list_payees()
        return {
            "total": len(payees),
            "payees": [p.model_dump() for p in payees[:PAGE]],
            **showing_screen(payees[:PAGE], len(payees), "list_payees()"),
        }

    @action(kind="read")
    def list_payees(self, app: BankingApp) -> list[Payee]:
        """Show every payee."""
        return app.list_payees()

    @action("Pay")
    def pay(self, app: BankingApp, payee_id: str) -> Transition:
        """Start a payment to a payee.

        Args:
            payee_id: the payee's id.
        """
        app.require_payee(payee_id)
        form = PayScreen(payee_id=payee_id, from_account_id=app.default_account_id() or None)
        return push(form, form.draft(app))

    @action(kind="write")
    def add_payee(self, app: BankingApp, name: str, account_number: str, bank: str = "") -> Done:
        """Add a payee.

        Args:
            name: the person or company.
            account_number: their account number.
            bank: their bank.
        """
        return app.add_payee(name, account_number, bank)

    @action(kind="write")
    def delete_payee(self, app: BankingApp, payee_id: str) -> str:
        """Delete a payee.

        Args:
            payee_id: the payee's id.
        """
        return app.delete_payee(payee_id)


class PayScreen(Screen):
    """A payment or a transfer being filled in: where from, to whom, how much. Nothing is sent from here;
    ``review`` shows it for confirmation.
    """

    name = "Pay"
    title = "Pay or transfer"
    payee_id: str | None = None
    to_account_id: str | None = None
    from_account_id: str | None = None
    amount: Money | None = None
    reference: str = ""

    def draft(self, app: BankingApp) -> dict[str, Any]:
        """The form as it stands, with the names of the payee and the accounts."""
        shown: dict[str, Any] = self.model_dump(mode="json")
        payee = app.state.payees.get(self.payee_id or "")
        if payee is not None:
            shown["to"] = f"{payee.name} ({payee.account_number})"
        target = app.state.accounts.get(self.to_account_id or "")
        if target is not None:
            shown["to"] = f"your {target.name} account"
        source = app.state.accounts.get(self.from_account_id or "")
        if source is not None:
            shown["from"] = f"{source.name}: {fmt(source.available)} available"
        return shown

    def display(self, app: BankingApp) -> dict[str, Any]:
        """The payment as filled in so far."""
        return self.draft(app)

    @action()
    def set_payee(self, app: BankingApp, payee_id: str) -> dict[str, Any]:
        """Pay this payee (instead of one of your accounts).

        Args:
            payee_id: the payee's id.
        """
        app.require_payee(payee_id)
        self.payee_id, self.to_account_id = payee_id, None
        return self.draft(app)

    @action()
    def set_to_account(self, app: BankingApp, account_id: str) -> dict[str, Any]:
        """Transfer to one of your own accounts (instead of a payee).

        Args:
            account_id: the account to transfer to.
        """
        app.require_account(account_id)
        self.to_account_id, self.payee_id = account_id, None
        return self.draft(app)

    @action()
    def set_from_account(self, app: BankingApp, account_id: str) -> dict[str, Any]:
        """Pay from this account.

        Args:
            account_id: the account the money leaves.
        """
        app.require_account(account_id)
        self.from_account_id = account_id
        return self.draft(app)

    @action()
    def set_amount(self, app: BankingApp, amount: Money) -> dict[str, Any]:
        """Set how much to send.

        Args:
            amount: the amount, above 0, at most two decimals.
        """
        self.amount = _positive(amount)
        return self.draft(app)

    @action()
    def set_reference(self, app: BankingApp, reference: str) -> dict[str, Any]:
        """Set what the payee sees with the payment.

        Args:
            reference: e.g. "Rent March".
        """
        self.reference = reference.strip()
        return self.draft(app)

    @action("Review")
    def review(self, app: BankingApp) -> Transition:
        """Check the payment before sending it: who gets what from where, and what is left after."""
        missing = [
            what
            for what, value in (
                ("who to pay (set_payee or set_to_account)", self.payee_id or self.to_account_id),
                ("the account to pay from (set_from_account)", self.from_account_id),
                ("the amount (set_amount)", self.amount),
            )
            if value is None
        ]
        if missing or self.from_account_id is None or self.amount is None:
            raise ToolError(f"The payment is missing {', '.join(missing)}.")
        source = app.require_account(self.from_account_id)
        if self.to_account_id == self.from_account_id:
            raise ToolError("The two accounts are the same; choose another account to transfer to.")
        if self.payee_id is not None:
            app.require_payee(self.payee_id)
        if self.to_account_id is not None:
            app.require_account(self.to_account_id)
        app.check_payment(source, self.amount)
        screen = ReviewScreen(
            payee_id=self.payee_id,
            to_account_id=self.to_account_id,
            from_account_id=self.from_account_id,
            amount=self.amount,
            reference=self.reference,
        )
        return push(screen, screen.summary(app))

    @action(BACK)
    def discard(self, app: BankingApp) -> Transition:
        """Abandon this payment; nothing is sent."""
        return back("Payment discarded; nothing was sent.")


class ReviewScreen(Screen):
    """A payment or transfer shown in full for the user to confirm: nothing moves until ``confirm``."""

    name = "Review"
    title = "Review and confirm"
    payee_id: str | None = None
    to_account_id: str | None = None
    from_account_id: str
    amount: Money
    reference: str = ""

    def summary(self, app: BankingApp) -> dict[str, Any] | str:
        """Who gets what from where, and what the account keeps after."""
        source = app.state.accounts.get(self.from_account_id)
        if source is None:
            return f"Account {self.from_account_id} no longer exists."
        payee = app.state.payees.get(self.payee_id or "")
        target = app.state.accounts.get(self.to_account_id or "")
        if payee is not None:
            to = f"{payee.name} ({payee.account_number})"
        elif target is not None:
            to = f"your {target.name} account ({target.account_id})"
        else:
            to = f"{self.payee_id or self.to_account_id}, which no longer exists"
        return {
            "pay": fmt(self.amount),
            "to": to,
            "from": source.label(),
            "reference": self.reference,
            "balance_after": fmt(source.balance - self.amount),
            "confirm": "confirm sends it; go_back changes it",
        }

    def display(self, app: BankingApp) -> dict[str, Any] | str:
        """The payment to confirm: amount, recipient, account, reference and the balance after."""
        return self.summary(app)

    @action("Home", kind="write")
    def confirm(self, app: BankingApp) -> Transition:
        """Send this payment now. It cannot be called back."""
        if self.payee_id is not None:
            done = app.pay_payee(self.payee_id, self.amount, self.from_account_id, self.reference)
        elif self.to_account_id is not None:
            done = app.transfer_between_accounts(
                self.from_account_id, self.to_account_id, self.amount, self.reference
            )
        else:  # pragma: no cover - review refuses a payment to nobody
            raise ToolError("The payment has no recipient; go back and choose one.")
        return back_to("Home", done)


class StandingOrdersScreen(Screen):
    """The user's standing orders."""

    name = "StandingOrders"
    title = "Standing orders"

    def display(self, app: BankingApp) -> dict[str, Any]:
        """The active standing orders, the next due first."""
        orders = app.list_standing_orders()
        return {
            "total": len(orders),
            "standing_orders": [o.model_dump(mode="json") for o in orders[:PAGE]],
            **showing_screen(orders[:PAGE], len(orders), "list_standing_orders()"),
        }

    @action(kind="read")
    def list_standing_orders(self, app: BankingApp, include_cancelled: bool = False) -> list[StandingOrder]:
        """Show your standing orders.

        Args:
            include_cancelled: also show cancelled ones.
        """
        return app.list_standing_orders(include_cancelled)

    @action(kind="write")
    def create_standing_order(
        self,
        app: BankingApp,
        payee_id: str,
        amount: Money,
        first_payment: SimTime,
        frequency: Frequency = "monthly",
        reference: str = "",
        from_account_id: str | None = None,
    ) -> Done:
        """Set up a standing order to a payee.

        Args:
            payee_id: the payee.
            amount: each payment.
            first_payment: when the first payment goes, e.g. "2025-04-01 09:00".
            frequency: "weekly" or "monthly".
            reference: what the payee sees.
            from_account_id: the account to pay from; your main account when left out.
        """
        account = from_account_id or app.default_account_id()
        return app.create_standing_order(payee_id, amount, first_payment, account, frequency, reference)

    @action(kind="write")
    def cancel_standing_order(self, app: BankingApp, standing_order_id: str) -> StandingOrder:
        """Cancel a standing order.

        Args:
            standing_order_id: the standing order's id.
        """
        return app.cancel_standing_order(standing_order_id)


class DirectDebitsScreen(Screen):
    """The user's direct debits."""

    name = "DirectDebits"
    title = "Direct debits"

    def display(self, app: BankingApp) -> dict[str, Any]:
        """The active direct debits, by merchant."""
        debits = app.list_direct_debits()
        return {
            "total": len(debits),
            "direct_debits": [d.model_dump(mode="json") for d in debits[:PAGE]],
            **showing_screen(debits[:PAGE], len(debits), "list_direct_debits()"),
        }

    @action(kind="read")
    def list_direct_debits(self, app: BankingApp, include_cancelled: bool = False) -> list[DirectDebit]:
        """Show your direct debits.

        Args:
            include_cancelled: also show cancelled ones.
        """
        return app.list_direct_debits(include_cancelled)

    @action(kind="write")
    def set_up_direct_debit(
        self, app: BankingApp, merchant: str, reference: str, account_id: str | None = None
    ) -> Done:
        """Allow a company to collect from your account.

        Args:
            merchant: who will collect.
            reference: your customer number with them.
            account_id: the account they collect from; your main account when left out.
        """
        account = account_id or app.default_account_id()
        return app.set_up_direct_debit(merchant, reference, account)

    @action(kind="write")
    def cancel_direct_debit(self, app: BankingApp, direct_debit_id: str) -> DirectDebit:
        """Cancel a direct debit.

        Args:
            direct_debit_id: the direct debit's id.
        """
        return app.cancel_direct_debit(direct_debit_id)


class CardsScreen(Screen):
    """The user's cards."""

    name = "Cards"
    title = "Cards"

    def display(self, app: BankingApp) -> dict[str, Any]:
        """Every card with its account, last four digits and whether it is frozen."""
        cards = app.list_cards()
        return {
            "cards": [c.model_dump() for c in cards[:PAGE]],
            **showing_screen(cards[:PAGE], len(cards), "list_cards()"),
        }

    @action(kind="read")
    def list_cards(self, app: BankingApp) -> list[Card]:
        """Show every card."""
        return app.list_cards()

    @action(kind="write")
    def freeze_card(self, app: BankingApp, card_id: str) -> Card:
        """Freeze a card: payments with it are declined until you unfreeze it.

        Args:
            card_id: the card's id.
        """
        return app.freeze_card(card_id)

    @action(kind="write")
    def unfreeze_card(self, app: BankingApp, card_id: str) -> Card:
        """Unfreeze a card.

        Args:
            card_id: the card's id.
        """
        return app.unfreeze_card(card_id)


BankingApp.set_screens(
    BankHome,
    AccountScreen,
    TransactionScreen,
    PayeesScreen,
    PayScreen,
    ReviewScreen,
    StandingOrdersScreen,
    DirectDebitsScreen,
    CardsScreen,
)
