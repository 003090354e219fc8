"""``pare scenarios``: list, show, self-test and describe the scenario library."""

from __future__ import annotations

from dataclasses import dataclass, field
from enum import StrEnum
from pathlib import Path
from typing import TYPE_CHECKING, Annotated

import typer

if TYPE_CHECKING:  # the library and the gate are imported by the commands: `pare --help` stays fast
    from rich.console import Console

    from pare.agents.models.config import ModelConfig
    from pare.bench.mutation_score import MutationScore
    from pare.bench.selftest import RunVerdict, ScenarioVerdict
    from pare.scenarios.checks import Outcome
    from pare.scenarios.model import Scenario

app = typer.Typer(
    help="The PARE-Bench scenarios: list, show, self-test, coverage, samples, likeness, schema, review.",
    no_args_is_help=True,
    rich_markup_mode=None,  # plain help: see pare.cli.app
)

AppFilter = Annotated[
    list[str] | None, typer.Option("--app", "-a", help="Only scenarios using this app (repeatable).")
]
TagFilter = Annotated[
    list[str] | None, typer.Option("--tag", "-t", help="Only scenarios with this tag (repeatable).")
]
DifficultyFilter = Annotated[
    list[str] | None, typer.Option("--difficulty", "-d", help="Only this difficulty: easy, medium, hard.")
]
SplitFilter = Annotated[
    str | None, typer.Option("--split", "-s", help="Only this split, e.g. full, smoke or ablation.")
]
Paths = Annotated[
    list[Path] | None,
    typer.Argument(help="Scenario files or directories (default: the shipped library).", show_default=False),
]


def _chosen(
    paths: list[Path] | None,
    split: str | None,
    apps: list[str] | None,
    tags: list[str] | None,
    difficulty: list[str] | None,
) -> list[Scenario]:
    from pare.scenarios.library import load_scenarios, select

    return select(
        load_scenarios(paths or None),
        split=split,
        apps=apps or (),
        tags=tags or (),
        difficulty=difficulty or (),
    )


@app.command("list")
def list_scenarios(
    paths: Paths = None,
    app_name: AppFilter = None,
    tag: TagFilter = None,
    difficulty: DifficultyFilter = None,
    split: SplitFilter = None,
) -> None:
    """List scenarios with their apps, tags and difficulty."""
    from rich.table import Table

    from pare.terminal_text import make_console, plain_text

    scenarios = _chosen(paths, split, app_name, tag, difficulty)
    table = Table(title=f"{len(scenarios)} scenarios")
    for column in ("id", "difficulty", "apps", "tags", "title"):
        table.add_column(column, overflow="fold")
    for scenario in scenarios:
        table.add_row(
            scenario.id,
            scenario.difficulty,
            ", ".join(scenario.apps),
            ", ".join(scenario.tags),
            plain_text(scenario.title),
        )
    make_console().print(table)


@app.command("show")
def show(
    scenario_id: Annotated[str, typer.Argument(help="A scenario id, or the path of a scenario file.")],
) -> None:
    """Show one scenario: story, apps, events, the oracle's proposal and the goals' checks."""
    from pare.scenarios.checks import check_sentences
    from pare.scenarios.library import load_scenarios, select
    from pare.scenarios.times import parse_time
    from pare.terminal_text import make_console, markup_safe, plain_text

    path = Path(scenario_id)
    if path.suffix in (".yaml", ".yml"):
        scenario = load_scenarios([path])[0]
    else:
        scenario = select(load_scenarios(), ids=[scenario_id])[0]
    console = make_console()
    console.print(f"[bold]{scenario.id}[/bold] — {markup_safe(scenario.title)}")
    console.print(
        f"{scenario.difficulty}; tags: {', '.join(scenario.tags)}; apps: {', '.join(scenario.apps)}"
    )
    console.print(f"starts {scenario.start.isoformat()}")
    console.print(plain_text(f"\n{scenario.story.strip()}\n"))
    seeded = ", ".join(
        f"{app} ({sum(len(v) if isinstance(v, list | dict) else 1 for v in data.values())})"
        for app, data in scenario.seed.items()
    )
    console.print(f"[bold]seed data[/bold]: {seeded or 'none'}")
    if scenario.events:
        console.print("[bold]events[/bold]:")
        for event in scenario.events:
            if event.at is not None:
                when = parse_time(event.at, scenario.start).isoformat()
            elif event.after is not None:
                when = f"{event.delay} after {event.after}"
            else:
                when = f"{event.delay} after the first matching action"
            console.print(plain_text(f"  {event.id}: {event.tool} at {when}"))
    console.print("[bold]oracle[/bold]:")
    for step in scenario.oracle.user:
        args = ", ".join(f"{k}={v!r}" for k, v in step.args.items())
        console.print(plain_text(f"  user: {step.tool}({args})"))
    for intervention in scenario.oracle.interventions:
        console.print(plain_text(f"  proposal: {intervention.proposal}"))
        for action in intervention.actions:
            console.print(plain_text(f"    then {action.tool}"))
    console.print("[bold]goals[/bold]:")
    sentences = check_sentences(scenario)  # what each check looks for, as review shows it
    for goal in scenario.goals:
        console.print(plain_text(f"  {goal.id}: {goal.description}"))
        for sentence in sentences[goal.id]:
            console.print(plain_text(f"    - {sentence}"))


PARALLEL_FROM = 10
"""By default the gate uses several processes from this many scenarios on (one takes about 0.1 s)."""


@app.command("check")
def check(
    paths: Paths = None,
    app_name: AppFilter = None,
    tag: TagFilter = None,
    difficulty: DifficultyFilter = None,
    split: SplitFilter = None,
    verbose: Annotated[
        bool,
        typer.Option(
            "--verbose",
            "-v",
            help="Show every run and variant, the events each run set off (and which branch each reactive "
            "one took), and every check's verdict.",
        ),
    ] = False,
    jobs: Annotated[
        int,
        typer.Option(
            "--jobs",
            "-j",
            help="Processes to self-test on: 0 (the default) one per core for 10 scenarios or more; "
            "1 only this process.",
        ),
    ] = 0,
    with_mutants: Annotated[
        bool,
        typer.Option(
            "--mutants",
            help="Also play the oracle's generated mutants (each must fail, unless the scenario declares it "
            "in equivalent_mutants) and rewrites (each must pass), and report the mutation score per "
            "scenario and for the library. A surviving mutant or a failing rewrite is a breach: listed, "
            "and the gate exits 1.",
        ),
    ] = False,
    judge_model: Annotated[
        str | None,
        typer.Option(
            "--judge-model",
            help="Also ask this model how reactive events with a 'judge' read each triggering text, and "
            "warn where it and the event's if_args rule disagree (the runs still use the rules).",
            show_default=False,
        ),
    ] = None,
    judge_provider: Annotated[
        str, typer.Option("--judge-provider", help="The judge's client: openai or litellm.")
    ] = "openai",
    judge_endpoint: Annotated[
        str | None, typer.Option("--judge-endpoint", help="The judge's base URL.", show_default=False)
    ] = None,
    judge_key_env: Annotated[
        str | None,
        typer.Option(
            "--judge-key-env",
            help="The variable holding the judge's API key ('none': no key, for a local server). "
            "Default: the provider's usual one.",
            show_default=False,
        ),
    ] = None,
) -> None:
    """Self-test scenarios: the oracle must pass, also with a slow user and with a busy user who never waits
    (every reply it sets off delivered, after the last turn if need be); doing nothing, the user alone, the
    user doing the task by hand and an unrelated proposal must fail; every variant must get its declared
    verdict, and neither the oracle nor a variant that passes may get a reactive event's otherwise reply
    (unless the variant's otherwise_ok says why). Exits 1 on any breach. With --mutants, also plays the
    oracle's mutants and rewrites, reports the mutation score, and breaches on a surviving mutant or a
    failing rewrite.
    """
    import functools
    import time

    from rich.table import Table

    from pare.bench import collector
    from pare.bench.mutation_score import MutationScore
    from pare.bench.processes import map_in_processes, resolve_jobs
    from pare.errors import UserInputError
    from pare.terminal_text import make_console, markup_safe, plain_text

    workers = resolve_jobs(jobs)
    judge = (
        None
        if judge_model is None
        else _judge_config(judge_model, judge_provider, judge_endpoint, judge_key_env)
    )
    began = time.perf_counter()
    with collector.paused():  # the library: long-lived objects only (see pare.bench.collector)
        scenarios = _chosen(paths, split, app_name, tag, difficulty)
    if not scenarios:  # a gate that checked nothing has passed nothing
        filtered = bool(split or app_name or tag or difficulty)
        raise UserInputError(_nothing_to_check(paths, filtered=filtered))
    if jobs == 0 and len(scenarios) < PARALLEL_FROM:
        workers = 1  # starting worker processes would cost more than it saves
    console = make_console()
    table = Table(title=f"self-test of {len(scenarios)} scenarios")
    table.add_column("scenario", overflow="fold")
    table.add_column("oracle\n(must pass;\nturns)", justify="center")
    table.add_column("slow user\n(must pass;\nturns)", justify="center")
    table.add_column("busy user\n(must pass;\nturns)", justify="center")
    table.add_column(f"must fail\n({', '.join(_failing_runs())})", justify="center")
    table.add_column("variants\n(as declared)", justify="center")
    if with_mutants:
        table.add_column("mutants\n(killed+declared\n/counted)", justify="center")
        table.add_column("rewrites\n(pass)", justify="center")
    table.add_column("ms", justify="right")
    score = MutationScore()
    breaches: list[str] = []
    warnings: list[str] = []
    unread: list[str] = []
    unjudged: list[str] = []
    fields: list[str] = []
    held_out = HeldOutTally()
    total = 0.0
    with collector.long_lived_frozen():
        for scenario, (verdict, outcomes) in zip(
            scenarios,
            map_in_processes(
                functools.partial(self_test, judge=judge, mutants=with_mutants), scenarios, workers
            ),
            strict=True,
        ):
            total += verdict.seconds
            failing = [run for run in verdict.runs if run.run in _failing_runs()]
            variants = [run for run in verdict.runs if run.run.startswith("variant:")]
            table.add_row(
                scenario.id,
                _cell(verdict.run("oracle")),
                _cell(verdict.run("slow_user")),
                _cell(verdict.run("busy_user")),
                _mark(all(run.ok for run in failing), f"{sum(run.ok for run in failing)}/{len(failing)}"),
                _mark(
                    all(run.ok for run in variants) and not verdict.problems,
                    f"{sum(run.ok for run in variants)}/{len(variants)}",
                ),
                *(_mutant_cells(verdict) if with_mutants else ()),
                f"{verdict.seconds * 1000:.0f}",
            )
            score.add(scenario.id, verdict.mutants)
            held_out.add(scenario, verdict)
            breaches.extend(verdict.breaches())
            warnings.extend(f"{scenario.id}: {line}" for line in verdict.warnings)
            unread.extend(f"{scenario.id}: {line}" for line in verdict.unread_sends)
            unjudged.extend(f"{scenario.id}: {line}" for line in verdict.unjudged_events)
            fields.extend(f"{scenario.id}: {line}" for line in verdict.unread_fields)
            if verbose:
                _print_details(console, scenario, verdict, outcomes)
    console.print(table)
    if with_mutants:
        _print_score(console, score)
    for line in warnings:
        console.print(f"[yellow]warning[/yellow] {markup_safe(line)}", highlight=False)
    found = {"unread send": unread, "unread field": fields, "unjudged event": unjudged}
    _print_unjudged(console, found)
    if held_out.judged:
        console.print(held_out.summary(), highlight=False)
    if breaches:
        console.print(f"[red]{len(breaches)} breach(es):[/red]")
        for line in breaches:
            console.print(plain_text(f"  {line}"))
        raise typer.Exit(1)
    wall = time.perf_counter() - began
    on = f"{workers} processes" if workers > 1 and len(scenarios) > 1 else "one process"
    console.print(
        f"all {len(scenarios)} scenarios pass the gate ({wall:.2f} s on {on}; {total:.2f} s of self-tests)"
    )


@dataclass
class HeldOutTally:
    """How the checks judged reviewers' held-out probes (variants with ``held_out: true``)."""

    judged: int = 0
    correct_rejected: list[str] = field(default_factory=list)
    wrong_accepted: list[str] = field(default_factory=list)

    def add(self, scenario: Scenario, verdict: ScenarioVerdict) -> None:
        """Count the held-out probes of ``scenario`` that could be played."""
        probes = {f"variant:{variant.id}" for variant in scenario.variants if variant.held_out}
        for run in verdict.runs:
            if run.run not in probes or run.success is None:
                continue
            self.judged += 1
            if run.success != run.expected_success:
                misjudged = self.correct_rejected if run.expected_success else self.wrong_accepted
                misjudged.append(f"{scenario.id} {run.run}")

    def summary(self) -> str:
        """One line: held-out probes judged and misjudged, by kind."""
        wrong = len(self.correct_rejected) + len(self.wrong_accepted)
        return (
            f"held-out probes: {self.judged} judged, {wrong} misjudged ({100 * wrong / self.judged:.0f} %): "
            f"{len(self.correct_rejected)} correct rejected, {len(self.wrong_accepted)} wrong accepted"
        )


def _mutant_cells(verdict: ScenarioVerdict) -> tuple[str, str]:
    mutants = [m for m in verdict.mutants if m.expect == "fail" and m.outcome != "stillborn"]
    rewrites = [m for m in verdict.mutants if m.expect == "pass"]
    judged = sum(m.ok for m in mutants)
    passed = sum(m.ok for m in rewrites)
    return (
        _mark(judged == len(mutants), f"{judged}/{len(mutants)}"),
        _mark(passed == len(rewrites), f"{passed}/{len(rewrites)}"),
    )


def _print_score(console: Console, score: MutationScore) -> None:
    from pare.terminal_text import plain_text

    for scenario_id, verdict in score.misjudged():
        kind = "surviving mutant" if verdict.expect == "fail" else "failing rewrite"
        why = f": {verdict.detail}" if verdict.detail else ""
        console.print(plain_text(f"  {kind} {scenario_id} {verdict.name} ({verdict.what}){why}"))
    stillborn = score.count("stillborn")
    if stillborn:
        console.print(
            f"{stillborn} stillborn mutant(s) not counted: the app refused the changed call, so nothing "
            "changed"
        )
    console.print(score.summary(), highlight=False)
    console.print(score.score_line(), highlight=False)


def _judge_config(model: str, provider: str, endpoint: str | None, key_env: str | None) -> ModelConfig:
    """The gate's judge model from its flags (a mistake in them stops the gate with the reason)."""
    from pydantic import ValidationError

    from pare.agents.models.config import ModelConfig
    from pare.errors import UserInputError

    fields: dict[str, object] = {"model": model, "backend": provider, "api_base": endpoint}
    if key_env is not None:
        fields["api_key_env"] = None if key_env.lower() == "none" else key_env
    try:
        return ModelConfig.model_validate(fields)
    except ValidationError as error:
        problems = "; ".join(f"{'.'.join(map(str, e['loc']))}: {e['msg']}" for e in error.errors())
        raise UserInputError(f"--judge-* flags: {problems}") from None


def _nothing_to_check(paths: list[Path] | None, *, filtered: bool) -> str:
    from pare.scenarios.library import scenario_files

    where = ", ".join(str(path) for path in paths) if paths else "the library"
    if filtered and scenario_files(paths):
        filters = "--split, --app, --tag, --difficulty"
        return f"no scenario in {where} matches the filters ({filters}): nothing to check"
    return f"no scenario was found in {where} (scenario files end in .yaml): nothing to check"


def self_test(
    scenario: Scenario, judge: ModelConfig | None = None, mutants: bool = False
) -> tuple[ScenarioVerdict, dict[str, Outcome]]:
    """The gate's verdict on ``scenario`` and each run's outcome, in a form that crosses processes (an
    episode's environment does not: its tools' argument models are made at run time). With ``judge``,
    the model that reads reactive events' texts beside their rules (calls go uncached); with ``mutants``,
    the verdicts on its generated mutants and rewrites too.
    """
    from dataclasses import replace

    from pare.bench.collector import settle
    from pare.bench.selftest import check_scenario

    model_judge = None
    if judge is not None:
        from pare.agents.judge import ModelJudge
        from pare.agents.models.ledger import UsageLedger
        from pare.bench.build import JudgeModel

        model_judge = ModelJudge(JudgeModel(judge, None, f"gate/{scenario.id}", UsageLedger()), judge.model)
    verdict = check_scenario(scenario, judge=model_judge, mutants=mutants)
    outcomes = {name: result.outcome for name, result in verdict.details.items()}
    result = replace(verdict, details={}), outcomes
    del verdict
    settle()  # the next scenario's collections walk only what it makes
    return result


def _outcome(run: RunVerdict) -> str:
    return "error" if run.success is None else ("pass" if run.success else "fail")


def _mark(ok: bool, text: str) -> str:
    return f"[green]{text}[/green]" if ok else f"[red]{text} ✗[/red]"


def _cell(run: RunVerdict) -> str:
    turns = f" {run.turns}" if run.turns is not None else ""
    return _mark(run.ok, _outcome(run) + turns)


def _print_details(
    console: Console, scenario: Scenario, verdict: ScenarioVerdict, outcomes: dict[str, Outcome]
) -> None:
    from rich.table import Table

    from pare.terminal_text import plain_text

    runs = Table(title=scenario.id, title_justify="left")
    for column in ("run", "must", "got", "turns", "why"):
        runs.add_column(column, overflow="fold")
    for run in verdict.runs:
        must = "pass" if run.expected_success else "fail"
        turns = "" if run.turns is None else str(run.turns)
        runs.add_row(plain_text(run.run), must, _mark(run.ok, _outcome(run)), turns, plain_text(run.why))
    console.print(runs)
    for run in verdict.runs:
        happened = "; ".join(event.describe(scenario.start) for event in run.events) or "none"
        console.print(plain_text(f"  [{run.run}] events: {happened}"), highlight=False)
        if run.after_last_turn:
            late = ", ".join(run.after_last_turn)
            console.print(plain_text(f"  [{run.run}] after the last turn: {late}"), highlight=False)
    if verdict.mutants:
        mutants = Table(title=f"{scenario.id}: mutants and rewrites", title_justify="left")
        for column in ("mutant", "must", "verdict", "what", "why"):
            mutants.add_column(column, overflow="fold")
        for mutant in verdict.mutants:
            mutants.add_row(
                plain_text(mutant.name),
                mutant.expect,
                _mark(mutant.ok or mutant.outcome == "stillborn", mutant.outcome),
                plain_text(mutant.what),
                plain_text(mutant.detail),
            )
        console.print(mutants)
    for name, outcome in outcomes.items():
        for goal in outcome.goals:
            for item in goal.checks:
                mark = "ok " if item.passed else "NO "
                console.print(plain_text(f"  [{name}] {mark}{goal.id}: {item.detail}"))
        for change in outcome.side_effects:
            console.print(plain_text(f"  [{name}] NO side effect: {change.describe()}"))
        for detail in outcome.invented:
            console.print(plain_text(f"  [{name}] NO invented: {detail.describe()}"))


@app.command("stats")
def stats(
    paths: Paths = None,
    app_name: AppFilter = None,
    tag: TagFilter = None,
    difficulty: DifficultyFilter = None,
    split: SplitFilter = None,
    with_mutants: Annotated[
        bool,
        typer.Option(
            "--mutants",
            help="Also play each scenario's generated mutants and rewrites (as `check --mutants` does) and "
            "show the mutation score: the share of mutants killed or declared equivalent, and the rewrites "
            "that pass.",
        ),
    ] = False,
    jobs: Annotated[
        int,
        typer.Option(
            "--jobs",
            "-j",
            help="With --mutants, processes to play them on: 0 (the default) one per core for 10 scenarios "
            "or more; 1 only this process.",
        ),
    ] = 0,
) -> None:
    """Coverage of the library: counts per app, tag, difficulty and kind, apps per scenario, text goals
    judged by a model, variants, and the gaps against PARE-Bench's targets; with --mutants, its mutation
    score too.
    """
    from pare.scenarios.stats import coverage, format_coverage

    scenarios = _chosen(paths, split, app_name, tag, difficulty)
    for line in format_coverage(coverage(scenarios)):
        typer.echo(line)
    if with_mutants:
        score = _mutation_score(scenarios, jobs)
        typer.echo(score.summary())
        typer.echo(score.score_line())


def _mutation_score(scenarios: list[Scenario], jobs: int) -> MutationScore:
    """The mutation score of ``scenarios``: each one's mutants and rewrites played by the gate."""
    import functools

    from pare.bench import collector
    from pare.bench.mutation_score import MutationScore
    from pare.bench.processes import map_in_processes, resolve_jobs

    workers = 1 if jobs == 0 and len(scenarios) < PARALLEL_FROM else resolve_jobs(jobs)
    score = MutationScore()
    with collector.long_lived_frozen():
        played = map_in_processes(functools.partial(self_test, mutants=True), scenarios, workers)
        for scenario, (verdict, _) in zip(scenarios, played, strict=True):
            score.add(scenario.id, verdict.mutants)
    return score


@app.command("sample")
def sample(
    size: Annotated[int, typer.Option("--size", "-n", min=1, help="How many scenarios.")] = 50,
    seed: Annotated[int, typer.Option("--seed", help="The seed that breaks ties.")] = 0,
    write: Annotated[
        str | None,
        typer.Option("--write", help="Store the sample in the library's splits file under this name."),
    ] = None,
    paths: Paths = None,
) -> None:
    """A stratified sample of the library (balanced by app, tag, difficulty, kind and app mix), with its
    profile beside the library's; --write stores it as a split (the ablation split is made this way).
    """
    from rich.table import Table

    from pare.scenarios.library import load_scenarios, write_split
    from pare.scenarios.sampling import stratified_sample
    from pare.terminal_text import make_console, markup_safe

    scenarios = load_scenarios(paths or None)
    if size > len(scenarios):
        raise typer.BadParameter(f"the library has only {len(scenarios)} scenarios", param_hint="--size")
    drawn = stratified_sample(scenarios, size, seed)
    table = Table(title=f"a stratified sample of {size} of {len(scenarios)} scenarios (seed {seed})")
    for column in ("feature", "library", "sample"):
        table.add_column(column, justify="left" if column == "feature" else "right")
    for name in sorted(drawn.library):
        table.add_row(name, f"{drawn.library[name]:.0%}", f"{drawn.sample.get(name, 0.0):.0%}")
    console = make_console()
    console.print(table)
    name, gap = drawn.largest_gap
    console.print(f"largest difference: {name} ({gap:.1%})")
    if write is None:
        typer.echo("\n".join(drawn.ids))
        return
    description = (
        f"A stratified sample of {size} of the library's {len(scenarios)} scenarios (pare scenarios sample "
        f"--size {size} --seed {seed}): apps, tags, difficulty, kind and app mix in the library's "
        "proportions."
    )
    write_split(write, description, drawn.ids)
    console.print(f"split '{markup_safe(write)}' written with {size} scenarios")


class Against(StrEnum):
    """What ``pare scenarios similar`` compares the given scenarios with."""

    library = "library"
    themselves = "themselves"


@app.command("similar")
def similar(
    paths: Paths = None,
    against: Annotated[
        Against | None,
        typer.Option(
            "--against",
            help="library: each given scenario against the shipped library (and the others given); "
            "themselves: only the given ones with each other. Default: library when a path is outside "
            "the library, else themselves.",
            show_default=False,
        ),
    ] = None,
    top: Annotated[
        int, typer.Option("--top", "-n", min=1, help="How many of the most alike pairs to show.")
    ] = 10,
    threshold: Annotated[
        float | None,
        typer.Option(
            "--threshold",
            min=0.0,
            max=1.0,
            help="Pairs at or above this fail the check (default: the library's threshold, 0.60).",
            show_default=False,
        ),
    ] = None,
) -> None:
    """The most alike pairs of scenarios by story (names left out), apps and oracle tools: new files are
    compared with the library they would join. Exits 1 when a pair reaches the threshold: the same story
    with names changed.
    """
    from rich.table import Table

    from pare.scenarios.library import BENCH_DIR, load_scenarios, scenario_files
    from pare.scenarios.similarity import THRESHOLD, similarities
    from pare.terminal_text import make_console, plain_text

    threshold = THRESHOLD if threshold is None else threshold

    scenarios = _chosen(paths, None, None, None, None)
    files = [file.resolve() for file in scenario_files(paths)] if paths else []
    library_dir = BENCH_DIR.resolve()
    if against is None:
        outside = any(library_dir not in file.parents for file in files)
        against = Against.library if outside else Against.themselves
    others: list[Scenario] = []
    if against is Against.library and paths:
        # a given file stands for the library scenario of its id (an edited copy is not its own twin)
        given = {scenario.id for scenario in scenarios}
        others = [scenario for scenario in load_scenarios() if scenario.id not in given]
    pairs = similarities(scenarios, others)
    compared = (
        f"{len(scenarios)} given against the library's {len(others)}" if others else str(len(scenarios))
    )
    title = f"most alike of {len(pairs)} pairs ({compared} scenarios; threshold {threshold:.2f})"
    table = Table(title=title)
    for column in ("score", "story", "apps", "tools", "pair"):
        table.add_column(column, justify="right" if column != "pair" else "left", overflow="fold")
    for pair in pairs[:top]:
        mark = "red" if pair.score >= threshold else "green"
        table.add_row(
            f"[{mark}]{pair.score:.2f}[/{mark}]",
            f"{pair.story:.2f}",
            f"{pair.apps:.2f}",
            f"{pair.tools:.2f}",
            f"{pair.first} ~ {pair.second}",
        )
    console = make_console()
    console.print(table)
    alike = [pair for pair in pairs if pair.score >= threshold]
    if alike:
        console.print(f"[red]{len(alike)} pair(s) tell the same story:[/red]")
        for pair in alike:
            console.print(plain_text(f"  {pair.first} ~ {pair.second} ({pair.score:.2f})"))
        raise typer.Exit(1)
    console.print(f"no pair reaches {threshold:.2f}")


_UNJUDGED = {
    "unread send": "message(s) of the solutions are read by no judge check, so a false text to that person "
    "would pass (docs/writing-scenarios.md, Side effects)",
    "unread field": "text field(s) the solutions write into items are read by no check, so a wrong value "
    "there would pass (docs/writing-scenarios.md, Checks)",
    "unjudged event": "reactive event(s) decide on free text by their rule alone, with no judge criterion "
    "(docs/writing-scenarios.md, Events)",
}


def _print_unjudged(console: Console, found: dict[str, list[str]]) -> None:
    """How many of each kind of what no judge or check reads (:mod:`pare.scenarios.unjudged`), in how many
    scenarios: each is also a breach, listed with the others.
    """
    for label, lines in found.items():
        if lines:
            places = len({line.split(":", 1)[0] for line in lines})
            console.print(f"{len(lines)} {_UNJUDGED[label]}, in {places} scenario(s)", highlight=False)


@app.command("schema")
def schema(
    output: Annotated[
        Path | None, typer.Option("--output", "-o", help="Write to this file instead of stdout.")
    ] = None,
    path: Annotated[
        bool, typer.Option("--path", help="Print where the installed schema file is (for $schema lines).")
    ] = False,
) -> None:
    """Print the JSON Schema of scenario files (for editors and validators)."""
    from pare.output_paths import write_output_file
    from pare.scenarios.schema import SCHEMA_FILE, schema_text

    if path:
        typer.echo(str(SCHEMA_FILE.resolve()))
        return
    text = schema_text()
    if output is None:
        typer.echo(text, nl=False)
    else:
        write_output_file(output, text, "--output")
        typer.echo(f"wrote {output}")


def _failing_runs() -> tuple[str, ...]:
    """The gate's runs that must fail."""
    from pare.bench.selftest import RUNS

    return tuple(name for name, (_, expected) in RUNS.items() if not expected)


@app.command("review")
def review(
    folder: Annotated[Path, typer.Argument(help="A folder of candidates written by pare generate.")],
    accept: Annotated[
        list[str] | None, typer.Option("--accept", help="Move this candidate into the library (repeatable).")
    ] = None,
    reject: Annotated[
        list[str] | None,
        typer.Option("--reject", help="Set this candidate aside (repeatable; needs --reason)."),
    ] = None,
    reason: Annotated[
        str | None, typer.Option("--reason", help="Why the rejected candidates are rejected.")
    ] = None,
    library: Annotated[
        Path | None,
        typer.Option("--library", help="Where accepted candidates go (default: the shipped library)."),
    ] = None,
    interactive: Annotated[
        bool | None,
        typer.Option("--interactive/--no-input", help="Ask about each candidate (default: at a terminal)."),
    ] = None,
) -> None:
    """Show each generated candidate (story, seed volume, events, oracle, goals, variants, gate table)
    and move accepted ones into a library folder, rejected ones to DIR/rejected/ with the reason.
    """
    from pare.cli.review_cmd import review as run_review

    run_review(folder, accept or [], reject or [], reason, library, interactive)


TRIAL_START = "2025-03-03T09:00:00Z"
"""The start ``pare scenarios match`` resolves relative days against unless told (a Monday)."""


@app.command("match")
def match(
    rule: Annotated[
        str,
        typer.Argument(
            help="A matcher as written in a scenario file, in YAML or JSON: '{affirms: [move*]}', "
            "'{any_of: [{mentions_day: day+3}, {contains: thu}]}'.",
            show_default=False,
        ),
    ],
    text: Annotated[
        str,
        typer.Argument(help="The text to try it on ('-' reads it from standard input).", show_default=False),
    ],
    start: Annotated[
        str,
        typer.Option("--start", help="The scenario's start, which day+N and +2h are counted from (ISO)."),
    ] = TRIAL_START,
) -> None:
    """Try a matcher on a text, as a check on a message would: PASS or FAIL with why, the clauses the text
    was cut into and the negations found. Exits 0 on PASS, 1 on FAIL, 2 when the rule is not a matcher.
    """
    import sys
    from datetime import UTC, datetime

    from pare.errors import UserInputError
    from pare.scenarios.trial import parse_rule, try_matcher

    matcher = parse_rule(rule)
    try:
        anchor = datetime.fromisoformat(start.strip().replace("Z", "+00:00"))
    except ValueError:
        raise UserInputError(f"--start: '{start}' is not an ISO time such as {TRIAL_START}") from None
    anchor = anchor if anchor.tzinfo else anchor.replace(tzinfo=UTC)
    if text == "-":
        text = sys.stdin.read().removesuffix("\n")  # the line break that ends what was piped in
    trial = try_matcher(matcher, text, anchor)
    from pare.terminal_text import printable

    for line in trial.lines:
        typer.echo(printable(line))
    if not trial.passed:
        raise typer.Exit(1)
