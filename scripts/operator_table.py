"""Write the scenario guide's table of matcher operators from their records.

    python scripts/operator_table.py            # write it
    python scripts/operator_table.py --check    # exit 1 if it is stale

The table in ``docs/writing-scenarios.md`` (between its two ``<!-- operators: ... -->`` lines) is made from
:data:`pare.scenarios.matchers.OPERATORS`; edit an operator's record, not the table. ``--check`` writes
nothing and exits 1 when the guide's table differs from the records (the tests run it so).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from pare.scenarios.operator_docs import with_operator_table

GUIDE = Path(__file__).resolve().parents[1] / "docs" / "writing-scenarios.md"


def main(argv: list[str] | None = None) -> int:
    """Write the table into the guide (or with ``--check``, say whether it is current); the exit code."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="write nothing; exit 1 if the table is stale")
    parser.add_argument("--guide", type=Path, default=GUIDE, help="the guide to write (default: %(default)s)")
    args = parser.parse_args(argv)
    written = args.guide.read_text(encoding="utf-8")
    current = with_operator_table(written)
    if current == written:
        return 0
    if args.check:
        print(f"{args.guide}: the table of operators is stale; run: python scripts/operator_table.py")
        return 1
    args.guide.write_text(current, encoding="utf-8")
    print(f"{args.guide}: table of operators written")
    return 0


if __name__ == "__main__":
    sys.exit(main())
