"""Reading scenario files: every problem reported at once, with its file, line and place."""

from __future__ import annotations

from pathlib import Path as FilePath
from typing import Any

from pydantic import ValidationError

from pare.errors import UserInputError, did_you_mean
from pare.scenarios.annotations import model_fields, step_into
from pare.scenarios.model import Scenario
from pare.scenarios.parsed_cache import cached, remember
from pare.scenarios.problem_groups import LocatedProblem, group_problems
from pare.scenarios.validation import Problem, format_path, validate_scenario
from pare.yaml_source import Path, UnreadableFile, YamlDocument, YamlSyntaxError, parse_yaml, read_text_file


class ScenarioError(UserInputError):
    """A scenario file that cannot be used; :attr:`problems` lists everything wrong with it, place by
    place, and the message says each mistake once (:attr:`grouped`: the same message at several places is
    one line with the places and their count).
    """

    def __init__(self, source: str, problems: list[LocatedProblem]) -> None:
        self.source = source
        self.problems = problems
        self.grouped = group_problems(problems)
        count = _count(len(self.grouped), "problem")
        if len(problems) != len(self.grouped):
            count += f" in {_count(len(problems), 'place')}"
        super().__init__(f"{source}: {count}:\n" + "\n".join(f"  {group}" for group in self.grouped))


def _count(number: int, noun: str) -> str:
    return f"{number} {noun}{'s' if number != 1 else ''}"


def load_scenario(path: str | FilePath) -> Scenario:
    """Read and fully validate the scenario file at ``path``; :class:`ScenarioError` lists all problems.

    A file inside a library must be named after its id (``<id>.yaml``).
    """
    file = FilePath(path)
    try:
        text = read_text_file(file)
    except FileNotFoundError:
        raise UserInputError(f"{file}: no such scenario file") from None
    except UnreadableFile as error:
        raise UserInputError(f"{file}: {error}") from None
    scenario = cached(text)
    if scenario is None:
        scenario = parse_scenario(text, source=str(file))
        remember(text, scenario)
    if file.stem != scenario.id:
        line = None
        raise ScenarioError(
            str(file),
            [
                LocatedProblem(
                    str(file), line, "id", f"the id '{scenario.id}' differs from the file name '{file.stem}'"
                )
            ],
        )
    return scenario


def parse_scenario(text: str, *, source: str = "<scenario>") -> Scenario:
    """Parse and fully validate a scenario given as YAML text."""
    try:
        # A message written as a folded or literal block reaches the apps without the line break YAML
        # ends such a block with: here, once for every text of the file (events, oracle, variants).
        document = parse_yaml(text, clip_block_scalars=True)
    except YamlSyntaxError as error:
        raise ScenarioError(source, [LocatedProblem(source, error.line, "(file)", str(error))]) from None
    if not isinstance(document.data, dict):
        kind = "empty" if document.data is None else f"a {type(document.data).__name__}"
        raise ScenarioError(
            source,
            [LocatedProblem(source, 1, "(top)", f"a scenario is a mapping of fields; this file is {kind}")],
        )
    if document.duplicate_keys:
        raise ScenarioError(
            source,
            [
                _locate(Problem(path, f"'{path[-1]}' is written twice in the same mapping"), document, source)
                for path in document.duplicate_keys
            ],
        )
    try:
        scenario = Scenario.model_validate(document.data)
    except ValidationError as error:
        raise ScenarioError(source, _structure_problems(error, document, source)) from None
    problems = validate_scenario(scenario)
    if problems:
        raise ScenarioError(source, [_locate(problem, document, source) for problem in problems])
    return scenario


def _structure_problems(error: ValidationError, document: YamlDocument, source: str) -> list[LocatedProblem]:
    located: list[LocatedProblem] = []
    for item in error.errors():
        # pydantic adds the names of union members and validators to locations; keep the document's keys
        path: Path = tuple(part for part in item["loc"] if isinstance(part, int) or "[" not in str(part))
        kind = item["type"]
        if kind == "missing":
            message = "required field missing"
        elif kind == "extra_forbidden":
            allowed = _fields_at(path[:-1])
            message = f"unknown field '{path[-1]}'" if path else "unknown field"
            if allowed:
                message += f".{did_you_mean(str(path[-1]), allowed)} Fields here: {', '.join(allowed)}"
        else:
            message = str(item["msg"]).removeprefix("Value error, ")
        located.append(_locate(Problem(path, message), document, source))
    return located


def _fields_at(path: Path) -> list[str]:
    """The field names of the model that sits at ``path`` in a scenario document (empty if none)."""
    annotation: Any = Scenario
    for part in path:
        annotation = step_into(annotation, part)
        if annotation is None:
            return []
    return list(model_fields(annotation) or [])


def _locate(problem: Problem, document: YamlDocument, source: str) -> LocatedProblem:
    return LocatedProblem(source, document.line_of(problem.path), format_path(problem.path), problem.message)
