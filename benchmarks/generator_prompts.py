"""What each of the generator's calls sends: the shared system message and each stage's first message.

    python benchmarks/generator_prompts.py [--apps email,calendar]

Builds the prompts ``pare generate`` would send for the given apps, with the library scenario it would
take as the worked example, and, as the sections written so far, that example cut into the stages'
sections (a candidate of about the example's size). Prints, in characters: the system message (and its
JSON Schema and example), each stage's first message, each first call (system and message), and the sum
of the four first calls (a candidate that passes each stage at its first answer). Prints numbers only.
"""

from __future__ import annotations

import argparse

from pare.generate.context import schema_text, worked_example
from pare.generate.prompts import stage_prompt, system_prompt
from pare.generate.sections import ORDER, STAGE_KEYS, STAGES, assemble, split_sections
from pare.scenarios.library import load_scenarios, scenario_files


def main() -> None:
    """Print the sizes for ``--apps``."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--apps", default="email,calendar", help="comma-separated apps (email,calendar)")
    apps = parser.parse_args().apps.split(",")
    files = {path.stem: path for path in scenario_files(None)}
    example = worked_example(apps, load_scenarios(None), files)
    if example is None:
        raise SystemExit("no library scenario to take as the worked example")
    system = system_prompt(example)
    print(f"apps {', '.join(apps)}; worked example {example.scenario_id}")
    parts = f"JSON Schema {len(schema_text()):,}, example {len(example.text):,}"
    print(f"system message: {len(system):,} ({parts})")
    sections = split_sections(example.text, ORDER).sections
    total = 0
    for position, stage in enumerate(STAGES):
        earlier = {key for done in STAGES[:position] for key in STAGE_KEYS[done]}
        written = {key: text for key, text in sections.items() if key in earlier}
        message = stage_prompt(stage, apps=apps, candidate=assemble(written), tag="goal_inference")
        call = len(system) + len(message)
        total += call
        print(f"{stage:<11} message {len(message):>7,}   call {call:>7,}")
    print(f"four first calls: {total:,}")


if __name__ == "__main__":
    main()
