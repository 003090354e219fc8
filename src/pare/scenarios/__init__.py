"""Scenarios: the file format, loading with clear errors, checks, the oracle and the PARE-Bench library."""

# First: the built-in matcher operators register themselves before anything here compiles a matcher.
from pare.scenarios import operators as _operators  # noqa: F401
from pare.scenarios.build import build_environment
from pare.scenarios.checks import CheckResult, GoalResult, Judge, JudgeVerdict, Outcome, aevaluate, evaluate
from pare.scenarios.library import get_scenario, library, load_scenarios, select, splits
from pare.scenarios.loader import ScenarioError, load_scenario, parse_scenario
from pare.scenarios.model import TAGS, Scenario
from pare.scenarios.oracle import OracleAssistant, OracleUser, UnrelatedAssistant
from pare.scenarios.schema import scenario_json_schema

__all__ = [
    "TAGS",
    "CheckResult",
    "GoalResult",
    "Judge",
    "JudgeVerdict",
    "OracleAssistant",
    "OracleUser",
    "Outcome",
    "Scenario",
    "ScenarioError",
    "UnrelatedAssistant",
    "aevaluate",
    "build_environment",
    "evaluate",
    "get_scenario",
    "library",
    "load_scenario",
    "load_scenarios",
    "parse_scenario",
    "scenario_json_schema",
    "select",
    "splits",
]
