"""Places that differ only in their indices are merged exactly: every place shown was reported."""

from __future__ import annotations

import pytest

from pare.scenarios.problem_groups import compact_places


@pytest.mark.parametrize(
    ("paths", "compact"),
    [
        (["a[0].b"], ["a[0].b"]),
        (["a[0].b", "a[1].b", "a[2].b", "a[5].b"], ["a[0-2,5].b"]),
        (["v[0].u[1].tool", "v[1].u[1].tool", "v[1].u[2].tool"], ["v[0-1].u[1].tool", "v[1].u[2].tool"]),
        # a diagonal is not a square: (0,0) and (1,1) must not become [0-1].[0-1]
        (["x[0].y[0]", "x[1].y[1]"], ["x[0].y[0]", "x[1].y[1]"]),
        (["x[0].y[0]", "x[0].y[1]", "x[1].y[0]", "x[1].y[1]"], ["x[0-1].y[0-1]"]),
        (["seed.email", "seed.email", "goals[0].id"], ["seed.email", "goals[0].id"]),
    ],
)
def test_places_are_compacted_exactly(paths: list[str], compact: list[str]) -> None:
    assert list(compact_places(paths)) == compact
