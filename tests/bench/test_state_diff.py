"""The state diff a trajectory records: valid JSON Patch, in an order that does not depend on the process."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import jsonpatch

from pare.bench.state_diff import state_changes

BEFORE = {
    "email": {"emails": {"e1": {"subject": "Hi", "is_read": False}, "e2": {"subject": "Bye"}}},
    "agent_ui": {"proposals": [{"id": "p1"}, {"id": "p2"}], "messages": []},
    "notes": {"a/b~c": 1},
}
AFTER = {
    "email": {"emails": {"e1": {"subject": "Hi", "is_read": True}, "e3": {"subject": "New"}}},
    "agent_ui": {"proposals": [{"id": "p1"}], "messages": [{"id": "m1"}, {"id": "m2"}]},
    "notes": {"a/b~c": 2},
}


def test_applying_the_changes_gives_the_final_state() -> None:
    changes = state_changes(BEFORE, AFTER)
    assert jsonpatch.apply_patch(BEFORE, changes) == AFTER
    assert state_changes(AFTER, AFTER) == []
    assert {"op": "replace", "path": "/notes/a~1b~0c", "value": 2} in changes


def test_the_order_is_the_same_in_every_process() -> None:
    code = (
        "import json; from pare.bench.state_diff import state_changes; "
        f"print(json.dumps(state_changes({BEFORE!r}, {AFTER!r})))"
    )
    outputs = set()
    for seed in ("1", "2", "3"):
        env = {**os.environ, "PYTHONHASHSEED": seed}
        done = subprocess.run(
            [sys.executable, "-c", code], capture_output=True, text=True, env=env, check=True
        )
        outputs.add(done.stdout)
    assert len(outputs) == 1
    assert json.loads(outputs.pop()) == state_changes(BEFORE, AFTER)


def test_only_the_parts_that_changed_are_written_deepest_first() -> None:
    # unchanged parts of a changed record are left out; a part that changed its type is replaced whole
    before = {"shop": {"orders": [{"id": "o1", "items": [1, 2]}, {"id": "o2", "n": 1}], "tags": {"a": 1}}}
    after = {"shop": {"orders": [{"id": "o1", "items": [1, 3, 4]}, {"id": "o2", "n": 1}], "tags": [1]}}
    assert state_changes(before, after) == [
        {"op": "replace", "path": "/shop/orders/0/items/1", "value": 3},
        {"op": "add", "path": "/shop/orders/0/items/2", "value": 4},
        {"op": "replace", "path": "/shop/tags", "value": [1]},
    ]
    assert jsonpatch.apply_patch(before, state_changes(before, after)) == after
