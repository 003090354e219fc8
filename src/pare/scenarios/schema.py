"""The JSON Schema of scenario files, generated from the models and shipped beside the library."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from pare.scenarios.model import Scenario

SCHEMA_FILE = Path(__file__).parent / "scenario.schema.json"
"""The shipped schema; scenario files point editors at it with a ``yaml-language-server`` comment."""


def scenario_json_schema() -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of a scenario file."""
    schema = Scenario.model_json_schema()
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "$id": "https://pare.example/schemas/scenario.schema.json",
        **schema,
    }


def schema_text() -> str:
    """The schema as the text of the shipped file."""
    return json.dumps(scenario_json_schema(), indent=2, ensure_ascii=False) + "\n"
