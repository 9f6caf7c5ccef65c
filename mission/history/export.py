"""The history as CSV for spreadsheets and notebooks: ``patrols.csv`` and ``observations.csv``,
the tables' columns as they are (spec/history.md), timestamps ISO 8601 UTC.

One source of rows, :func:`csv_lines`, for ``lupin history export`` (files) and the web
dashboard's ``/export.csv`` and per-page CSV (a stream): the same rows either way. Rows are
streamed from the database in batches, so a year of observations (millions of rows) is written
without holding it in memory; a file is written beside itself and renamed into place, so a
reader never sees half a file.
"""
from __future__ import annotations

import csv
import io
import os
from datetime import datetime
from pathlib import Path
from typing import Iterator

from sqlalchemy import Select, select

from mission.history.records import iso
from mission.history.schema import observations, patrols
from mission.history.store import History

BATCH = 5000
TABLES = {"patrols.csv": patrols, "observations.csv": observations}


def _cell(v):
    if isinstance(v, datetime):
        return iso(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    return "" if v is None else v


def rows_query(name: str, mission: str | None = None, patrol: int | None = None, pot: str | None = None) -> Select:
    """The rows of table file ``name`` in export order, only ``mission``'s, one ``patrol``'s or
    one ``pot``'s when given (each read through an index: the primary key, the pot's, the
    mission's patrols)."""
    if name == "patrols.csv":
        q = select(patrols).order_by(patrols.c.started_at, patrols.c.id)
        if patrol is not None:
            q = q.where(patrols.c.id == patrol)
    else:
        q = (select(observations).join(patrols, patrols.c.id == observations.c.patrol_id)
             .order_by(observations.c.patrol_id, observations.c.seq))
        if patrol is not None:
            q = q.where(observations.c.patrol_id == patrol)
        if pot is not None:
            q = q.where(observations.c.pot_id == pot)
    return q if mission is None else q.where(patrols.c.mission == mission)


def csv_lines(history: History, name: str, **only) -> Iterator[str]:
    """The CSV text of table file ``name`` (``only``: :func:`rows_query`'s filters), a batch of
    lines at a time, header first."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(TABLES[name].c.keys())
    with history.engine.connect() as conn:
        result = conn.execution_options(stream_results=True, yield_per=BATCH).execute(rows_query(name, **only))
        for rows in result.partitions():
            w.writerows([_cell(v) for v in r] for r in rows)
            yield buf.getvalue()
            buf.seek(0)
            buf.truncate()
    if buf.tell():
        yield buf.getvalue()


def export_csv(history: History, directory: Path, mission: str | None = None) -> dict[str, int]:
    """Write ``patrols.csv`` and ``observations.csv`` (only ``mission``'s when given) into
    ``directory``; rows written per file."""
    directory.mkdir(parents=True, exist_ok=True)
    counts = {}
    for name in TABLES:
        out, tmp = directory / name, directory / f".{name}.tmp"
        n = -1  # the header is a line, not a row
        with open(tmp, "w", newline="") as f:
            for text in csv_lines(history, name, mission=mission):
                f.write(text)
                n += text.count("\r\n")
        os.replace(tmp, out)
        counts[name] = n
    return counts
