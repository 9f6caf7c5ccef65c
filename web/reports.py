"""A patrol's report directory, and the files the dashboard may serve from it.

The history keeps where each patrol wrote its report (``patrols.report_path``); the pictures are
files beside it, served as files (never through the database). Where that directory is gone (the
reports were moved to the farm server), ``lupin web --runs DIR`` names where they are now:
``DIR/<the report directory's name>`` (``lupin serve`` writes ``DIR/<mission>-<k>/``).

Only plain files directly in that directory, of the kinds a report writes, are served: a name
with a slash, a dot file or another kind is not found, so no URL reaches anything else on disk.
"""
from __future__ import annotations

import json
from pathlib import Path

SERVED = {".png": "image/png", ".jpg": "image/jpeg", ".jpeg": "image/jpeg", ".json": "application/json",
          ".yaml": "text/plain; charset=utf-8", ".txt": "text/plain; charset=utf-8"}


def report_dir(report_path: str | None, runs: Path | None) -> Path | None:
    """Where a patrol's report and pictures are now, or None when neither place has them."""
    if not report_path:
        return None
    here = Path(report_path).parent
    if here.is_dir():
        return here
    if runs is not None and (runs / here.name).is_dir():
        return runs / here.name
    return None


def served_file(directory: Path | None, name: str) -> Path | None:
    """The file ``name`` in ``directory`` when it may be served, else None."""
    if directory is None or not name or "/" in name or "\\" in name or name.startswith("."):
        return None
    path = directory / name
    return path if path.suffix.lower() in SERVED and path.is_file() else None


def read_report(directory: Path | None) -> dict | None:
    """The report's JSON, or None when it is missing or unreadable (a patrol still writing it
    has replaced it atomically, so a half file is never read)."""
    path = served_file(directory, "report.json")
    if path is None:
        return None
    try:
        doc = json.loads(path.read_text())
    except (OSError, ValueError):
        return None
    return doc if isinstance(doc, dict) else None


def read_text(directory: Path | None, name: str, limit: int = 200_000) -> str | None:
    """A text file of the report (``config.yaml``), at most ``limit`` characters."""
    path = served_file(directory, name)
    if path is None:
        return None
    try:
        return path.read_text(errors="replace")[:limit]
    except OSError:
        return None


def saved_occupancy(directory: Path | None):
    """The SLAM map saved beside the report, cropped to what was explored (with a margin), or
    None: the greenhouse map's background and ``/patrols/<id>/map.png``, so both place it alike."""
    from mission.history.pest_map import saved_map

    m = saved_map(str(directory / "report.json")) if directory is not None else None
    return None if m is None else m.cropped(margin=4)
