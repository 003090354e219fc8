"""Independent work spread over processes: results in order, errors raised, jobs resolved."""

from __future__ import annotations

from pathlib import Path

import pytest

from pare.bench.processes import available_cores, map_in_processes, resolve_jobs
from pare.cli import main
from pare.errors import UserInputError
from tests.scenarios.helpers import sound, to_yaml


def square_or_refuse(number: int) -> int:
    if number == 13:
        raise ValueError("13 is refused")
    return number * number


def test_results_come_back_in_the_items_order() -> None:
    numbers = list(range(12))
    assert list(map_in_processes(square_or_refuse, numbers, jobs=3)) == [n * n for n in numbers]


def test_an_error_for_one_item_is_raised_with_its_message() -> None:
    with pytest.raises(ValueError, match="13 is refused"):
        list(map_in_processes(square_or_refuse, [1, 2, 13, 4], jobs=2))


def test_jobs_zero_means_one_per_core_and_negative_is_refused() -> None:
    assert resolve_jobs(0) == available_cores() >= 1
    assert resolve_jobs(3) == 3
    with pytest.raises(UserInputError, match="--jobs must be 0"):
        resolve_jobs(-1)


def test_the_gate_says_the_same_on_several_processes(
    tmp_path: Path, capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("COLUMNS", "200")
    for index in range(3):
        data = sound()
        data["id"] = f"tiny_reply_{index}"
        (tmp_path / f"tiny_reply_{index}.yaml").write_text(to_yaml(data))
    outputs = []
    for jobs in ("1", "2"):
        assert main(["scenarios", "check", "-v", "-j", jobs, str(tmp_path)]) == 0
        lines = capsys.readouterr().out.splitlines()
        # the tables' rows without their timings (the ms column) and every check's verdict; borders and
        # titles are left out (centred over a width that depends on the timings)
        rows = [line.rsplit("│", 2)[0] for line in lines if line.startswith("│")]
        assert sum("tiny_reply_" in row for row in rows) >= 3
        outputs.append(rows + [line for line in lines if line.startswith("  [")])
    assert outputs[0] == outputs[1]
    assert any("[variant:wrong_person] NO replied:" in line for line in outputs[1])
