"""The history over the link: the answers ``lupin serve`` gives a console (the same shapes as
``lupin history --json``), and a console asking a running sim service, which records the patrol
it is sent (slow)."""
from __future__ import annotations

import json
import threading
import time
from datetime import timedelta

import pytest

from mission.history.answers import BadQuery, answer
from mission.link.commands import CommandRefused, parse_command

from .conftest import T0, add_patrol, obs


def test_each_question_answered_as_data(sqlite_history):
    h = sqlite_history
    add_patrol(h, [obs("P01"), obs("P02")], started=T0)
    add_patrol(h, [obs("P01", bug=True), obs("P02")], started=T0 + timedelta(hours=6))
    assert [p["id"] for p in answer(h, "patrols")["patrols"]] == [2, 1]
    assert [p["id"] for p in answer(h, "patrols", limit=1)["patrols"]] == [2]
    assert [e["bug"] for e in answer(h, "pot", pot="P01")["timeline"]] == [False, True]
    assert [(c["pot"], c["kind"]) for c in answer(h, "changes")["changes"]] == [("P01", "pest_new")]
    pests = answer(h, "pests", last=5)
    assert pests["patrols"] == [2, 1] and {p["pot_id"]: p["streak"] for p in pests["pots"]} == {"P01": 1, "P02": 0}
    with pytest.raises(BadQuery, match="name the pot"):
        answer(h, "pot")
    with pytest.raises(BadQuery, match="unknown query"):
        answer(h, "weather")


def test_the_link_checks_a_history_question_like_any_command():
    args = parse_command("history", b'{"query": "pot", "pot": "P01", "token": "t"}', "t")
    assert (args.query, args.pot, args.last) == ("pot", "P01", 10)
    for payload, words in ((b'{"query": "weather", "token": "t"}', "query"), (b'{"query": "pests", "last": 0, '
                                                                               b'"token": "t"}', "last"),
                           (b'{"query": "patrols"}', "operator token")):
        with pytest.raises(CommandRefused, match=words):
            parse_command("history", payload, "t")


@pytest.mark.slow
def test_a_console_reads_the_history_of_a_running_service(tmp_path, sqlite_history):
    from mission.jobs.serve import run_service
    from mission.jobs.sim_serve import start_sim_service
    from mission.link.client import LinkClient
    from mission.link.server import LinkServer, free_endpoint
    from mission.patrol.mission_file import mission_from_world
    from mission.runtime.config import LupinConfig, with_overrides
    from sim.world import load_default_world
    from tests.link.sim_service import wait_for

    add_patrol(sqlite_history, [obs("P01"), obs("P02")], started=T0)
    add_patrol(sqlite_history, [obs("P01", bug=True), obs("P02", blooms=4)], started=T0 + timedelta(hours=6))
    config = with_overrides(LupinConfig(), {"link": {"command_timeout": 20.0}})  # a loaded machine is slow
    service = start_sim_service(load_default_world(), config, tmp_path / "runs", time.perf_counter,
                                history=sqlite_history)
    endpoint = free_endpoint()
    server = LinkServer(service, config.link, "tok", endpoint)
    stop = threading.Event()
    thread = threading.Thread(target=run_service, args=(service, stop, server.close), daemon=True)
    thread.start()
    c = LinkClient(endpoint, "mirte", clock=time.monotonic, token="tok", timeout=25.0)
    try:
        got, error = c.history("changes")
        assert error is None and [(x["pot"], x["kind"]) for x in got["changes"]] == [("P01", "pest_new"),
                                                                                   ("P02", "blooms")]
        got, error = c.history("pot", pot="P01")
        assert error is None and [e["bug"] for e in got["timeline"]] == [False, True]
        got, error = c.history("pot")
        assert got is None and "name the pot" in error
        # serve records every patrol it runs
        one = mission_from_world(load_default_world()).model_copy(update={"name": "served"})
        one = one.model_copy(update={"pots": one.pots[:1]})
        assert c.send("mission_start", mission=json.loads(json.dumps(one.model_dump()))) is None
        assert wait_for(lambda: service.outcome != "", 300), "the served patrol never ended"
        assert wait_for(lambda: all(not r.pending for r in service._writing), 30)
        got, error = c.history("patrols", mission="served")
        assert error is None and len(got["patrols"]) == 1
        served = got["patrols"][0]
        assert served["outcome"] == service.outcome and served["observed"] == 1 and served["ended_at"] is not None
        assert served["report_path"].endswith("report.json") and str(tmp_path / "runs") in served["report_path"]
    finally:
        c.close()
        stop.set()
        thread.join(30)
