"""Shared builders for the dashboard's tests: a history of two patrols of one mission, written
through the history's own interface, with their report directories beside them (report.json,
run.png, config.yaml and each pot's two pictures), and a test client on the app.

Patrol 1: P01 clean, P02 a pest, P03 failed, P04 clean. Patrol 2: P01 a pest (new, 0.8 m from
P02: spreading), P02 still a pest, P03 failed again, P04 found moved.
"""
from __future__ import annotations

import json
from datetime import timedelta
from pathlib import Path

import cv2
import numpy as np
import pytest
from starlette.testclient import TestClient

from mission.history.store import History, open_history
from tests.history.conftest import T0, add_patrol, obs, pg_url, postgres  # noqa: F401 (fixtures)
from web.app import make_app
from web.auth import Sessions, hash_password

PASSWORD = "greenhouse-42"
XY = {"P01": (0.0, 0.0), "P02": (0.8, 0.0), "P03": (3.0, 0.0), "P04": (3.0, 2.0)}


def _report_dir(root: Path, name: str, rows, anomalies: list[dict]) -> Path:
    d = root / name
    d.mkdir(parents=True)
    for o in rows:
        if o.status != "inspected":
            continue
        for cam, colour in (("front", (90, 140, 60)), ("wrist", (60, 60, 200) if o.bug else (200, 120, 220))):
            img = np.full((120, 160, 3), colour, np.uint8)
            cv2.putText(img, f"{o.pot_id} {cam} {name}", (6, 60), cv2.FONT_HERSHEY_SIMPLEX, 0.45, (255, 255, 255), 1)
            cv2.imwrite(str(d / f"{o.pot_id}_{cam}.jpg"), img)
    cv2.imwrite(str(d / "run.png"), np.full((80, 120, 3), 240, np.uint8))
    (d / "config.yaml").write_text("patrol:\n  inspect_pose: inspect_plant\n")
    (d / "report.json").write_text(json.dumps({"mission": "m", "outcome": "completed", "anomalies": anomalies}))
    return d


def _with_images(rows, d: Path):
    from dataclasses import replace

    return [replace(o, front_image=str(d / f"{o.pot_id}_front.jpg"), wrist_image=str(d / f"{o.pot_id}_wrist.jpg"))
            if o.status == "inspected" else o for o in rows]


def write_two_patrols(history: History, root: Path) -> tuple[int, int]:
    first = [obs("P01", x=0.0, y=0.0), obs("P02", bug=True, anomalies=("bug",), x=0.8, y=0.0),
             obs("P03", status="failed", anomalies=("unreachable",), x=3.0, y=0.0), obs("P04", x=3.0, y=2.0)]
    second = [obs("P01", bug=True, blooms=2, anomalies=("bug",), x=0.0, y=0.0),
              obs("P02", bug=True, anomalies=("bug",), x=0.8, y=0.0),
              obs("P03", status="failed", anomalies=("unreachable",), x=3.0, y=0.0),
              obs("P04", anomalies=("moved",), x=3.2, y=2.1)]
    d1 = _report_dir(root, "m-1", first, [{"kind": "bug", "pot": "P02", "detail": "dark spot on a bloom"}])
    d2 = _report_dir(root, "m-2", second, [{"kind": "bug", "pot": "P01", "detail": "dark spot on a leaf"},
                                           {"kind": "moved", "pot": "P04", "detail": "0.22 m from the mission's"}])
    a = add_patrol(history, _with_images(first, d1), started=T0, report_path=str(d1 / "report.json"))
    b = add_patrol(history, _with_images(second, d2), started=T0 + timedelta(hours=6),
                   report_path=str(d2 / "report.json"))
    return a, b


@pytest.fixture
def history(tmp_path) -> History:
    h = open_history(str(tmp_path / "h.db"))
    write_two_patrols(h, tmp_path / "runs")
    yield h
    h.close()


@pytest.fixture
def client(history) -> TestClient:
    """The open dashboard (no password) on the two patrols."""
    return TestClient(make_app(history, None, Sessions(None)))


@pytest.fixture
def locked(history) -> TestClient:
    """The dashboard behind the password ``PASSWORD``."""
    return TestClient(make_app(history, None, Sessions(hash_password(PASSWORD))))
