"""Fleet benchmarks: a fleet's link on loopback through a real router (spec/fleet.md).

Three robots serve in every run: r1 is a real-time sim runtime in this process (its wheel duties
are watched here), r2 and r3 are ``lupin serve --robot rK`` processes, the load a fleet puts on
one router and on this machine's 2 cores. The console is ``ops``.

``fleet.link``: the console's soft e-stop to all-zero wheel duty on r1, as ``link.estop``
times it (``lupin.bench.link.press_trials``: drive by teleop, press at a random phase of the
control beat, every press counted), through the router over mutual TLS with access control;
then, for comparison, through a ``--no-tls`` router (``tcp``) and straight to r1 with no router
(``direct``, r2 and r3 serving on their own ports). Top-level figures are the TLS run's.

``fleet.bytes``: payload bytes per second the console receives through the TLS router with the
three robots idle, in total and per robot; the goal is a total within 3x one robot's.

``fleet.soak``: the issue's ten minutes, three ``lupin serve`` robots and a console on the TLS
router, a stop every 2 s (a robot's stop key from another robot's certificate, the console's
command, the fleet stop), every one checked in the robot's own telemetry: nothing may be lost.

``fleet.join``: from r1's link opening (its session to the router, its liveliness token) to the
console listing it, over ``JOIN_TRIALS`` joins; and from a ``lupin serve`` robot's SIGKILL to the
console dropping it, over ``DEATH_TRIALS`` deaths; before each death the robot is frozen
(SIGSTOP: its socket open and silent, as a robot off the network) and ``silence`` is the time to
the console dropping it (its lease, ``mission.link.session.ROBOT_LEASE_MS``). Goal: 1 s each. ``process_start`` is from
spawning ``lupin serve`` to the console listing it: the runtime's own start-up (the simulator,
SLAM) comes first, and the link joins once it is built.
"""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time
from contextlib import ExitStack, contextmanager
from pathlib import Path

import numpy as np

from fleet.certs import make_fleet, member_files
from lupin.bench import Sample, benchmark
from lupin.bench.link import STOP_WITHIN_S, TOKEN, _stderr, _wait, console_presses, live_runtime
from lupin.cli.console import stop_child
from mission.link.client import LinkClient
from mission.link.roster import Roster
from mission.link.server import LinkServer
from mission.link.session import free_endpoint, open_session, session_config
from mission.runtime.config import LupinConfig, with_overrides

LUPIN = str(Path(sys.executable).parent / "lupin")
OTHERS = ("r2", "r3")
JOIN_TRIALS = 20
DEATH_TRIALS = 5


def start_lupin(args: list[str], until: str, env: dict | None = None, timeout: float = 120.0) -> subprocess.Popen:
    """``lupin ARGS`` as a child, returned once a line of its output holds ``until`` (its log to
    /dev/null, never a pipe nobody drains); RuntimeError with its last line otherwise."""
    proc = subprocess.Popen([LUPIN, *args], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                            env={**os.environ, **(env or {})})
    end = time.monotonic() + timeout
    line = "?"
    while time.monotonic() < end:
        line = proc.stdout.readline()
        if until in line:
            return proc
        if not line and proc.poll() is not None:
            break
    stop_child(proc)
    raise RuntimeError(f"lupin {' '.join(args[:1])} did not start: {line.strip()}")


@contextmanager
def fleet_files():
    with tempfile.TemporaryDirectory() as tmp:
        certs = Path(tmp) / "certs"
        make_fleet(certs, ["r1", *OTHERS], ["ops"])
        yield certs, Path(tmp)


@contextmanager
def fleet_run(config: LupinConfig, how: str, certs: Path, tmp: Path):
    """r1 in this process, r2 and r3 as processes, joined ``how``: ``tls`` or ``tcp`` through a
    router, ``direct`` each on its own port; yields (service, r1's endpoint, the console's TLS
    files or None, the router's endpoint or None)."""
    env = {"LUPIN_LINK__TOKEN": TOKEN, "LUPIN_LINK__COMMAND_TIMEOUT": "8", "LUPIN_HISTORY__URL": "none"}
    with ExitStack() as stack:
        router = None
        if how != "direct":
            router = free_endpoint("tls" if how == "tls" else "tcp")
            args = ["router", "--listen", router] + (["--certs", str(certs)] if how == "tls" else ["--no-tls"])
            stack.callback(stop_child, start_lupin(args, "listening on"))
        for name in OTHERS:
            where = ["--listen", free_endpoint()] if router is None else (
                ["--connect", router] + (["--certs", str(certs)] if how == "tls" else []))
            child = start_lupin(["serve", "--robot", name, "--runs", str(tmp / name), *where], f"robot {name!r}", env)
            stack.callback(stop_child, child)
        r1 = with_overrides(config, {"link": {"robot": "r1"}})
        tls = member_files(certs, "r1") if how == "tls" else None
        fleet = {"connect": router, "tls": tls} if router is not None else {}
        service, server, endpoint = stack.enter_context(
            live_runtime(r1, None if tls is not None else TOKEN, **fleet))
        yield service, endpoint, (member_files(certs, "ops") if how == "tls" else None), router


def _estop_trials(service, endpoint: str, tls, config: LupinConfig):
    console = LinkClient(endpoint, "r1", clock=time.monotonic, token=TOKEN, tls=tls)
    try:
        return console_presses(service, console, config, "fleet.link")
    finally:
        console.close()


def _summary(tally) -> dict:
    t = np.asarray(tally.times_ms, float)
    stats = {"median_ms": round(float(np.median(t)), 3), "p95_ms": round(float(np.percentile(t, 95)), 3)} if t.size \
        else {"median_ms": None, "p95_ms": None}
    return {**stats, "attempted": tally.attempted, "stopped": tally.stopped, "failed": len(tally.failures),
            "not_driving": tally.not_driving}


@benchmark("fleet.link")
def link(config: LupinConfig) -> Sample:
    runs = {}
    with fleet_files() as (certs, tmp):
        for how in ("tls", "tcp", "direct"):
            with fleet_run(config, how, certs, tmp / how) as (service, endpoint, tls, router):
                runs[how] = _estop_trials(service, endpoint, tls, config)
    tls = runs["tls"]
    return Sample(tls.times_ms, {**tls.figures(), "robots": 3, "transport": "tls (mutual, access control)",
                                 "tcp": _summary(runs["tcp"]), "direct": _summary(runs["direct"])})


@benchmark("fleet.bytes")
def link_bytes(config: LupinConfig) -> Sample:
    window = 20.0
    with fleet_files() as (certs, tmp), fleet_run(config, "tls", certs, tmp) as (service, endpoint, tls, router):
        session = open_session(session_config("connect", router, tls), "connect", router, "--connect")
        roster = Roster(session)
        counted: dict[str, int] = {}
        try:
            if not _wait(lambda: roster.robots() == ["r1", *OTHERS], 30):
                _stderr(f"fleet.bytes: only {roster.robots()} up after 30 s")

            def on_sample(s) -> None:
                robot = str(s.key_expr).split("/")[1]
                counted[robot] = counted.get(robot, 0) + len(s.payload.to_bytes())

            sub = session.declare_subscriber("lupin/**", on_sample)  # the console: every robot's telemetry
            time.sleep(3.0)  # every robot's keyframes have passed once
            counted.clear()
            t0 = time.perf_counter()
            time.sleep(window)
            dt = time.perf_counter() - t0
            per_robot = {r: round(b / dt) for r, b in sorted(counted.items())}
            sub.undeclare()
        finally:
            roster.close()
            session.close()
    total = sum(per_robot.values())
    one = max(per_robot.values()) if per_robot else 0
    return Sample([dt * 1000.0], {"total_bps": total, "per_robot_bps": per_robot, "robots": len(per_robot),
                                  "ratio_to_one_robot": round(total / one, 2) if one else None, "window_s": window})


@benchmark("fleet.join")
def join(config: LupinConfig) -> Sample:
    joins: list[float] = []
    deaths: list[float] = []
    starts: list[float] = []
    silences: list[float] = []
    missed: list[str] = []
    with fleet_files() as (certs, tmp):
        router = free_endpoint("tls")
        with ExitStack() as stack:
            stack.callback(stop_child, start_lupin(["router", "--listen", router, "--certs", str(certs)], "listening on"))
            session = open_session(session_config("connect", router, member_files(certs, "ops")), "connect", router, "--connect")
            stack.callback(session.close)
            roster = Roster(session)
            stack.callback(roster.close)
            r1 = with_overrides(config, {"link": {"robot": "r1"}, "sim": {"realtime": True}})
            from mission.jobs.sim_serve import start_sim_service
            from sim.world import load_default_world

            service = start_sim_service(load_default_world(), r1, tmp / "r1", time.perf_counter)
            stack.callback(service.close)
            for i in range(JOIN_TRIALS):  # the runtime is built, not stepped: only its link comes and goes
                t0 = time.perf_counter()
                server = LinkServer(service, r1.link, None, connect=router, tls=member_files(certs, "r1"))
                if _wait(lambda: "r1" in roster.robots(), 5.0):
                    joins.append((time.perf_counter() - t0) * 1000.0)
                else:
                    missed.append(f"join {i + 1}: not listed within 5 s")
                server.close()
                _wait(lambda: "r1" not in roster.robots(), 5.0)
            for i in range(DEATH_TRIALS):
                spawned = time.perf_counter()
                child = start_lupin(["serve", "--robot", "r2", "--connect", router, "--certs", str(certs),
                                     "--runs", str(tmp / "r2")], "robot 'r2'", {"LUPIN_HISTORY__URL": "none"})
                if not _wait(lambda: "r2" in roster.robots(), 10.0):
                    missed.append(f"death {i + 1}: r2 never listed")
                    stop_child(child)
                    continue
                starts.append((time.perf_counter() - spawned) * 1000.0)
                t0 = time.perf_counter()
                os.kill(child.pid, signal.SIGSTOP)  # silent first: hung, or off the network
                if _wait(lambda: "r2" not in roster.robots(), 5.0):
                    silences.append((time.perf_counter() - t0) * 1000.0)
                else:
                    missed.append(f"silence {i + 1}: still listed 5 s after SIGSTOP")
                os.kill(child.pid, signal.SIGCONT)
                if not _wait(lambda: "r2" in roster.robots(), 10.0):
                    missed.append(f"death {i + 1}: r2 not listed again after SIGCONT")
                t0 = time.perf_counter()
                child.kill()
                if _wait(lambda: "r2" not in roster.robots(), 5.0):
                    deaths.append((time.perf_counter() - t0) * 1000.0)
                else:
                    missed.append(f"death {i + 1}: still listed 5 s after SIGKILL")
                child.wait(30)
    for m in missed:
        _stderr(f"fleet.join: FAILED {m}")

    def stats(v: list[float]) -> dict:
        return {"median_ms": round(float(np.median(v)), 1), "p95_ms": round(float(np.percentile(v, 95)), 1),
                "max_ms": round(max(v), 1), "n": len(v)} if v else {"n": 0}

    return Sample(joins + deaths, {"join": stats(joins), "death": stats(deaths), "silence": stats(silences),
                                   "process_start": stats(starts),
                                   "attempted_joins": JOIN_TRIALS,
                                   "attempted_deaths": DEATH_TRIALS, "failures": missed})


SOAK_S = 600.0
"""The issue's soak: three robots and a console through one router for 10 minutes."""
SOAK_EVERY_S = 2.0


@benchmark("fleet.soak")
def soak(config: LupinConfig) -> Sample:
    """Three ``lupin serve`` robots and a console on the TLS router for ``SOAK_S``; every
    ``SOAK_EVERY_S`` a stop goes out in turn as a robot's stop key from another robot, the
    console's ``estop`` command and the fleet stop, then the console releases. A stop is *lost*
    when its query is not answered or the robot's telemetry does not show it engaged within
    ``STOP_WITHIN_S``; every one is counted (times: query sent to engaged in its telemetry, the
    fleet stop's robots read one after another). Each release must show in the telemetry before
    the next stop, so an engaged flag is never an old one."""
    from mission.link.fleet_link import FleetLink

    robots = ["r1", *OTHERS]
    times: list[float] = []
    lost: list[str] = []
    attempted = 0
    with fleet_files() as (certs, tmp), ExitStack() as stack:
        router = free_endpoint("tls")
        stack.callback(stop_child, start_lupin(["router", "--listen", router, "--certs", str(certs)], "listening on"))
        env = {"LUPIN_LINK__COMMAND_TIMEOUT": "8", "LUPIN_HISTORY__URL": "none"}
        for name in robots:
            stack.callback(stop_child, start_lupin(["serve", "--robot", name, "--connect", router, "--certs", str(certs),
                                                    "--runs", str(tmp / name)], f"robot {name!r}", env))
        console = FleetLink(router, clock=time.monotonic, tls=member_files(certs, "ops"), timeout=STOP_WITHIN_S)
        stack.callback(console.close)
        peer = LinkClient(router, "r1", clock=time.monotonic, tls=member_files(certs, "r2"), timeout=STOP_WITHIN_S)
        stack.callback(peer.close)  # r2's certificate: may stop, may not release
        if not _wait(lambda: console.robots() == robots and all(console.client(r).view().connected for r in robots), 60):
            _stderr(f"fleet.soak: only {console.robots()} up after 60 s; every stop is tried anyway")
        end, k = time.perf_counter() + SOAK_S, 0
        while time.perf_counter() < end:
            how = ("peer", "console", "fleet")[k % 3]
            target = robots[k % len(robots)]
            k += 1
            t0 = time.perf_counter()
            if how == "peer":
                err, targets = peer.stop(), ["r1"]
            elif how == "console":
                err, targets = console.client(target).send("estop", engaged=True), [target]
            else:
                answered = console.stop_fleet()
                err, targets = (None if answered == robots else f"answered {answered}"), robots
            for r in targets:
                attempted += 1
                if err is not None:
                    lost.append(f"{how} stop of {r}: {err}")
                elif _wait(lambda: console.client(r).view().estop_engaged, STOP_WITHIN_S):
                    times.append((time.perf_counter() - t0) * 1000.0)
                else:
                    lost.append(f"{how} stop of {r}: not engaged in its telemetry within {STOP_WITHIN_S:g} s")
            for r in targets:
                if console.client(r).send("estop", engaged=False) is not None:
                    lost.append(f"release of {r} refused")
            for r in targets:  # released in its telemetry before the next stop is timed
                if not _wait(lambda: not console.client(r).view().estop_engaged, STOP_WITHIN_S):
                    lost.append(f"release of {r}: still engaged in its telemetry after {STOP_WITHIN_S:g} s")
            time.sleep(max(0.0, SOAK_EVERY_S - (time.perf_counter() - t0)))
    for m in lost:
        _stderr(f"fleet.soak: LOST {m}")
    return Sample(times, {"attempted": attempted, "engaged": len(times), "lost": len(lost), "soak_s": SOAK_S,
                          "robots": len(robots), "losses": lost[:20]})
