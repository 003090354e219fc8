"""Tools: typed, documented methods that actors call, with schemas taken from their signatures.

A tool is a method decorated with :func:`tool` (agent API and environment methods on an app's backend) or
:func:`pare.apps.screens.action` (a user action on a screen). Its arguments are validated against a
pydantic model built from the type hints, and its description and argument descriptions come from its
Google-style docstring, which is what the models read.
"""

from __future__ import annotations

import functools
import inspect
import re
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from datetime import date, datetime
from decimal import Decimal
from enum import Enum
from functools import cached_property
from types import UnionType
from typing import Annotated, Any, Literal, TypeVar, Union, get_args, get_origin, get_type_hints

import docstring_parser
from pydantic import BaseModel, ConfigDict, Field, ValidationError, create_model
from pydantic_core import ErrorDetails

from pare.apps.harm import Harm
from pare.errors import SimulationBug, ToolError
from pare.sim.log import Actor, ToolKind

F = TypeVar("F", bound=Callable[..., Any])

TOOL_MARKER = "__pare_tool__"


@dataclass(frozen=True, slots=True)
class ToolMeta:
    """What the decorator records on the function; turned into a :class:`ToolSpec` by the owner class."""

    kind: ToolKind
    actors: frozenset[Actor]
    leads_to: tuple[str, ...] = ()
    available: Callable[[Any], bool] | None = None


def tool(
    kind: ToolKind,
    *,
    actors: Sequence[Actor] = ("assistant",),
    available: Callable[[Any], bool] | None = None,
) -> Callable[[F], F]:
    """Declare an app method as a tool.

    Args:
        kind: ``read``, ``write`` or ``env`` for app backends; ``ui`` or ``control`` for the shell.
        actors: who may call it besides the world (``env``) and the oracle, who may call anything.
            App backend methods are the assistant's flat API; shell tools are the user's.
        available: for tools whose availability depends on state (``go_back`` needs somewhere to go
            back to), a predicate on the owning app.
    """

    def decorate(func: F) -> F:
        target = _counting_writes(func) if kind in ("write", "env") else func
        setattr(target, TOOL_MARKER, ToolMeta(kind=kind, actors=frozenset(actors), available=available))
        return target  # type: ignore[return-value]

    return decorate


def _counting_writes(func: Callable[..., Any]) -> Callable[..., Any]:
    """Wrap a backend write so the app's ``write_count`` goes up when it succeeds.

    This is how the environment knows that a user action changed data: user actions call the same
    backend methods the assistant calls, directly, and are logged once as the user's.
    """

    @functools.wraps(func)
    def wrapper(self: Any, *args: Any, **kwargs: Any) -> Any:
        result = func(self, *args, **kwargs)
        self.write_count += 1
        return result

    return wrapper


class ToolSpec:
    """A tool as actors and models see it: name, kind, description, argument schema."""

    def __init__(
        self,
        *,
        app: str,
        name: str,
        func: Callable[..., Any],
        meta: ToolMeta,
        skip: int,
        owner: str,
    ) -> None:
        self.app = app
        self.name = name
        self.func = func
        self.kind: ToolKind = meta.kind
        self.actors: frozenset[Actor] = meta.actors
        self.leads_to = meta.leads_to
        self.available = meta.available
        self.harm: Harm | None = None
        """How bad a wrong call is, for an app's write tools (:mod:`pare.apps.harm`); set by the app."""
        # Tools are documented in the Google style; naming it spares trying every style on each of the
        # few hundred docstrings read when the apps are imported.
        doc = docstring_parser.parse(inspect.getdoc(func) or "", docstring_parser.DocstringStyle.GOOGLE)
        summary = " ".join(part for part in (doc.short_description, doc.long_description) if part)
        if not summary:
            raise SimulationBug(f"{owner}.{name} has no docstring: every tool needs one, models read it")
        self.summary = " ".join(summary.split())
        self.returns: str | None = doc.returns.description if doc.returns else None
        self._doc, self._skip, self._owner = doc, skip, owner

    @cached_property
    def params(self) -> type[BaseModel]:
        """The arguments as a pydantic model, built on first use: a process that calls a few tools does
        not pay for building all of them (an import of every app would build about 260).
        """
        return _params_model(self.func, skip=self._skip, owner=self._owner, docs=self._doc)

    @cached_property
    def returned_record(self) -> type[BaseModel] | None:
        """The model of the object the tool returns (a write's ``Done``), when it returns one: a result
        whose fields a caller must pick from, not a bare value.
        """
        try:
            returned = get_type_hints(self.func).get("return")
        except (NameError, TypeError):  # an annotation that does not resolve: not a known record
            return None
        return returned if isinstance(returned, type) and issubclass(returned, BaseModel) else None

    @property
    def qualified_name(self) -> str:
        """``app__tool``, the name the assistant calls it by (a valid function name for every API)."""
        return f"{self.app}__{self.name}"

    @cached_property
    def parameters_schema(self) -> dict[str, Any]:
        """The JSON Schema of the arguments."""
        schema = self.params.model_json_schema()
        schema.pop("title", None)
        for prop in schema.get("properties", {}).values():
            prop.pop("title", None)
        schema.setdefault("properties", {})
        schema.setdefault("required", [])
        schema["additionalProperties"] = False
        return schema

    @cached_property
    def description(self) -> str:
        """The summary plus what the tool returns, for the model."""
        return f"{self.summary} Returns: {self.returns}" if self.returns else self.summary

    def function_schema(self, name: str | None = None) -> dict[str, Any]:
        """The tool in the OpenAI function-calling format."""
        return {
            "type": "function",
            "function": {
                "name": name or self.name,
                "description": self.description,
                "parameters": self.parameters_schema,
            },
        }

    @cached_property
    def signature(self) -> str:
        """A one-line Python-like signature, e.g. ``search_emails(query: str, limit: int = 10)``."""
        parts = []
        for field_name, info in self.params.model_fields.items():
            annotation = _type_name(info.annotation, expand_models=True)
            if info.is_required():
                parts.append(f"{field_name}: {annotation}")
            else:
                parts.append(f"{field_name}: {annotation} = {info.default!r}")
        return f"{self.name}({', '.join(parts)})"

    def validate(self, args: dict[str, Any]) -> dict[str, Any]:
        """Arguments checked and converted against the signature; :class:`ToolError` says what is wrong."""
        try:
            model = self.params.model_validate(args)
        except ValidationError as error:
            raise ToolError(describe_validation_error(self, error)) from None
        return {name: getattr(model, name) for name in self._argument_names}

    @cached_property
    def _argument_names(self) -> tuple[str, ...]:
        # Reading ``model_fields`` from a pydantic class costs more than the validation of a small call.
        return tuple(self.params.model_fields)


def describe_validation_error(spec: ToolSpec, error: ValidationError) -> str:
    """Turn pydantic's report into one sentence per problem, naming the argument."""
    return describe_argument_errors(spec, error.errors())


def describe_argument_errors(spec: ToolSpec, errors: Iterable[ErrorDetails]) -> str:
    """One sentence per problem in pydantic's error details, naming the argument."""
    problems = []
    for item in errors:
        where = ".".join(str(part) for part in item["loc"]) or "arguments"
        if item["type"] == "missing":
            problems.append(f"missing required argument '{where}'")
        elif item["type"] == "extra_forbidden":
            problems.append(f"unexpected argument '{where}'")
        else:
            problems.append(f"argument '{where}': {item['msg']} (got {item.get('input')!r})")
    return f"Invalid arguments for {spec.name}: " + "; ".join(problems) + f". Expected {spec.signature}."


DATETIME_FORMAT_HINT = "YYYY-MM-DD HH:MM"
"""How a datetime argument is written; ISO 8601 with a ``T`` or seconds is accepted too."""


def _type_name(annotation: Any, *, expand_models: bool = False) -> str:
    """A short, readable, run-independent type: ``list[str] | None``, ``datetime``, ``Folder``.

    ``Annotated`` metadata (validators) is dropped: its text holds memory addresses, which would make
    error messages, and so logs, differ between runs. With ``expand_models`` (what a model reads in a
    tool's signature), dates say how they are written and a nested model lists its fields, so that
    ``updates: EventUpdate`` does not leave the reader guessing what it holds.
    """
    origin = get_origin(annotation)
    if origin is Annotated:
        return _type_name(get_args(annotation)[0], expand_models=expand_models)
    if origin in (Union, UnionType):
        return " | ".join(_type_name(arg, expand_models=expand_models) for arg in get_args(annotation))
    if origin is Literal:
        return " | ".join(repr(arg) for arg in get_args(annotation))
    if origin is not None:
        name = getattr(origin, "__name__", str(origin))
        inner = ", ".join(_type_name(arg, expand_models=expand_models) for arg in get_args(annotation))
        return f"{name}[{inner}]"
    if annotation is type(None):
        return "None"
    if isinstance(annotation, type) and issubclass(annotation, Enum):
        return " | ".join(repr(member.value) for member in annotation)  # models need the choices
    if annotation is Decimal:  # money: written as a number, kept exact
        return "number (at most two decimals)" if expand_models else "number"
    if expand_models and annotation is datetime:
        return f"datetime ({DATETIME_FORMAT_HINT})"
    if expand_models and annotation is date:
        return "date (YYYY-MM-DD)"
    if expand_models and isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return _model_fields(annotation)
    if isinstance(annotation, type):
        return annotation.__name__
    return re.sub(r"\b(?:[A-Za-z_]\w*\.)+([A-Za-z_]\w*)", r"\1", str(annotation))


def _model_fields(model: type[BaseModel]) -> str:
    """``EventUpdate{title?: str, start_datetime?: datetime (YYYY-MM-DD HH:MM)}``: ``?`` marks a field
    that may be left out; a field that may be ``None`` only to be optional is shown without ``None``.
    """
    parts = []
    for name, info in model.model_fields.items():
        annotation: Any = info.annotation
        optional = not info.is_required()
        if optional and info.default is None and get_origin(annotation) in (Union, UnionType):
            kept = [arg for arg in get_args(annotation) if arg is not type(None)]
            annotation = kept[0] if len(kept) == 1 else Union[tuple(kept)]  # noqa: UP007 - built at run time
        parts.append(f"{name}{'?' if optional else ''}: {_type_name(annotation, expand_models=True)}")
    return f"{model.__name__}{{{', '.join(parts)}}}"


type_name = _type_name
"""Public name of :func:`_type_name`, for other readers of the app models (the seed format)."""


def _params_model(
    func: Callable[..., Any], *, skip: int, owner: str, docs: docstring_parser.Docstring
) -> type[BaseModel]:
    signature = inspect.signature(func)
    hints = get_type_hints(func, include_extras=True)
    described = {param.arg_name: param.description for param in docs.params}
    fields: dict[str, Any] = {}
    for position, (name, parameter) in enumerate(signature.parameters.items()):
        if position < skip:
            continue
        if parameter.kind in (inspect.Parameter.VAR_POSITIONAL, inspect.Parameter.VAR_KEYWORD):
            raise SimulationBug(f"{owner}.{func.__name__} takes *args/**kwargs; tools need named arguments")
        if name not in hints:
            raise SimulationBug(f"{owner}.{func.__name__}: argument '{name}' has no type hint")
        if name not in described:
            raise SimulationBug(
                f"{owner}.{func.__name__}: argument '{name}' is not described in the docstring"
            )
        default = ... if parameter.default is inspect.Parameter.empty else parameter.default
        fields[name] = (hints[name], Field(default=default, description=described[name]))
    config = ConfigDict(extra="forbid", arbitrary_types_allowed=False)
    model: type[BaseModel] = create_model(f"{owner}_{func.__name__}_args", __config__=config, **fields)
    return model


def collect_tools(cls: type, *, app: str, skip: int) -> dict[str, ToolSpec]:
    """Every decorated method of ``cls`` (and its bases), as specs keyed by name."""
    specs: dict[str, ToolSpec] = {}
    for klass in reversed(cls.__mro__):
        for name, member in vars(klass).items():
            meta = getattr(member, TOOL_MARKER, None)
            if isinstance(meta, ToolMeta):
                specs[name] = ToolSpec(
                    app=app, name=name, func=member, meta=meta, skip=skip, owner=cls.__name__
                )
    return specs
