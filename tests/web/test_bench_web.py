"""``web.pages``' server half on a small synthetic history (two days of the year's greenhouse):
every page answered 200 over HTTP, each timed the number of times asked."""
from __future__ import annotations

import pytest

from lupin.bench.history import build_year
from lupin.bench.web import PAGES, server_times
from mission.history.store import open_history


@pytest.mark.slow  # serves over HTTP (uvicorn)
def test_server_times_asks_every_page_of_a_synthetic_history(tmp_path):
    h = open_history(str(tmp_path / "days.db"))
    build_year(h, days=2)
    h.close()
    got = server_times(str(tmp_path / "days.db"), n=2)
    assert got["errors"] == 0 and len(got["_times"]) == 2 * len(PAGES)
    assert all(got[f"{p}_ms"]["n"] == 2 for p in PAGES)
