"""Aisle locks (fleet/aisle_locks.py): the table's rules, then the same through a real router on
loopback (mutual TLS, the fleet's access control) with the dispatcher's arbiter and robots as
bare sessions under their certificates, holding their liveliness tokens as runtimes do."""
from __future__ import annotations

import time

import pytest
import zenoh

from fleet.aisle_locks import AISLES, LOCK_GRACE, AisleLockServer, AisleTable
from mission.link.aisle_client import AisleLockClient, ask_key
from mission.link.wire import alive_key
from tests.fleet.conftest import member, wait_for

A, B = 0, 1


class Clock:
    def __init__(self):
        self.t = 0.0

    def __call__(self) -> float:
        return self.t


def test_one_robot_per_aisle_the_second_waits_and_gets_it_when_the_first_leaves():
    t = AisleTable(Clock())
    assert t.request("r1", [A]).granted
    refused = t.request("r2", [A])
    assert not refused.granted and refused.held_by == {A: "r1"} and not refused.yield_
    assert t.request("r1", [A, B]).granted  # asking again for more keeps what it has
    assert t.request("r1", [B]).granted  # left A for B: A is free
    assert t.request("r2", [A]).granted and t.held() == {A: "r2", B: "r1"}


def test_a_leg_through_two_aisles_is_granted_whole_or_not_at_all():
    t = AisleTable(Clock())
    assert t.request("r2", [B]).granted
    assert not t.request("r1", [A, B]).granted
    assert t.held() == {B: "r2"}  # r1 took nothing while it waits: no hold-and-wait
    t.request("r2", [])
    assert t.request("r1", [A, B]).granted


def test_a_wait_that_would_close_a_cycle_is_told_to_yield_and_the_other_goes_on():
    t = AisleTable(Clock())
    assert t.request("r1", [A]).granted and t.request("r2", [B]).granted  # each inside its aisle
    first = t.request("r1", [A, B])
    assert not first.granted and not first.yield_  # r1 waits for r2 ...
    second = t.request("r2", [B, A])
    assert not second.granted and second.yield_  # ... and r2 waiting for r1 would be a deadlock
    assert t.request("r2", []).granted  # r2 backs out to open ground and lets go
    assert t.request("r1", [A, B]).granted
    assert not t.request("r2", [B]).yield_  # waiting on r1 alone is no cycle


def test_a_wait_given_up_long_ago_is_no_cycle():
    clock = Clock()
    t = AisleTable(clock)
    t.request("r1", [A]), t.request("r2", [B])
    assert not t.request("r1", [A, B]).granted  # r1 waits for r2, then plans another way
    clock.t = 6.0
    answer = t.request("r2", [B, A])
    assert not answer.granted and not answer.yield_  # r2 just waits for r1 to leave A


def test_a_dead_robots_locks_are_freed_and_a_lock_held_too_long_is_reported():
    clock = Clock()
    t = AisleTable(clock)
    t.request("r1", [A])
    clock.t = 5.0
    t.request("r2", [B])
    clock.t = 62.0
    assert t.overdue(60.0) == {A: ("r1", 62.0)}
    assert t.keep_only({"r2"}) == ["r1"]
    assert t.held() == {B: "r2"} and t.request("r3", [A]).granted


@pytest.mark.slow
def test_locks_through_the_router_follow_liveliness_and_nobody_asks_in_anothers_name(router, certs):
    dispatcher, r1, r2, ops = (member(router, certs, n) for n in ("dispatcher", "r1", "r2", "ops"))
    server = AisleLockServer(dispatcher, time.monotonic)
    try:
        table, spied = [], []
        r2.declare_subscriber(AISLES, lambda s: table.append(s.payload.to_bytes()))
        c1, c2 = AisleLockClient(r1, "r1"), AisleLockClient(r2, "r2")
        # the arbiter's queryable reaches the router a moment after it is declared
        assert wait_for(lambda: c1.ask([A]) is not None)
        assert not c1.ask([A]).granted  # no liveliness token yet: no lock
        tokens = [r1.liveliness().declare_token(alive_key("r1")), r2.liveliness().declare_token(alive_key("r2"))]
        assert wait_for(lambda: server.roster.robots() == ["r1", "r2"])
        assert c1.ask([A]).granted
        got = c2.ask([A])
        assert got is not None and not got.granted and got.held_by == {A: "r1"}
        assert wait_for(lambda: table and table[-1] == b'{"0":"r1"}')
        # r2 cannot release r1's lock: the router does not pass its query on r1's key
        assert list(r2.get(ask_key("r1"), payload=b'{"aisles": []}', timeout=0.5)) == []
        assert list(ops.get(ask_key("r1"), payload=b'{"aisles": []}', timeout=0.5)) == []  # nor a console
        assert server.table.held() == {A: "r1"}
        spy = r2.declare_queryable(f"{AISLES}/ask/*", lambda q: (spied.append(1), q.reply(q.key_expr, b'{}')))
        asked_all = list(r1.get(ask_key("r1"), payload=b'{"aisles": [0]}', target=zenoh.QueryTarget.ALL, timeout=0.5))
        assert len(asked_all) == 1 and spied == []  # nor can it pose as the arbiter
        spy.undeclare()  # (its own queries would reach it, in its own session)
        # a deadlock-shaped pair of requests through the router: one is told to yield
        assert c2.ask([B]).granted
        assert not c1.ask([A, B]).yield_
        assert c2.ask([B, A]).yield_ and c2.release()
        assert c1.ask([A, B]).granted and c1.release()
        assert c1.ask([A]).granted
        r1.close()  # r1 dies holding A: its token goes, and its lock with it once it stays away
        assert wait_for(lambda: server.table.held() == {}, 10.0 + LOCK_GRACE)
        assert c2.ask([A]).granted
        assert tokens
    finally:
        server.close()
        for s in (dispatcher, r2, ops):
            s.close()


@pytest.mark.slow
def test_a_robot_whose_token_blips_keeps_its_lock(router, certs):
    """A machine stalled past the lease drops a live robot's token for a moment (mission.link.roster):
    its session reconnects, its token is back, and its aisle was never free."""
    dispatcher, r2 = member(router, certs, "dispatcher"), member(router, certs, "r2")
    server = AisleLockServer(dispatcher, time.monotonic, lock_grace=30.0)  # no stall of this machine outlasts it
    r1 = member(router, certs, "r1")
    try:
        token, kept = (s.liveliness().declare_token(alive_key(n)) for s, n in ((r1, "r1"), (r2, "r2")))
        assert wait_for(lambda: server.roster.robots() == ["r1", "r2"])
        assert AisleLockClient(r1, "r1").ask([A]).granted
        token.undeclare()  # gone, as a lapsed lease makes it ...
        r1.close()
        assert wait_for(lambda: server.roster.leaving() == ["r1"])
        r1 = member(router, certs, "r1")  # ... and back, as the reconnected session redeclares it
        back = r1.liveliness().declare_token(alive_key("r1"))
        assert wait_for(lambda: server.roster.leaving() == [])
        got = AisleLockClient(r2, "r2").ask([A])
        assert got is not None and not got.granted and got.held_by == {A: "r1"}
        assert server.table.held() == {A: "r1"} and AisleLockClient(r1, "r1").ask([A]).granted
        assert kept and back
    finally:
        server.close()
        for s in (dispatcher, r1, r2):
            s.close()
