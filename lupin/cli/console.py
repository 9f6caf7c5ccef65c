"""`lupin console`: the operator console (Textual) on a robot's link.

``--connect ENDPOINT`` attaches to a running ``lupin serve``; ``--sim`` starts one (a child
process running the simulated greenhouse in real time, on a free loopback port, with a fresh
token) and attaches to it: the one-command demo. Closing the console never stops the robot's
mission; with ``--sim`` the child service is stopped with the console (SIGTERM: a running
patrol is finished ``aborted``). ``--as NAME`` makes it a fleet's console (spec/fleet.md): the
endpoint is the fleet's router, ``--certs DIR`` holds NAME's certificate for a ``tls/`` one, and
every robot that is up is listed, keys 1-9 switch between them, ``E`` stops them all.
"""
from __future__ import annotations

import os
import secrets
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Optional

import typer

from hw.errors import InputError
from lupin.cli.sim import run_config
from mission.link.server import free_endpoint

def console(
    ctx: typer.Context,
    sim: bool = typer.Option(False, "--sim", help="Start a simulated robot (lupin serve) for the console."),
    world: Optional[Path] = typer.Option(None, "--world", help="With --sim: the world file (default: the built-in greenhouse)."),
    connect: Optional[str] = typer.Option(None, "--connect", help="Endpoint of a running lupin serve, e.g. tcp/192.168.1.20:7447."),
    token: Optional[str] = typer.Option(None, "--token", help="Operator token (default: link.token, LUPIN_LINK__TOKEN)."),
    certs: Optional[Path] = typer.Option(None, "--certs", help="With --as and a tls/ router: the fleet's certificates."),
    as_name: Optional[str] = typer.Option(None, "--as", help="A fleet's console: this console's name in the fleet "
                                                             "(its certificate's); --connect is then the router."),
) -> None:
    """The operator console."""
    from mission.link.client import LinkClient
    from mission.link.server import check_endpoint
    from tui.app import make_app

    config = run_config(ctx)
    if sim == (connect is not None):
        raise InputError("lupin console: give exactly one of --sim or --connect ENDPOINT")
    if world is not None and not sim:
        raise InputError("lupin console: --world goes with --sim")
    if (certs is not None or as_name is not None) and connect is None:
        raise InputError("lupin console: --as and --certs go with --connect (the fleet's router)")
    if as_name is not None:
        run_fleet_console(check_endpoint(connect, "--connect"), as_name, certs,
                          token if token is not None else config.link.token)
        return
    if certs is not None:
        raise InputError("lupin console --certs: say who this console is with --as NAME")
    child = None
    if sim:
        child, endpoint, token = start_child_service(world)
    else:
        endpoint = check_endpoint(connect, "--connect")
        token = token if token is not None else config.link.token
    client = LinkClient(endpoint, config.link.robot, clock=time.monotonic, token=token)
    try:
        make_app(client.view, client).run()
    finally:
        client.close()
        if child is not None:
            stop_child(child)


def run_fleet_console(endpoint: str, name: str, certs: Path | None, token: str) -> None:
    from fleet.certs import check_name
    from lupin.cli.fleet import tls_for
    from mission.link.fleet_link import FleetLink
    from tui.fleet_app import FleetConsoleApp

    tls = tls_for(certs, check_name(name, "--as"), endpoint)
    fleet = FleetLink(endpoint, clock=time.monotonic, tls=tls, token=token)
    try:
        FleetConsoleApp(fleet).run()
    finally:
        fleet.close()


def start_child_service(world: Path | None) -> tuple[subprocess.Popen, str, str]:
    """``lupin serve`` as a child on a free loopback port with a fresh token; returns once it
    listens (its first line), else InputError with what it said."""
    endpoint, token = free_endpoint(), secrets.token_urlsafe(12)
    lupin = str(Path(sys.executable).parent / "lupin")
    args = [lupin, "serve", "--listen", endpoint] + (["--world", str(world)] if world is not None else [])
    env = {**os.environ, "LUPIN_LINK__TOKEN": token}
    # its log goes to a file, never a pipe nobody drains (a full pipe would stall the robot)
    log = tempfile.NamedTemporaryFile("w+", prefix="lupin-serve-", suffix=".log", delete=False)
    child = subprocess.Popen(args, stdout=subprocess.PIPE, stderr=log, env=env, text=True)
    line = child.stdout.readline()  # "lupin serve: sim backend, world ...", then "... on ENDPOINT" once it listens
    if line.startswith("lupin serve: sim backend"):
        line = child.stdout.readline()
    if endpoint not in line:
        stop_child(child)
        log.seek(0)
        err = log.read().strip().splitlines()
        raise InputError(f"lupin console --sim: the sim service did not start: {err[-1] if err else line.strip()}")
    return child, endpoint, token


def stop_child(child: subprocess.Popen) -> None:
    if child.poll() is None:
        child.send_signal(signal.SIGTERM)
        try:
            child.wait(timeout=30)
        except subprocess.TimeoutExpired:
            child.kill()
    deadline = time.monotonic() + 1.0
    while child.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
