"""The dashboard in a real browser (headless Chromium over the DevTools protocol,
``lupin.bench.chromium``) as a grower uses it, on the history of two real sim patrols.

Two patrols of pots P03 and P04 of the default greenhouse: the first in a copy of it where P04
has no pest, the second in the greenhouse as it is (P04's pest) -- the same greenhouse by name,
so P04's pest is new. ``lupin web`` is started as a grower would (a password set first), and the
browser signs in (a wrong password first), sees P04 marked new on the greenhouse page, follows
it to its page (two patrols' pictures, loaded, and the chart), opens the alerts, downloads the
CSV and reads its rows; an unknown pot is a 404 page; and no page asked any host but the
dashboard's (the browser's network log).
"""
from __future__ import annotations

import csv
import os
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from lupin.bench.chromium import Chromium
from lupin.cli import main
from mission.patrol.mission_file import dump_mission, mission_from_world
from sim.world import DEFAULT_WORLD, load_default_world

pytestmark = pytest.mark.slow
PASSWORD = "aphids-on-the-roses"


def two_patrols(root: Path) -> Path:
    """A history of two sim patrols of P03 and P04, P04's pest appearing in the second."""
    world = load_default_world()
    m = mission_from_world(world)
    m = m.model_copy(update={"name": "two-pots", "pots": [p for p in m.pots if p.id in ("P03", "P04")]})
    (root / "m.yaml").write_text(dump_mission(m))
    clean = root / "clean.yaml"
    text = Path(DEFAULT_WORLD).read_text()
    assert ", bug: true}" in text
    clean.write_text(text.replace(", bug: true}", "}"))
    db = root / "h.db"
    for k, w in enumerate((clean, Path(DEFAULT_WORLD))):
        code = main(["patrol", "--world", str(w), "--mission", str(root / "m.yaml"), "--history", str(db),
                     "--report", str(root / f"run{k}" / "report.json"), "--seed", "0"])
        assert code == 0
    return db


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def dashboard(tmp_path_factory):
    root = tmp_path_factory.mktemp("web")
    db = two_patrols(root)
    env = {**os.environ, "LUPIN_RUNTIME__STATE_DIR": str(root / "state")}
    lupin = [str(Path(sys.executable).parent / "lupin")]
    subprocess.run([*lupin, "web", "--set-password"], input=PASSWORD + "\n", text=True, env=env, check=True)
    port = free_port()
    server = subprocess.Popen([*lupin, "web", "--history", str(db), "--listen", f"127.0.0.1:{port}"], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    until = time.monotonic() + 60
    while True:
        try:
            socket.create_connection(("127.0.0.1", port), timeout=1).close()
            break
        except OSError:
            assert server.poll() is None, server.stderr.read()
            assert time.monotonic() < until, "lupin web did not listen within 60 s"
            time.sleep(0.2)
    yield f"http://127.0.0.1:{port}", root
    server.terminate()
    server.wait(10)


def status_of(b: Chromium, url: str) -> int:
    return [e["params"]["response"]["status"] for e in b.events
            if e["method"] == "Network.responseReceived" and e["params"]["response"]["url"] == url][-1]


def test_a_grower_follows_a_new_pest_from_the_greenhouse_to_its_pot_alerts_and_csv(dashboard):
    base, root = dashboard
    with Chromium(width=1280, height=900) as b:
        b.goto(base + "/")
        assert b.eval("location.pathname") == "/login"
        b.type_into("#password", "not-the-password")
        b.click("form.login button")
        assert b.eval("location.pathname") == "/login" and "Wrong password" in b.eval("document.body.innerText")
        b.type_into("#password", PASSWORD)
        b.click("form.login button")
        assert b.eval("location.pathname") == "/"

        # the greenhouse: P04 marked new, on the map and in the list
        assert b.eval("document.querySelector('#pot-P04').classList.contains('new')")
        assert "★ NEW" in b.eval("document.querySelector('#pot-P04').textContent")
        assert not b.eval("document.querySelector('#pot-P03').classList.contains('new')")
        assert "P04 ★ NEW" in b.eval("document.querySelector('table.rows').innerText")
        assert b.eval("document.querySelector('svg.greenhouse image').getAttribute('href')") == "/patrols/2/map.png"
        assert status_of(b, base + "/patrols/2/map.png") == 200  # the SLAM map saved beside the report

        # follow it to its page: both patrols' pictures, loaded, and the chart
        b.click("#pot-P04 circle")
        assert b.eval("location.pathname") == "/pots/P04"
        widths = b.eval("Promise.all([...document.querySelectorAll('.pair img')].map("
                        "i => { i.loading = 'eager'; return i.decode().then(() => i.naturalWidth); }))")
        assert len(widths) == 4 and all(w > 0 for w in widths)
        assert b.eval("document.querySelectorAll('figure.chart polyline').length") == 1
        assert b.eval("document.querySelectorAll('figure.chart .pest-mark').length") == 1
        assert b.eval("document.querySelectorAll('table.rows tbody tr').length") == 2

        b.click("header nav a[href='/alerts']")
        alerts = b.eval("document.querySelector('ul.alerts').innerText")
        assert "new pest" in alerts and "P04" in alerts and "P03" not in alerts

        csv_file = b.download("header nav a[href='/export.csv']", root / "downloads")
        rows = list(csv.DictReader(csv_file.open()))
        assert [(r["pot_id"], r["bug"]) for r in rows] == [("P03", "false"), ("P04", "false"),
                                                          ("P03", "false"), ("P04", "true")]

        b.goto(base + "/pots/NOPE")
        assert status_of(b, base + "/pots/NOPE") == 404
        assert "pot NOPE: not in the history" in b.eval("document.body.innerText")

        asked = b.requested()
        assert len(asked) > 8 and all(u.startswith(base + "/") for u in asked), \
            [u for u in asked if not u.startswith(base + "/")]


def sign_in(b: Chromium, base: str) -> None:
    b.goto(base + "/")
    b.type_into("#password", PASSWORD)
    b.click("form.login button")


def test_the_pages_fit_a_phones_screen(dashboard):
    base, _ = dashboard
    with Chromium(width=390, height=800, mobile=True) as b:
        sign_in(b, base)
        for path in ("/", "/pots/P04", "/patrols", "/patrols/2", "/alerts"):
            b.goto(base + path)
            assert b.eval("document.documentElement.scrollWidth") <= 390, path
            if path.startswith("/pots/"):  # a patrol's two pictures side by side, even on a phone
                left, right = b.eval("[...document.querySelector('.pair').children].map("
                                     "e => e.getBoundingClientRect().top)")
                assert left == right
