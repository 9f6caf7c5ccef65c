"""`lupin fleet certs` and `lupin router`: a fleet's certificates and its Zenoh router (spec/fleet.md).

``fleet certs`` makes the authority and one key and certificate per robot, console, the router
and the dispatcher (``fleet.certs``). ``router`` runs zenoh's router mode with the fleet's TLS
and access control (``fleet.router``) until Ctrl-C or SIGTERM; ``--no-tls`` (plain TCP, no
access control: anyone on the network may command any robot) is for a bench on one machine
and says so on every start. ``fleet sim`` runs such a router in-process with robots r1..rN in
one simulated greenhouse (``mission.jobs.fleet_sim``), each joined to it under its own name.
"""
from __future__ import annotations

import json
import logging
import signal
import sys
import threading
import time
from pathlib import Path
from typing import Optional

import typer

from hw.errors import InputError

fleet_app = typer.Typer(help="A fleet of robots: certificates (and, next, a simulated fleet and a fleet patrol).",
                        no_args_is_help=True)


def _names(text: str) -> list[str]:
    return [n.strip() for n in text.split(",") if n.strip()] if text else []


@fleet_app.command("certs")
def certs(
    robots: str = typer.Option("", "--robots", help="Robot names, comma-separated, e.g. r1,r2,r3."),
    consoles: str = typer.Option("", "--consoles", help="Console names, comma-separated, e.g. ops,laptop."),
    out: Path = typer.Option(..., "-o", "--out", help="Directory for ca.pem and each NAME.pem / NAME.key."),
    router_hosts: str = typer.Option("", "--router-hosts",
                                     help="Names or addresses the router is reached by besides localhost and "
                                          "127.0.0.1, comma-separated (its certificate must carry them)."),
) -> None:
    """Make the fleet's certificate authority and a key and certificate per member."""
    from fleet.certs import make_fleet

    names = make_fleet(out, _names(robots), _names(consoles),
                       router_hosts=tuple(_names(router_hosts)))
    print(f"lupin fleet certs: {out}/ca.pem and a key and certificate for {', '.join(names)} "
          f"(keys owner-only; ca.key makes new members: keep it off the robots)")


def tls_for(certs: Path | None, name: str, endpoint: str, option: str = "--certs"):
    """``name``'s TLS files for ``endpoint``: required for ``tls/``, refused for plain ones."""
    from fleet.certs import member_files

    if endpoint.startswith("tls/"):
        if certs is None:
            raise InputError(f"{endpoint}: a tls/ endpoint needs the fleet's certificates ({option} DIR)")
        return member_files(certs, name, option)
    if certs is not None:
        raise InputError(f"{option} {certs}: {endpoint} is not a tls/ endpoint (certificates go with tls/...)")
    return None


def router_options(listen: str | None, certs: Path | None, no_tls: bool, who: str):
    """The router's endpoint, its TLS files and the fleet's members from the options (``--no-tls``:
    plain TCP, no access control, said loudly on stderr; the default endpoint on 0.0.0.0:7447)."""
    from fleet.members import read_members
    from fleet.router import DEFAULT_LISTEN
    from mission.link.session import check_endpoint

    endpoint = check_endpoint(listen or (DEFAULT_LISTEN.replace("tls/", "tcp/") if no_tls else DEFAULT_LISTEN), "--listen")
    if no_tls:
        if endpoint.startswith("tls/") or certs is not None:
            raise InputError(f"{who} --no-tls: no --certs and no tls/ endpoint with it")
        print(f"{who}: WARNING --no-tls: plain TCP and NO access control; anyone who reaches "
              f"{endpoint} can read and command every robot. A bench on one machine only.", file=sys.stderr, flush=True)
        return endpoint, None, None
    if not endpoint.startswith("tls/"):
        raise InputError(f"{who} --listen {endpoint}: the router serves tls/ (or give --no-tls)")
    if certs is None:
        raise InputError(f"{who}: give --certs DIR (lupin fleet certs -o DIR), or --no-tls for a bench")
    members = read_members(certs)
    return endpoint, tls_for(certs, "router", endpoint), members


def router(
    listen: Optional[str] = typer.Option(None, "--listen", help="Endpoint to listen on (default tls/0.0.0.0:7447)."),
    certs: Optional[Path] = typer.Option(None, "--certs", help="The fleet's certificates (lupin fleet certs -o DIR)."),
    no_tls: bool = typer.Option(False, "--no-tls", help="Plain TCP, no access control: a bench on one machine only."),
    write_config: Optional[Path] = typer.Option(None, "--write-config", metavar="FILE",
                                                help="Write the router's config as JSON (for zenohd -c FILE) and exit."),
) -> None:
    """The fleet's Zenoh router: TLS with mutual authentication and access control by name."""
    from fleet.router import open_router, router_settings

    endpoint, tls, members = router_options(listen, certs, no_tls, "lupin router")
    if write_config is not None:
        try:
            write_config.write_text(json.dumps(router_settings(endpoint, tls, members), indent=2) + "\n")
        except OSError as exc:
            raise InputError(f"--write-config {write_config}: cannot write it: {exc.strerror}") from None
        print(f"lupin router: config for zenohd in {write_config} (zenohd -c {write_config})")
        return
    session = open_router(endpoint, tls, members)
    if members is not None:
        print(f"lupin router: robots {', '.join(members.robots) or '(none)'}; consoles "
              f"{', '.join(members.consoles) or '(none)'}", flush=True)
    print(f"lupin router: listening on {endpoint}", flush=True)
    stop = threading.Event()
    previous = {s: signal.signal(s, lambda *_: stop.set()) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        while not stop.wait(0.2):  # a timed wait: the signal may land on one of zenoh's threads, which
            pass                   # would not wake a main thread blocked for good (its handler runs here)
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
        session.close()
    print("lupin router: stopped", flush=True)


@fleet_app.command("sim")
def fleet_sim(
    ctx: typer.Context,
    robots: int = typer.Option(..., "--robots", min=1, max=9, help="How many robots, named r1..rN."),
    world: Optional[Path] = typer.Option(None, "--world", help="World file with a spawn per robot (spawns:); default: "
                                                              "a generated greenhouse with one dock per robot."),
    listen: Optional[str] = typer.Option(None, "--listen", help="The router's endpoint (default tls/0.0.0.0:7447)."),
    fast: bool = typer.Option(False, "--fast", help="Run as fast as the machine allows instead of real time."),
    certs: Optional[Path] = typer.Option(None, "--certs", help="The fleet's certificates, with r1..rN among its robots."),
    no_tls: bool = typer.Option(False, "--no-tls", help="Plain TCP, no access control: a bench on one machine only."),
    runs: Path = typer.Option(Path("lupin-runs"), "--runs", help="Robot R's patrols go to RUNS/R/<mission>-<k>/."),
    history: Optional[str] = typer.Option(None, "--history", metavar="URL",
                                          help="Record every patrol here (default: history.url); none: nowhere."),
) -> None:
    """N simulated robots in one greenhouse, each a runtime joined to an in-process router."""
    from fleet.router import open_router
    from lupin.cli.patrol import open_patrol_history
    from lupin.cli.sim import run_config, world_or_default
    from mission.jobs.fleet_sim import fleet_world, robot_config, run_fleet, start_fleet_sim
    from mission.runtime.config import with_overrides

    config = with_overrides(run_config(ctx), {"sim": {"realtime": not fast}})
    endpoint, tls, members = router_options(listen, certs, no_tls, "lupin fleet sim")
    names = [f"r{k}" for k in range(1, robots + 1)]
    missing = [n for n in names if members is not None and n not in members.robots]
    if missing:
        raise InputError(f"--certs {certs}: no robot {', '.join(missing)} in its fleet (lupin fleet certs --robots "
                         f"{','.join(names)} -o DIR)")
    robot_tls = {n: tls_for(certs, n, endpoint) for n in names}
    w = fleet_world(robots) if world is None else world_or_default(world)
    if len(w.spawn_poses) < robots:
        raise InputError(f"--world {world}: {robots} robots need {robots} spawns, it has {len(w.spawn_poses)} "
                         f"(spawns: in spec/world.md; lupin sim generate --robots {robots} writes them)")
    stores = {n: open_patrol_history(robot_config(config, n), history) for n in names}
    router_session = open_router(endpoint, tls, members)
    try:
        fleet = start_fleet_sim(w, config, names, runs, time.perf_counter, stores.get)
        try:  # with certificates no operator token: the router's access control says who commands
            fleet.join(endpoint.replace("0.0.0.0", "127.0.0.1"), robot_tls.get, None if tls else config.link.token or None)
        except BaseException:
            fleet.close()
            raise
        logging.getLogger().setLevel(min(logging.getLogger().level, logging.INFO))  # consoles get INFO, as from serve
        print(f"lupin fleet sim: {w.name}: robots {', '.join(names)} through the router on {endpoint}"
              f"{' (fast)' if fast else ''}", flush=True)
        store = stores[names[0]]
        print(f"lupin fleet sim: each robot's patrols in {runs}/<robot>/, recorded in "
              f"{store.shown + ' under its name' if store is not None else 'no history (--history none)'}", flush=True)
        stop = threading.Event()
        previous = {s: signal.signal(s, lambda *_: stop.set()) for s in (signal.SIGINT, signal.SIGTERM)}
        try:
            run_fleet(fleet, stop)
        finally:
            for s, handler in previous.items():
                signal.signal(s, handler)
    finally:
        router_session.close()
    print("lupin fleet sim: stopped", flush=True)


@fleet_app.command("patrol")
def fleet_patrol(
    ctx: typer.Context,
    mission: Path = typer.Option(..., "--mission", help="The mission (spec/mission.md), in the first dock's map frame."),
    robots: Optional[str] = typer.Option(None, "--robots", help="Only these robots, comma-separated; each must be up."),
    connect: Optional[str] = typer.Option(None, "--connect", help="The router (default tls/127.0.0.1:7447)."),
    certs: Optional[Path] = typer.Option(None, "--certs", help="The fleet's certificates; the dispatcher's are dispatcher.pem/.key."),
    no_tls: bool = typer.Option(False, "--no-tls", help="Plain TCP to a --no-tls router: a bench on one machine only."),
    report: Path = typer.Option(Path("lupin-fleet"), "--report", help="Directory for each robot's report, fleet.json, fleet.png."),
    world: Optional[Path] = typer.Option(None, "--world", help="The sim world: its spawns are the docks, its plan the map."),
    map_path: Optional[Path] = typer.Option(None, "--map", help="A saved map in the mission's frame to split on (a farm)."),
) -> None:
    """Split a mission's pots between the robots up, send each its part, follow them, hand a lost one's pots over."""
    from fleet.dispatcher import DispatchError
    from fleet.fleet_patrol import fleet_patrol as run, read_inputs, robots_option
    from lupin.cli.sim import run_config
    from mission.link.session import check_endpoint

    endpoint = check_endpoint(connect or ("tcp/127.0.0.1:7447" if no_tls else "tls/127.0.0.1:7447"), "--connect")
    if no_tls and (certs is not None or endpoint.startswith("tls/")):
        raise InputError("lupin fleet patrol --no-tls: no --certs and no tls/ endpoint with it")
    if not no_tls and not endpoint.startswith("tls/"):
        raise InputError(f"lupin fleet patrol --connect {endpoint}: the router serves tls/ (or give --no-tls)")
    if no_tls:
        print("lupin fleet patrol: WARNING --no-tls: plain TCP, no access control", file=sys.stderr, flush=True)
    tls = None if no_tls else tls_for(certs, "dispatcher", endpoint)
    config = run_config(ctx)
    inputs = read_inputs(mission, world, map_path, config)
    try:
        summary = run(inputs, endpoint, tls, robots_option(robots), report, config,
                      lambda line: print(f"lupin fleet patrol: {line}", flush=True))
    except DispatchError as exc:  # a robot up that would not take its part: the job failed, not the input
        print(f"lupin fleet patrol: {exc}", file=sys.stderr, flush=True)
        raise typer.Exit(1) from None
    pots = summary["pots"]
    print(f"lupin fleet patrol: {'complete' if summary['complete'] else 'INCOMPLETE'}, {pots['inspected']}/{pots['total']} "
          f"pots inspected by {len(summary['robots'])} robots, makespan {summary['makespan_s']:.1f} s robot time "
          f"({report}/fleet.json)", flush=True)
    if not summary["complete"]:
        raise typer.Exit(1)
