"""The change of the apps' data over an episode, as JSON Patch operations in a fixed order.

The order must not depend on the process (a set's order does, through string hashing), so that the same
episode writes the same trajectory byte for byte wherever it runs, locally or on a Ray worker: mapping
keys are visited in sorted order, list items by position.
"""

from __future__ import annotations

from typing import Any


def state_changes(before: Any, after: Any) -> list[dict[str, Any]]:
    """The operations (RFC 6902: ``add``, ``remove``, ``replace``) that turn ``before`` into ``after``,
    applicable in order.
    """
    changes: list[dict[str, Any]] = []
    _diff(before, after, "", changes)
    return changes


def _diff(old: Any, new: Any, path: str, out: list[dict[str, Any]]) -> None:
    if old is new or old == new:  # the same object: an app whose data the episode never read
        return
    _diff_unequal(old, new, path, out)


def _diff_unequal(old: Any, new: Any, path: str, out: list[dict[str, Any]]) -> None:
    """:func:`_diff` of values known to differ; their parts are compared before their path is written,
    since most parts of a changed record did not change.
    """
    if isinstance(old, dict) and isinstance(new, dict):
        for key in sorted(old.keys() | new.keys(), key=str):
            if key in new and key in old:
                before, after = old[key], new[key]
                if before is after or before == after:
                    continue
            where = f"{path}/{str(key).replace('~', '~0').replace('/', '~1')}"
            if key not in new:
                out.append({"op": "remove", "path": where})
            elif key not in old:
                out.append({"op": "add", "path": where, "value": new[key]})
            else:
                _diff_unequal(before, after, where, out)
    elif isinstance(old, list) and isinstance(new, list):
        common = min(len(old), len(new))
        for index in range(common):
            before, after = old[index], new[index]
            if before is not after and before != after:
                _diff_unequal(before, after, f"{path}/{index}", out)
        out.extend(
            {"op": "remove", "path": f"{path}/{index}"} for index in range(len(old) - 1, common - 1, -1)
        )
        out.extend(
            {"op": "add", "path": f"{path}/{index}", "value": new[index]} for index in range(common, len(new))
        )
    else:
        out.append({"op": "replace", "path": path, "value": new})
