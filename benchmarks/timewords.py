"""What reading days and times in free text costs: the rules, the date library, and the cache.

    python benchmarks/timewords.py [--repeat 5]

Reads every message the library's files hold (each ``content`` value: seed data, events, the oracle's and
the variants' actions) with :func:`pare.scenarios.timewords.mentions`, as of its scenario's start, and
prints:

- the cost of importing the date library and of its first reading (its language data loads then);
- per text, read for the first time (the cache emptied before each pass), for all texts and for the share
  the date library is asked about;
- per text, read again (what every later check on the same message costs).

Times are the median of ``--repeat`` passes. Prints numbers only; no assertion.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import time
from datetime import UTC, datetime
from typing import Any

from pare.scenarios import load_scenarios, timewords


def contents(data: Any) -> list[str]:
    """Every ``content`` text in a scenario file's data."""
    if isinstance(data, dict):
        found = [value for key, value in data.items() if key == "content" and isinstance(value, str)]
        return found + [text for value in data.values() for text in contents(value)]
    if isinstance(data, list):
        return [text for item in data for text in contents(item)]
    return []


def library_texts() -> list[tuple[str, datetime]]:
    """Each message of the library with its scenario's start, once per pair."""
    texts: dict[tuple[str, datetime], None] = {}
    for scenario in load_scenarios():
        for text in contents(scenario.model_dump()):
            texts[(text, scenario.start)] = None
    return list(texts)


def per_text_us(texts: list[tuple[str, datetime]], repeat: int, *, fresh: bool) -> float:
    samples = []
    for _ in range(repeat):
        if fresh:
            timewords.mentions.cache_clear()
        else:
            for text, start in texts:
                timewords.mentions(text, start)
        began = time.perf_counter()
        for text, start in texts:
            timewords.mentions(text, start)
        samples.append((time.perf_counter() - began) / len(texts) * 1e6)
    return statistics.median(samples)


def import_cost_ms() -> tuple[float, float]:
    """Importing the date library, and its first reading, in a fresh interpreter (milliseconds)."""
    probe = (
        "import time\n"
        "began = time.perf_counter()\n"
        "from dateparser.search import search_dates\n"
        "imported = time.perf_counter()\n"
        "search_dates('in two days', languages=['en'])\n"
        "done = time.perf_counter()\n"
        "print((imported - began) * 1e3, (done - imported) * 1e3)\n"
    )
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout
    imported, first = (float(part) for part in out.split())
    return imported, first


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    texts = library_texts()
    asked = [(text, start) for text, start in texts if timewords.asks_library(text)]
    imported, first = import_cost_ms()
    print(f"texts: {len(texts)} messages of the library, {len(asked)} of them given to the date library")
    print(f"date library: import {imported:.0f} ms, first reading {first:.0f} ms (once per process)")
    timewords.mentions("in two days", datetime(2025, 1, 1, tzinfo=UTC))  # its language data, loaded
    print(f"first reading per text: {per_text_us(texts, args.repeat, fresh=True):.0f} us (all texts)", end="")
    if asked:
        print(f", {per_text_us(asked, args.repeat, fresh=True):.0f} us (those given to the date library)")
    else:
        print()
    print(f"read again (cached): {per_text_us(texts, args.repeat, fresh=False):.2f} us per text")


if __name__ == "__main__":
    main()
