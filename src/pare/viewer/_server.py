"""Serving the site on the loopback interface (Starlette under uvicorn): read-only but for annotations.

Pages are ``GET`` and ``HEAD`` only. The one write is ``POST /annotate``, a person's mark on an episode
(:mod:`pare.viewer._annotate`): it needs the server's key, a JSON body (a form another site submits cannot
send one without the browser asking first, which this server never allows) and a request from the viewer's
own pages, and it only ever appends one checked line to a run folder's ``annotations.jsonl``. Pages are
looked up by name (see :mod:`pare.viewer._site`): no URL is ever turned into a file path. The ``Host``
header must name the loopback address, so a web page elsewhere cannot reach the viewer by rebinding its
own domain name to 127.0.0.1.

Pages of other sites cannot read the runs either, though a browser lets any page load a script from
anywhere: the episodes table (``rows.js``) is given only with the key this server made when it started,
which only the viewer's own pages carry (another site cannot read them); a request the browser marks as
coming from another site is refused, except a link followed to a page; and every answer says
``Cross-Origin-Resource-Policy: same-origin``, so the browser itself keeps other sites from loading it.
"""

from __future__ import annotations

import ipaddress
import json
import secrets
import socket

from starlette.applications import Starlette
from starlette.middleware import Middleware
from starlette.middleware.trustedhost import TrustedHostMiddleware
from starlette.requests import Request
from starlette.responses import JSONResponse, PlainTextResponse, Response
from starlette.routing import Route

from pare.errors import UserInputError
from pare.viewer._annotate import MAX_BODY_BYTES, record_annotation
from pare.viewer._site import Site

LOOPBACK_NAMES = ("127.0.0.1", "localhost", "::1")
SECURITY_HEADERS = {
    "Content-Security-Policy": (
        "default-src 'none'; script-src 'self'; style-src 'self'; img-src 'self' data:; "
        "connect-src 'self'; frame-src 'self'; frame-ancestors 'self'; form-action 'none'; base-uri 'none'"
    ),
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "Cache-Control": "no-store",
    "Cross-Origin-Resource-Policy": "same-origin",
    "Cross-Origin-Opener-Policy": "same-origin",
}
DATA_KEY_PARAMETER = "key"
_OWN_SITE = ("same-origin", "none")
"""``Sec-Fetch-Site`` values of requests made by the viewer's own pages or typed by the user."""


def check_loopback(host: str) -> None:
    """Refuse any host that is not the loopback interface: the viewer shows runs to this machine only.

    Raises:
        UserInputError: ``host`` is not 127.0.0.1, ::1 or localhost.
    """
    if host == "localhost":
        return
    try:
        loopback = ipaddress.ip_address(host).is_loopback
    except ValueError:
        loopback = False
    if not loopback:
        raise UserInputError(
            f"pare view serves on the loopback interface only (127.0.0.1, ::1 or localhost), not {host!r}; "
            "to share runs, write a static site with --export DIR"
        )


def create_app(site: Site, bound: str = "127.0.0.1") -> Starlette:
    """The ASGI app serving ``site``; requests must name the loopback (or the address ``bound``) as
    their host.
    """
    if site.data_key is None:  # served: the data needs a key that only the viewer's pages know
        site.data_key = secrets.token_urlsafe(18)
    key = site.data_key

    async def page(request: Request) -> Response:
        if refusal := _cross_site_refusal(request, key):
            return PlainTextResponse(refusal, status_code=403, headers=SECURITY_HEADERS)
        found = site.page(request.url.path)
        if found is None:
            return PlainTextResponse("not found", status_code=404, headers=SECURITY_HEADERS)
        return Response(found.body, media_type=found.media_type, headers=SECURITY_HEADERS)

    async def annotate(request: Request) -> Response:
        refusal = _cross_site_refusal(request, key) or _annotation_refusal(request, key)
        if refusal:
            return JSONResponse({"error": refusal}, status_code=403, headers=SECURITY_HEADERS)
        body = await request.body()
        if len(body) > MAX_BODY_BYTES:
            return JSONResponse({"error": "annotation too large"}, status_code=413, headers=SECURITY_HEADERS)
        try:
            annotation = record_annotation(site.catalog, json.loads(body))
        except (ValueError, UserInputError) as error:
            return JSONResponse({"error": str(error)}, status_code=400, headers=SECURITY_HEADERS)
        return JSONResponse(annotation.model_dump(mode="json"), headers=SECURITY_HEADERS)

    return Starlette(
        routes=[
            Route("/annotate", annotate, methods=["POST"]),
            Route("/{path:path}", page, methods=["GET", "HEAD"]),
        ],
        middleware=[Middleware(TrustedHostMiddleware, allowed_hosts=_host_names(bound))],
    )


def _cross_site_refusal(request: Request, key: str) -> str | None:
    """Why a request must not be answered (it comes from another site, or asks for data without the
    key), or ``None``.
    """
    fetch_site = request.headers.get("sec-fetch-site")
    navigating = request.headers.get("sec-fetch-mode") in (None, "navigate")
    if fetch_site is not None and fetch_site not in _OWN_SITE and not navigating:
        return "refused: the viewer's pages and data are for its own pages only"
    if request.url.path.endswith("/rows.js"):
        given = request.query_params.get(DATA_KEY_PARAMETER, "")
        if not secrets.compare_digest(given.encode(), key.encode()):
            return "refused: the viewer's data is given to its own pages only"
    return None


def _annotation_refusal(request: Request, key: str) -> str | None:
    """Why a mark must not be stored: it lacks the key, is not JSON, or comes from another page than the
    viewer's own; ``None`` when it may.
    """
    given = request.query_params.get(DATA_KEY_PARAMETER, "")
    if not secrets.compare_digest(given.encode(), key.encode()):
        return "refused: annotations are taken from the viewer's own pages only"
    if request.headers.get("content-type", "").split(";")[0].strip() != "application/json":
        return "refused: an annotation is sent as application/json"
    if request.headers.get("sec-fetch-site", "same-origin") != "same-origin":
        return "refused: annotations are taken from the viewer's own pages only"
    return None


def _host_names(bound: str) -> list[str]:
    """What a request's ``Host`` may name: the loopback, and the bound address (IPv6 in brackets too)."""
    names = {*LOOPBACK_NAMES, bound}
    return sorted(names | {f"[{name}]" for name in names if ":" in name})


def bind(host: str, port: int) -> socket.socket:
    """A listening socket on the loopback ``host`` (``port`` 0: a free one).

    Raises:
        UserInputError: ``host`` is not loopback, or the port cannot be had.
    """
    check_loopback(host)
    family = socket.AF_INET6 if ":" in host else socket.AF_INET
    sock = socket.socket(family, socket.SOCK_STREAM)
    try:
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host, port))
        sock.listen(128)
    except OSError as error:
        sock.close()
        raise UserInputError(f"cannot listen on {host}:{port}: {error.strerror or error}") from None
    sock.set_inheritable(True)
    return sock


def url_of(sock: socket.socket) -> str:
    """The address a browser opens for a bound socket."""
    host, port = sock.getsockname()[:2]
    return f"http://[{host}]:{port}/" if ":" in host else f"http://{host}:{port}/"


def serve(site: Site, sock: socket.socket) -> None:
    """Serve ``site`` on ``sock`` until interrupted."""
    import uvicorn

    bound = sock.getsockname()[0]
    config = uvicorn.Config(create_app(site, bound), log_level="warning", access_log=False, lifespan="off")
    uvicorn.Server(config).run(sockets=[sock])
