"""``make_app(history, runs, sessions)``: the dashboard as a Starlette app (spec/web.md), used
by ``lupin web`` (served by uvicorn) and by the tests (Starlette's test client, a real browser).

Every page is a stable URL with a JSON twin under ``/api`` and, where it shows a table, a CSV:

=================================  ============================  =================================
page                               JSON                          CSV
=================================  ============================  =================================
``/`` (``?mission=M&last=N``)      ``/api/greenhouse``           ``/export.csv`` (every row)
``/pots/<id>``                     ``/api/pots/<id>``            ``/pots/<id>/observations.csv``
``/patrols`` (``?page=K``)         ``/api/patrols``              ``/patrols.csv``
``/patrols/<id>``                  ``/api/patrols/<id>``         ``/patrols/<id>/observations.csv``
``/alerts`` (``?mission=M``)       ``/api/alerts``
=================================  ============================  =================================

A patrol's pictures are files (``/patrols/<id>/files/<name>``, ``web.reports``), its saved map
drawn as a PNG (``/patrols/<id>/map.png``). Everything answers GET only, but signing in and out:
nothing here writes to the history or commands a robot. Unknown pots and patrols are a 404 page
(JSON under ``/api``); a history that does not answer is a 503 page saying why. Every response
carries a Content-Security-Policy of ``'self'`` only: the browser itself refuses anything a page
might ask of another host.
"""
from __future__ import annotations

import asyncio
import gc
import re
from datetime import datetime
from pathlib import Path
from urllib.parse import parse_qs, quote

import cv2
from sqlalchemy.exc import SQLAlchemyError
from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import (FileResponse, JSONResponse, RedirectResponse, Response, StreamingResponse)
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles
from starlette.templating import Jinja2Templates

from mission.history import queries
from mission.history.export import csv_lines
from mission.history.records import as_utc
from mission.history.store import History, HistoryError, reason
from nav.map_render import render_map
from web import pages
from web.auth import COOKIE, SESSION_S, Sessions
from web.reports import SERVED, report_dir, saved_occupancy, served_file

HERE = Path(__file__).parent
HEADERS = [(b"content-security-policy", b"default-src 'self'; img-src 'self' data:; frame-ancestors 'none'"),
           (b"x-content-type-options", b"nosniff"), (b"referrer-policy", b"same-origin")]
OPEN_PATHS = ("/login", "/static/")
MAX_LAST = 365
WRONG_PASSWORD_S = 1.0
"""A wrong password is answered after a second (without holding up anyone else's pages): a
guesser gets one try a second per connection, a person who mistyped hardly notices."""


def _when(text: str | None) -> str:
    """An ISO time as a grower reads it (UTC)."""
    if not text:
        return "-"
    return as_utc(datetime.fromisoformat(text.replace("Z", "+00:00"))).strftime("%Y-%m-%d %H:%M")


def _templates() -> Jinja2Templates:
    t = Jinja2Templates(directory=str(HERE / "templates"))
    t.env.filters["when"] = _when
    t.env.globals["RESULTS"] = pages.RESULTS
    return t


class SignIn:
    """ASGI middleware: a page for someone not signed in sends them to ``/login`` (JSON and CSV
    answer 401); and every response gets the security headers."""

    def __init__(self, app, sessions: Sessions):
        self.app, self.sessions = app, sessions

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)

        async def with_headers(message):
            if message["type"] == "http.response.start":
                message["headers"] = list(message.get("headers", [])) + HEADERS
            await send(message)

        path = scope["path"]
        if not path.startswith(OPEN_PATHS) and not self.sessions.signed_in(Request(scope).cookies.get(COOKIE)):
            if path.startswith("/api/") or path.endswith(".csv"):
                response = JSONResponse({"error": "sign in first (POST /login)"}, 401)
            else:
                query = scope.get("query_string", b"").decode()
                response = RedirectResponse("/login?next=" + quote(path + (f"?{query}" if query else "")), 303)
            return await response(scope, receive, with_headers)
        await self.app(scope, receive, with_headers)


def freeze_heap() -> None:
    """Before serving: what the process holds by now (the libraries, the engine) moves out of
    the garbage collector's way (``gc.freeze``). A greenhouse page makes ~40,000 objects, which
    sets off full collections; each walked the whole heap, 65 ms on every second or third page of
    a year's greenhouse (CPU 90 ms a page, 155 on those)."""
    gc.collect()
    gc.freeze()


def make_app(history: History, runs: Path | None, sessions: Sessions) -> Starlette:
    templates = _templates()

    def html(request: Request, name: str, status: int = 200, **context) -> Response:
        return templates.TemplateResponse(request, name, {"open": sessions.open, **context}, status_code=status)

    def read(fn, *args):
        with history.reading() as conn:
            return fn(conn, *args)

    def _int(request: Request, name: str, default: int, lo: int, hi: int) -> int:
        text = request.query_params.get(name)
        if text is None:
            return default
        try:
            value = int(text)
        except ValueError:
            value = lo - 1
        if not lo <= value <= hi:
            raise HTTPException(400, f"{name}={text[:20]}: give a whole number from {lo} to {hi}")
        return value

    def of_mission(page: pages.Page | None, request: Request) -> pages.Page:
        if page is None:
            raise HTTPException(404, f"mission {request.query_params['mission']}: no patrol of it in the history")
        return page

    def greenhouse_page(request: Request) -> pages.Page:
        last = _int(request, "last", pages.PEST_LAST, 1, MAX_LAST)
        return of_mission(read(pages.greenhouse, runs, request.query_params.get("mission"), last), request)

    def pot_page(request: Request) -> pages.Page:
        pot_id = request.path_params["pot_id"]
        page = read(pages.pot, pot_id, runs, request.query_params.get("mission"))
        if page is None:
            raise HTTPException(404, f"pot {pot_id}: not in the history")
        return page

    def patrols_page(request: Request) -> pages.Page:
        return read(pages.patrols, _int(request, "page", 0, 0, 10 ** 6), request.query_params.get("mission"))

    def patrol_page(request: Request) -> pages.Page:
        pid = request.path_params["patrol_id"]
        page = read(pages.patrol, pid, runs)
        if page is None:
            raise HTTPException(404, f"patrol {pid}: not in the history")
        return page

    def alerts_page(request: Request) -> pages.Page:
        return of_mission(read(pages.alerts, request.query_params.get("mission")), request)

    builders = {"greenhouse": greenhouse_page, "pots": pot_page, "patrols": patrols_page, "patrol": patrol_page,
                "alerts": alerts_page}

    def page_routes(path: str, api: str, kind: str, template: str) -> list[Route]:
        build = builders[kind]

        def as_html(request: Request) -> Response:
            page = build(request)
            query = f"?{request.url.query}" if request.url.query else ""
            twin = (api if path == "/" else "/api" + request.url.path) + query
            return html(request, template, page=page.data, view=page.view, api=twin)

        def as_json(request: Request) -> Response:
            return JSONResponse(build(request).data)

        return [Route(path, as_html, name=kind), Route(api, as_json, name=f"api_{kind}")]

    def csv(name: str, filename: str, **only) -> Response:
        filename = re.sub(r"[^A-Za-z0-9._-]", "_", filename)  # a pot id from the URL, into a header
        return StreamingResponse(csv_lines(history, name, **only), media_type="text/csv; charset=utf-8",
                                 headers={"content-disposition": f'attachment; filename="{filename}"'})

    def export(request: Request) -> Response:
        mission = request.query_params.get("mission")
        return csv("observations.csv", "observations.csv", mission=mission)

    def patrols_csv(request: Request) -> Response:
        return csv("patrols.csv", "patrols.csv", mission=request.query_params.get("mission"))

    def pot_csv(request: Request) -> Response:
        pot_id = request.path_params["pot_id"]
        return csv("observations.csv", f"{pot_id}.csv", pot=pot_id)

    def patrol_csv(request: Request) -> Response:
        pid = request.path_params["patrol_id"]
        if read(queries.patrol, pid) is None:
            raise HTTPException(404, f"patrol {pid}: not in the history")
        return csv("observations.csv", f"patrol-{pid}.csv", patrol=pid)

    def _directory(pid: int) -> Path | None:
        p = read(queries.patrol, pid)
        if p is None:
            raise HTTPException(404, f"patrol {pid}: not in the history")
        return report_dir(p.report_path, runs)

    def patrol_file(request: Request) -> Response:
        name = request.path_params["name"]
        path = served_file(_directory(request.path_params["patrol_id"]), name)
        if path is None:
            raise HTTPException(404, f"{name}: no such file beside that patrol's report")
        return FileResponse(path, media_type=SERVED[path.suffix.lower()],
                            headers={"cache-control": "private, max-age=3600"})

    def patrol_map(request: Request) -> Response:
        occupancy = saved_occupancy(_directory(request.path_params["patrol_id"]))
        if occupancy is None:
            raise HTTPException(404, "no saved map beside that patrol's report")
        png = cv2.imencode(".png", render_map(occupancy))[1]
        return Response(png.tobytes(), media_type="image/png", headers={"cache-control": "private, max-age=3600"})

    async def login(request: Request) -> Response:
        target = request.query_params.get("next", "/")
        target = target if target.startswith("/") and not target.startswith("//") else "/"
        if request.method == "GET":
            return html(request, "login.html", target=target, wrong=False)
        form = parse_qs((await request.body()).decode(errors="replace"))
        token = await run_in_threadpool(sessions.sign_in, form.get("password", [""])[0])  # scrypt: off the loop
        if token is None:
            await asyncio.sleep(WRONG_PASSWORD_S)
            return html(request, "login.html", status=401, target=target, wrong=True)
        response = RedirectResponse(target, 303)
        response.set_cookie(COOKIE, token, max_age=int(SESSION_S), httponly=True, samesite="strict")
        return response

    def logout(request: Request) -> Response:
        sessions.sign_out(request.cookies.get(COOKIE))
        response = RedirectResponse("/login", 303)
        response.delete_cookie(COOKIE)
        return response

    def error(request: Request, exc: Exception) -> Response:
        if isinstance(exc, HTTPException):
            status, detail = exc.status_code, exc.detail
        else:  # the database did not answer
            status, detail = 503, f"the history {history.shown} does not answer: {reason(exc)}"
        if request.url.path.startswith("/api/"):
            return JSONResponse({"error": detail}, status)
        return html(request, "error.html", status=status, status_code=status, detail=detail)

    routes = [
        *page_routes("/", "/api/greenhouse", "greenhouse", "greenhouse.html"),
        *page_routes("/pots/{pot_id}", "/api/pots/{pot_id}", "pots", "pot.html"),
        *page_routes("/patrols", "/api/patrols", "patrols", "patrols.html"),
        *page_routes("/patrols/{patrol_id:int}", "/api/patrols/{patrol_id:int}", "patrol", "patrol.html"),
        *page_routes("/alerts", "/api/alerts", "alerts", "alerts.html"),
        Route("/export.csv", export), Route("/patrols.csv", patrols_csv),
        Route("/pots/{pot_id}/observations.csv", pot_csv),
        Route("/patrols/{patrol_id:int}/observations.csv", patrol_csv),
        Route("/patrols/{patrol_id:int}/files/{name}", patrol_file),
        Route("/patrols/{patrol_id:int}/map.png", patrol_map),
        Route("/login", login, methods=["GET", "POST"]), Route("/logout", logout, methods=["POST"]),
        Mount("/static", StaticFiles(directory=str(HERE / "static")), name="static"),
    ]
    app = Starlette(routes=routes, exception_handlers={HTTPException: error, SQLAlchemyError: error,
                                                       HistoryError: error})
    return SignIn(app, sessions)
