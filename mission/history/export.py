"""The history as CSV files for spreadsheets and notebooks: ``patrols.csv`` and
``observations.csv``, the tables' columns as they are (spec/history.md), timestamps ISO 8601 UTC.

Rows are streamed from the database in batches, so a year of observations (millions of rows)
is written without holding it in memory; each file is written beside itself and renamed into
place, so a reader never sees half a file.
"""
from __future__ import annotations

import csv
import os
from datetime import datetime
from pathlib import Path

from sqlalchemy import select

from mission.history.records import iso
from mission.history.schema import observations, patrols
from mission.history.store import History

BATCH = 5000


def _cell(v):
    if isinstance(v, datetime):
        return iso(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    return "" if v is None else v


def export_csv(history: History, directory: Path, mission: str | None = None) -> dict[str, int]:
    """Write ``patrols.csv`` and ``observations.csv`` (only ``mission``'s when given) into
    ``directory``; rows written per file."""
    directory.mkdir(parents=True, exist_ok=True)
    pq = select(patrols).order_by(patrols.c.started_at, patrols.c.id)
    oq = (select(observations).join(patrols, patrols.c.id == observations.c.patrol_id)
          .order_by(observations.c.patrol_id, observations.c.seq))
    if mission is not None:
        pq, oq = pq.where(patrols.c.mission == mission), oq.where(patrols.c.mission == mission)
    counts = {}
    with history.engine.connect() as conn:
        for name, table, q in (("patrols.csv", patrols, pq), ("observations.csv", observations, oq)):
            out, tmp = directory / name, directory / f".{name}.tmp"
            n = 0
            with open(tmp, "w", newline="") as f:
                w = csv.writer(f)
                w.writerow(table.c.keys())
                result = conn.execution_options(stream_results=True, yield_per=BATCH).execute(q)
                for rows in result.partitions():
                    w.writerows([_cell(v) for v in r] for r in rows)
                    n += len(rows)
            os.replace(tmp, out)
            counts[name] = n
    return counts
