"""The grower's web dashboard (spec/web.md): ``lupin web``, a read-only view of the patrol
history and the patrols' reports in a browser, on the office PC or a phone in the aisle.

A presentation package beside ``tui/`` (DESIGN.md): it reads the history through the same
interface the console and ``lupin history`` use (``History.reading()`` and
``mission.history.queries``), and never writes to it or commands a robot.

- ``app.py``: ``make_app(history, runs, auth)``, the Starlette app: the routes, each page's HTML
  from ``templates/`` and its JSON twin under ``/api``, the CSV, the files;
- ``pages.py``: what each page shows, as JSON-ready data (one function per page);
- ``charts.py``: the greenhouse map, a pot's chart and the pest trend as SVG geometry, drawn on
  the server (no chart library, nothing for a browser to fetch);
- ``reports.py``: a patrol's report directory and the files served from it;
- ``auth.py``: the password (scrypt, salted, in the state directory) and the signed-in sessions;
- ``templates/`` (Jinja2) and ``static/`` (the stylesheet): every asset served by ``lupin web``
  itself, since a greenhouse network is often offline.
"""
