"""Each route of the dashboard through Starlette's test client: the JSON twins say what the
pages show, unknown pots and patrols are 404s, CSV is the export's rows, pictures are files."""
from __future__ import annotations

import csv
import io

from mission.history.export import export_csv


def test_the_greenhouse_json_marks_the_new_pest_and_the_pressure(client):
    g = client.get("/api/greenhouse").json()
    assert g["mission"] == "m" and g["latest"]["id"] == 2 and g["before"]["id"] == 1
    pots = {p["pot"]: p for p in g["pots"]}
    assert g["new_pests"] == ["P01"] and pots["P01"]["new_pest"] and not pots["P02"]["new_pest"]
    assert pots["P01"]["result"] == "pest" and pots["P03"]["result"] == "failed" and pots["P04"]["result"] == "anomaly"
    assert (pots["P02"]["pests"], pots["P02"]["observed"], pots["P02"]["streak"]) == (2, 2, 2)
    assert (pots["P01"]["pests"], pots["P01"]["observed"]) == (1, 2) and pots["P03"]["observed"] == 0
    assert (pots["P04"]["x"], pots["P04"]["y"]) == (3.2, 2.1)  # where it was last seen
    assert g["pests_now"] == 2 and [t["pests"] for t in g["trend"]] == [1, 2] and g["alerts"] == 3


def test_the_greenhouse_page_draws_each_pot_as_a_link_with_its_result_in_words(client):
    page = client.get("/").text
    assert 'href="/pots/P01"' in page and "★ NEW" in page and "✕ failed" in page
    assert 'href="/api/greenhouse"' in page and 'href="/static/style.css"' in page


def test_a_pot_over_time_with_its_pictures_and_chart(client):
    p = client.get("/api/pots/P01").json()
    assert p["observations"] == 2 and [e["bug"] for e in p["timeline"]] == [False, True]
    assert p["latest"]["result"] == "pest" and p["latest"]["patrol"] == 2
    assert [s["patrol"] for s in p["pictures"]] == [2, 1]
    assert p["pictures"][0]["wrist"] == "/patrols/2/files/P01_wrist.jpg"
    page = client.get("/pots/P01").text
    assert "<polyline" in page and page.count("<img src=\"/patrols/") == 4
    jpg = client.get(p["pictures"][0]["wrist"])
    assert jpg.status_code == 200 and jpg.headers["content-type"] == "image/jpeg" and jpg.content[:2] == b"\xff\xd8"


def test_an_unknown_pot_or_patrol_is_a_404_page_not_a_traceback(client):
    r = client.get("/pots/NOPE")
    assert r.status_code == 404 and "pot NOPE: not in the history" in r.text and "Traceback" not in r.text
    assert client.get("/api/pots/NOPE").json() == {"error": "pot NOPE: not in the history"}
    assert client.get("/patrols/99").status_code == 404 and client.get("/api/patrols/99").status_code == 404
    assert client.get("/patrols/abc").status_code == 404
    assert client.get("/?last=abc").status_code == 400
    assert client.get("/api/alerts?mission=nope").json() == {"error": "mission nope: no patrol of it in the history"}
    assert client.get("/?mission=nope").status_code == 404 and client.get("/?mission=m").status_code == 200


def test_patrols_and_one_patrols_report(client):
    ps = client.get("/api/patrols").json()
    assert [p["id"] for p in ps["patrols"]] == [2, 1] and ps["patrols"][0]["pests"] == 2 and not ps["more"]
    r = client.get("/api/patrols/2").json()
    assert r["patrol"]["observed"] == 4 and r["before"]["id"] == 1 and r["report"]
    assert {(c["pot"], c["kind"]) for c in r["changes"]} == {("P01", "pest_new"), ("P01", "blooms")}
    assert [a["kind"] for a in r["anomalies"]] == ["bug", "moved"] and "inspect_plant" in r["config"]
    assert r["run_png"] == "/patrols/2/files/run.png" and client.get(r["run_png"]).content[:4] == b"\x89PNG"
    assert "What changed" in client.get("/patrols/2").text


def test_alerts_new_spreading_failed_twice_moved(client):
    a = client.get("/api/alerts").json()
    assert [(x["pot"], x["kind"]) for x in a["alerts"]] == [("P01", "spreading"), ("P03", "failed"), ("P04", "moved")]
    assert 'href="/pots/P01"' in client.get("/alerts").text


def test_the_csv_export_is_the_same_rows_as_lupin_history_export(client, history, tmp_path):
    export_csv(history, tmp_path / "out")
    r = client.get("/export.csv")
    assert r.headers["content-type"].startswith("text/csv") and "attachment" in r.headers["content-disposition"]
    assert r.text == (tmp_path / "out" / "observations.csv").read_bytes().decode()
    assert client.get("/patrols.csv").text == (tmp_path / "out" / "patrols.csv").read_bytes().decode()
    rows = list(csv.DictReader(io.StringIO(client.get("/pots/P01/observations.csv").text)))
    assert [(r["patrol_id"], r["bug"]) for r in rows] == [("1", "false"), ("2", "true")]
    assert len(list(csv.DictReader(io.StringIO(client.get("/patrols/1/observations.csv").text)))) == 4
    odd = client.get('/pots/a%22b%0Ac/observations.csv')
    assert odd.status_code == 200 and odd.headers["content-disposition"] == 'attachment; filename="a_b_c.csv"'


def test_only_plain_report_files_are_served(client):
    assert client.get("/patrols/2/files/report.json").status_code == 200
    for name in ("..%2Fm-1%2Freport.json", ".hidden.png", "nothing.png", "h.db"):
        assert client.get(f"/patrols/2/files/{name}").status_code == 404, name


def test_pages_are_read_only_and_ask_the_browser_to_load_nothing_from_elsewhere(client, history):
    before = history.patrols()
    for url in ("/", "/alerts", "/patrols/2", "/pots/P01"):
        assert client.post(url).status_code == 405
        csp = client.get(url).headers["content-security-policy"]
        assert csp.startswith("default-src 'self'")
    assert history.patrols() == before


def test_a_password_is_asked_and_a_wrong_one_refused(locked):
    from tests.web.conftest import PASSWORD

    r = locked.get("/pots/P01", follow_redirects=False)
    assert r.status_code == 303 and r.headers["location"] == "/login?next=/pots/P01"
    assert locked.get("/api/greenhouse").status_code == 401 and locked.get("/export.csv").status_code == 401
    wrong = locked.post("/login?next=/pots/P01", data={"password": "not-it"}, follow_redirects=False)
    assert wrong.status_code == 401 and "Wrong password" in wrong.text and "lupin_web" not in wrong.cookies
    right = locked.post("/login?next=/pots/P01", data={"password": PASSWORD}, follow_redirects=False)
    assert right.status_code == 303 and right.headers["location"] == "/pots/P01"
    assert locked.get("/api/greenhouse").status_code == 200
    locked.post("/logout")
    assert locked.get("/api/greenhouse").status_code == 401


def test_reports_moved_elsewhere_are_found_under_runs(history, tmp_path):
    from starlette.testclient import TestClient

    from web.app import make_app
    from web.auth import Sessions

    (tmp_path / "runs").rename(tmp_path / "farm")
    lost = TestClient(make_app(history, None, Sessions(None)))
    assert lost.get("/api/patrols/2").json()["run_png"] is None
    assert lost.get("/api/pots/P01").json()["pictures"] == [] and "No pictures" in lost.get("/pots/P01").text
    found = TestClient(make_app(history, tmp_path / "farm", Sessions(None)))
    assert found.get("/api/patrols/2").json()["run_png"] == "/patrols/2/files/run.png"
    assert found.get("/patrols/1/files/P01_wrist.jpg").status_code == 200


def test_a_history_that_does_not_answer_is_a_503_page_saying_why(client, history):
    history.outage_until(1e9, lambda: 0.0)
    r = client.get("/")
    assert r.status_code == 503 and "does not answer" in r.text and "Traceback" not in r.text
    assert client.get("/api/alerts").status_code == 503


def test_postgresql_answers_every_page_as_sqlite_does(client, pg_url, tmp_path):
    from starlette.testclient import TestClient

    from mission.history.store import open_history
    from tests.web.conftest import write_two_patrols
    from web.app import make_app
    from web.auth import Sessions

    pg = open_history(pg_url)
    write_two_patrols(pg, tmp_path / "pg-runs")
    on_pg = TestClient(make_app(pg, None, Sessions(None)))
    for url in ("/api/greenhouse", "/api/pots/P01", "/api/patrols", "/api/patrols/2", "/api/alerts"):
        assert _same(client.get(url).json(), on_pg.get(url).json()), url
    assert on_pg.get("/export.csv").text.replace("/pg-runs/", "/runs/") == client.get("/export.csv").text
    pg.close()


def _same(a, b) -> bool:
    """Equal but for where the two histories' report files are."""
    import json

    return json.dumps(a, sort_keys=True).replace("/runs/", "/X/") == json.dumps(b, sort_keys=True).replace(
        "/pg-runs/", "/X/")


def test_an_empty_history_says_so_on_every_page(tmp_path):
    from starlette.testclient import TestClient

    from mission.history.store import open_history
    from web.app import make_app
    from web.auth import Sessions

    h = open_history(str(tmp_path / "empty.db"))
    c = TestClient(make_app(h, None, Sessions(None)))
    assert c.get("/api/greenhouse").json()["mission"] is None and "No patrol recorded yet" in c.get("/").text
    assert c.get("/api/alerts").json()["alerts"] == [] and "No patrol recorded yet" in c.get("/alerts").text
    assert c.get("/api/patrols").json()["patrols"] == [] and c.get("/patrols").status_code == 200
    h.close()
