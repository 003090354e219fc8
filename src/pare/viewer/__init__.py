"""The trajectory viewer: ``pare view`` serves run and sweep folders as a local web app (read-only but
for annotations, loopback only), and ``pare view --export`` writes the same pages as a static site.

Needs the ``viewer`` extra (Starlette and uvicorn; the pages are Jinja2 templates with plain CSS and a
little JavaScript).
"""

from pare.viewer._episode import EpisodeView, build_episode
from pare.viewer._export import export_site
from pare.viewer._paths import OutsideRunError, confined, slug
from pare.viewer._runs import Catalog, Configuration
from pare.viewer._site import Page, Site

__all__ = [
    "Catalog",
    "Configuration",
    "EpisodeView",
    "OutsideRunError",
    "Page",
    "Site",
    "build_episode",
    "confined",
    "export_site",
    "slug",
]
