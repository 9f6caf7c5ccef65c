"""The fleet's router on loopback, real TLS, real access control (spec/fleet.md "Security"):
who may connect, who may publish and read what, who may stop and who may release. The robots
here are bare sessions under a robot's certificate: exactly what a robot, or someone holding a
robot's key, can do; tests/fleet/test_fleet_sim.py has the real runtimes."""
from __future__ import annotations

import datetime as dt
import json

import pytest
import zenoh

from fleet.certs import load_ca, make_fleet, make_member, write_cert, write_key
from mission.link.roster import Roster, stop_fleet
from mission.link.session import TlsFiles, session_config
from tests.fleet.conftest import ask, member, wait_for


def _refused(conf: zenoh.Config) -> bool:
    try:
        zenoh.open(conf).close()
    except zenoh.ZError:
        return True
    return False


def test_no_certificate_another_authority_or_an_expired_one_is_refused(router, certs, tmp_path):
    plain = zenoh.Config()
    plain.insert_json5("mode", '"client"')
    plain.insert_json5("connect/endpoints", json.dumps([router]))
    plain.insert_json5("transport/link/tls", json.dumps({"root_ca_certificate": str(certs / "ca.pem")}))
    assert _refused(plain), "a client with no certificate connected"
    other = tmp_path / "other"
    make_fleet(other, ["r1"], [])
    assert _refused(session_config("connect", router, TlsFiles(certs / "ca.pem", other / "r1.pem", other / "r1.key"))), \
        "a certificate from another authority connected"
    ca_key, ca_cert = load_ca(certs)
    key, cert = make_member("r1", ca_key, ca_cert, dt.datetime.now(dt.timezone.utc) - dt.timedelta(days=10), days=2)
    write_key(tmp_path / "r1.key", key)
    write_cert(tmp_path / "r1.pem", cert)
    assert _refused(session_config("connect", router, TlsFiles(certs / "ca.pem", tmp_path / "r1.pem", tmp_path / "r1.key"))), \
        "an expired certificate connected"
    member(router, certs, "r1").close()  # and the fleet's own does connect


def test_a_robot_publishes_only_under_its_own_name(router, certs):
    ops, r1, r2 = (member(router, certs, n) for n in ("ops", "r1", "r2"))
    try:
        got = []
        ops.declare_subscriber("lupin/**", lambda s: got.append((str(s.key_expr), s.payload.to_bytes())))
        assert wait_for(lambda: (r1.put("lupin/r1/tel/state", b"ping"), got)[1])
        got.clear()
        r2.put("lupin/r1/tel/state", b"forged")
        r2.put("lupin/r2/tel/state", b"own")
        r1.put("lupin/r1/tel/state", b"real")
        assert wait_for(lambda: len([g for g in got if g[1] != b"ping"]) >= 2)
        assert sorted(g for g in got if g[1] != b"ping") == [("lupin/r1/tel/state", b"real"), ("lupin/r2/tel/state", b"own")]
    finally:
        for s in (ops, r1, r2):
            s.close()


def test_a_robot_cannot_read_another_robots_commands_and_a_console_commands_each(router, certs):
    ops, r1, r2 = (member(router, certs, n) for n in ("ops", "r1", "r2"))
    heard = {"r1": [], "r2": [], "spy": []}
    try:
        keep = [r1.declare_queryable("lupin/r1/cmd/*", lambda q: (heard["r1"].append(str(q.key_expr)), q.reply(q.key_expr, b"r1"))),
                r2.declare_queryable("lupin/r2/cmd/*", lambda q: (heard["r2"].append(str(q.key_expr)), q.reply(q.key_expr, b"r2"))),
                r2.declare_queryable("lupin/r1/cmd/*", lambda q: (heard["spy"].append(1), q.reply(q.key_expr, b"spy"))),
                r2.declare_subscriber("lupin/r1/**", lambda s: heard["spy"].append(2))]
        assert wait_for(lambda: ask(ops, "lupin/r1/cmd/teleop") == [b"r1"])
        assert ask(ops, "lupin/r2/cmd/pause") == [b"r2"]
        r1.put("lupin/r1/tel/state", b"x")
        assert ask(r2, "lupin/r1/cmd/estop", {"engaged": False}) == [b"spy"]  # its own queryable, nobody else's
        assert heard["r1"] == ["lupin/r1/cmd/teleop"] and heard["spy"] == [1]
        assert keep
    finally:
        for s in (ops, r1, r2):
            s.close()


def test_any_member_may_stop_a_robot_or_the_fleet_but_only_a_console_commands(router, certs):
    ops, r1, r2, r3 = (member(router, certs, n) for n in ("ops", "r1", "r2", "r3"))
    stops: dict[str, int] = {"r1": 0, "r2": 0, "r3": 0}
    releases: list[str] = []

    def robot(session, name):
        def stop(q):
            stops[name] += 1
            q.reply(q.key_expr, json.dumps({"robot": name}).encode())
        return [session.declare_queryable(f"lupin/{name}/stop", stop), session.declare_queryable("lupin/fleet/stop", stop),
                session.declare_queryable(f"lupin/{name}/cmd/*", lambda q: (releases.append(name), q.reply(q.key_expr, b"ok")))]

    try:
        keep = robot(r1, "r1") + robot(r2, "r2") + robot(r3, "r3")
        assert wait_for(lambda: ask(r2, "lupin/r1/stop") != [])  # r2 stops r1
        assert stops["r1"] >= 1 and stops["r2"] == 0
        assert ask(r2, "lupin/r1/cmd/estop", {"engaged": False}) == [] and releases == []  # ... but cannot release it
        assert ask(ops, "lupin/r1/cmd/estop", {"engaged": False}) == [b"ok"] and releases == ["r1"]
        before = dict(stops)
        assert stop_fleet(r3) == ["r1", "r2", "r3"]  # a robot may stop the whole fleet
        assert stop_fleet(ops) == ["r1", "r2", "r3"]
        assert all(stops[n] == before[n] + 2 for n in stops)
        assert keep
    finally:
        for s in (ops, r1, r2, r3):
            s.close()


def test_the_roster_sees_robots_come_and_go_and_a_new_console_finds_them(router, certs):
    """A death is seen when the robot's socket closes, not when a lease runs out: these bare
    sessions announce zenoh's 10 s lease, so seeing it inside that is the close's doing. How
    long it takes on this machine is fleet.join's figure (goal 1 s), never a test's."""
    ops = member(router, certs, "ops")
    roster = Roster(ops)
    r1, r2 = member(router, certs, "r1"), member(router, certs, "r2")
    try:
        tokens = [r1.liveliness().declare_token("lupin/r1/alive"), r2.liveliness().declare_token("lupin/r2/alive")]
        assert wait_for(lambda: roster.robots() == ["r1", "r2"])
        r2.close()
        assert wait_for(lambda: roster.robots() == ["r1"], 5.0), "r2's death was not seen from its closed socket"
        roster.close()
        ops.close()
        ops = member(router, certs, "ops")  # a console restarts: the tokens held come with its roster
        again = Roster(ops)
        assert wait_for(lambda: again.robots() == ["r1"])
        impostor = r1.liveliness().declare_token("lupin/r9/alive")  # r1 cannot pose as another robot
        tokens[0].undeclare()  # after the impostor on r1's one link: once this shows, so would r9
        assert wait_for(lambda: again.robots() == [])
        assert "r9" not in Roster(ops).robots() and impostor
    finally:
        for s in (ops, r1):
            s.close()


def test_a_console_reads_and_commands_but_forges_nothing(router, certs):
    ops, watcher, r1 = (member(router, certs, n) for n in ("ops", "dispatcher", "r1"))
    try:
        got = []
        watcher.declare_subscriber("lupin/**", lambda s: got.append((str(s.key_expr), s.payload.to_bytes())))
        roster = Roster(watcher)
        token = ops.liveliness().declare_token("lupin/r1/alive")  # a console posing as a robot
        assert wait_for(lambda: (r1.put("lupin/r1/tel/state", b"real"), got)[1])
        ops.put("lupin/r1/tel/state", b"forged")
        ops.put("lupin/fleet/assignments", b"forged")
        watcher.put("lupin/fleet/assignments", b"dispatched")  # the dispatcher writes the fleet's keys
        assert wait_for(lambda: ("lupin/fleet/assignments", b"dispatched") in got)
        assert all(payload != b"forged" for _, payload in got)
        assert roster.robots() == [] and token
    finally:
        for s in (ops, watcher, r1):
            s.close()
