"""The viewer's pages as a site: a page for every path, rendered on demand (served) or all at once
(exported). Links are relative, so the same pages work served and opened from disk.

Paths::

    index.html                              the configurations with their headline metrics
    c/<config>/index.html                   one configuration: its metrics and the episodes table
    c/<config>/rows.js                      the table's rows (loaded by that page; served only with the
                                            site's data key, see :mod:`pare.viewer._server`)
    c/<config>/e/<scenario>/run-<r>.html    one episode
    compare.html                            two configurations' runs of one episode side by side
    leaderboard.html                        the configurations ranked (with two or more of them)
    static/viewer.css, static/viewer.js
"""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import dataclass
from importlib import resources
from typing import Any

from jinja2 import Environment, PackageLoader, StrictUndefined, select_autoescape

from pare.errors import UserInputError
from pare.results import report
from pare.results.metrics import Estimate
from pare.viewer._annotate import episode_annotations
from pare.viewer._episode import build_episode
from pare.viewer._evidence import final_state, library_scenario, matched_entries, state_entries
from pare.viewer._leaderboard import leaderboard
from pare.viewer._paths import OutsideRunError, slug
from pare.viewer._rows import FILTERS, episode_href, filter_choices, rows, rows_script
from pare.viewer._runs import Catalog, Configuration

STATIC = ("viewer.css", "viewer.js", "leaderboard.js")
NOTHING = "\N{EN DASH}"
"""What a table shows for a number that was not measured."""
_EPISODE = re.compile(r"c/([^/]+)/e/([^/]+)/run-([1-9][0-9]{0,5})\.html")
_CONFIG = re.compile(r"c/([^/]+)/(index\.html|rows\.js)")
_TYPES = {".html": "text/html; charset=utf-8", ".js": "text/javascript; charset=utf-8", ".css": "text/css"}


@dataclass(frozen=True)
class Page:
    """A rendered page: its bytes and media type."""

    body: bytes
    media_type: str
    status: int = 200


class Site:
    """Renders the viewer's pages for the configurations of a :class:`Catalog`."""

    def __init__(self, catalog: Catalog, *, data_key: str | None = None) -> None:
        self.catalog = catalog
        self.data_key = data_key
        """The key a page adds to the data it loads (``rows.js?key=…``) when served: the server gives the
        data only to requests that carry it, and only the viewer's own pages know it. ``None`` in an
        export, which is opened from disk."""
        self.templates = Environment(
            loader=PackageLoader("pare.viewer", "templates"),
            autoescape=select_autoescape(default=True),
            undefined=StrictUndefined,
            trim_blocks=True,
            lstrip_blocks=True,
        )
        self.templates.filters.update(
            estimate=format_estimate, share=format_share, pretty=pretty, short=short
        )
        self.templates.globals["episode_href"] = episode_href

    # -- the paths --------------------------------------------------------------------------------------
    def page(self, path: str) -> Page | None:
        """The page at ``path`` (relative, ``/``-separated), or ``None`` when there is none."""
        path = path.lstrip("/") or "index.html"
        if path.endswith("/"):
            path += "index.html"
        if path == "index.html":
            return self._html(self.runs_page())
        if path == "compare.html":
            return self._html(self.compare_page())
        if path == "leaderboard.html":
            return self._html(self.leaderboard_page()) if self.has_leaderboard else None
        if path.startswith("static/") and path[len("static/") :] in STATIC:
            name = path[len("static/") :]
            body = resources.files("pare.viewer").joinpath("static", name).read_bytes()
            return Page(body, _TYPES["." + name.rsplit(".", 1)[1]])
        if found := _CONFIG.fullmatch(path):
            configuration = self.catalog.get(found.group(1))
            if configuration is None:
                return None
            if found.group(2) == "rows.js":
                script = rows_script(configuration.cid, rows(configuration.records.values()))
                return Page(script.encode("utf-8"), _TYPES[".js"])
            return self._html(self.configuration_page(configuration))
        if found := _EPISODE.fullmatch(path):
            configuration = self.catalog.get(found.group(1))
            if configuration is None:
                return None
            text = self.episode_page(configuration, found.group(2), int(found.group(3)))
            return None if text is None else self._html(text)
        return None

    def paths(self) -> Iterator[str]:
        """Every page of the site (for the static export)."""
        yield "index.html"
        yield "compare.html"
        if self.has_leaderboard:
            yield "leaderboard.html"
        yield from (f"static/{name}" for name in STATIC)
        for configuration in self.catalog.configurations:
            yield f"c/{configuration.cid}/index.html"
            yield f"c/{configuration.cid}/rows.js"
            for scenario, run in configuration.records:
                yield f"c/{configuration.cid}/e/{slug(scenario)}/run-{run}.html"

    @property
    def has_leaderboard(self) -> bool:
        """Whether the site ranks its configurations (it has two or more)."""
        return len(self.catalog.configurations) >= 2

    def _html(self, text: str) -> Page:
        return Page(text.encode("utf-8"), _TYPES[".html"])

    def _render(self, template: str, depth: int, **values: Any) -> str:
        query = f"?key={self.data_key}" if self.data_key else ""
        return self.templates.get_template(template).render(root="../" * depth, data_query=query, **values)

    # -- the pages -------------------------------------------------------------------------------------
    def runs_page(self) -> str:
        """The configurations with their headline metrics."""
        return self._render(
            "runs.html",
            0,
            title="PARE runs",
            configurations=[(c, c.metrics) for c in self.catalog.configurations],
            params=sorted({name for c in self.catalog.configurations for name in c.sweep_point}),
            leaderboard=self.has_leaderboard,
        )

    def leaderboard_page(self) -> str:
        """The configurations ranked by success, sortable by every column."""
        return self._render(
            "leaderboard.html", 0, title="Leaderboard", rows=leaderboard(self.catalog.configurations)
        )

    def configuration_page(self, configuration: Configuration) -> str:
        """One configuration's metrics and its episodes table (rows come from ``rows.js``)."""
        table = rows(configuration.records.values())
        return self._render(
            "configuration.html",
            2,
            title=configuration.label,
            configuration=configuration,
            metrics=configuration.metrics,
            filters=FILTERS,
            choices=filter_choices(table),
            count=len(table),
        )

    def episode_page(self, configuration: Configuration, scenario_slug: str, run: int) -> str | None:
        """One episode; ``None`` when the configuration has no such episode.

        A trajectory that cannot be shown (unreadable, of another format, or damaged so that some part
        is missing or of the wrong type) gives the page with what is wrong in place of the episode: one
        damaged file never takes down a page or an export.
        """
        record = configuration.record(scenario_slug, run)
        if record is None:
            return None
        keys = list(configuration.records)
        position = keys.index(record.key)
        page: dict[str, Any] = {
            "title": f"{record.scenario_id} run {record.run}",
            "configuration": configuration,
            "record": record,
            "others": [c for c in self.catalog.configurations if c is not configuration],
            "annotations": None,
            "neighbours": tuple(
                configuration.records[keys[i]] if 0 <= i < len(keys) else None
                for i in (position - 1, position + 1)
            ),
        }
        try:
            trajectory = configuration.trajectory(record)
        except (OutsideRunError, UserInputError) as error:
            return self._render("episode.html", 4, **page, episode=None, problem=str(error))
        if trajectory is None:
            problem = record.failure.message if record.failure is not None else "no trajectory was stored"
            return self._render("episode.html", 4, **page, episode=None, problem=problem)
        try:
            scenario = library_scenario(record.scenario_id, record.scenario_hash)
            matched = None
            if scenario is not None:
                final = final_state(scenario, trajectory)
                matched = {
                    **matched_entries(scenario, trajectory, final),
                    **state_entries(scenario, trajectory, final),
                }
            episode = build_episode(trajectory, list(record.proposals), matched)
            if self.data_key is not None and record.complete:  # served: a person may mark it
                page["annotations"] = episode_annotations(configuration.path, record, trajectory)
            return self._render("episode.html", 4, **page, episode=episode, problem=None)
        except Exception as error:  # any part of a damaged file may be missing or of the wrong type
            problem = f"{record.trajectory}: damaged, cannot be shown: {_describe(error)}"
            return self._render("episode.html", 4, **page, episode=None, problem=problem)

    def compare_page(self) -> str:
        """Two configurations' runs of one episode side by side (chosen in the page)."""
        listing = [{"id": c.cid, "label": c.label} for c in self.catalog.configurations]
        return self._render(
            "compare.html", 0, title="Compare", configurations=json.dumps(listing, ensure_ascii=True)
        )


def _describe(error: Exception) -> str:
    """What went wrong reading a damaged trajectory, in one short line."""
    text = short(str(error), 200)
    return f"{type(error).__name__} {text}" if text else type(error).__name__


def format_estimate(value: Estimate, percent: bool = True) -> str:
    """An estimate as ``pare report`` prints it, :data:`NOTHING` when nothing was measured."""
    return report.format_estimate(value, percent=percent, missing=NOTHING)


def format_share(value: float | None) -> str:
    """A share as a percentage, :data:`NOTHING` when undefined."""
    return report.format_percent(value, missing=NOTHING)


def pretty(value: Any) -> str:
    """JSON-like data as indented text."""
    return value if isinstance(value, str) else json.dumps(value, indent=1, ensure_ascii=False)


def short(value: Any, limit: int = 160) -> str:
    """One line of at most ``limit`` characters."""
    text = value if isinstance(value, str) else json.dumps(value, ensure_ascii=False)
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 1] + "…"
