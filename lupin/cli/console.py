"""`lupin console`: the operator console (Textual) on a robot's link.

``--connect ENDPOINT`` attaches to a running ``lupin serve``; ``--sim`` starts one (a child
process running the simulated greenhouse in real time, on a free loopback port, with a fresh
token) and attaches to it: the one-command demo. Closing the console never stops the robot's
mission; with ``--sim`` the child service is stopped with the console (SIGTERM: a running
patrol is finished ``aborted``). ``--as NAME`` makes it a fleet's console (spec/fleet.md): the
endpoint is the fleet's router, ``--certs DIR`` holds NAME's certificate for a ``tls/`` one, and
every robot that is up is listed, keys 1-9 switch between them, ``E`` stops them all.
``--gamepad /dev/input/eventN`` drives the robot shown from a pad on this machine, dead-man held
(``tui.gamepad``).
"""
from __future__ import annotations

import errno
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
    gamepad: Optional[Path] = typer.Option(None, "--gamepad", metavar="DEVICE",
                                           help="Drive with a gamepad on this machine (Linux evdev, e.g. "
                                                "/dev/input/event5): left bumper held, sticks drive."),
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
                          token if token is not None else config.link.token, gamepad)
        return
    if certs is not None:
        raise InputError("lupin console --certs: say who this console is with --as NAME")
    fd = open_gamepad(gamepad)  # before a child service starts: a pad that cannot be read starts nothing
    child = None
    if sim:
        child, endpoint, token = start_child_service(world)
    else:
        endpoint = check_endpoint(connect, "--connect")
        token = token if token is not None else config.link.token
    client = LinkClient(endpoint, config.link.robot, clock=time.monotonic, token=token)
    try:
        run_with_gamepad(make_app(client.view, client), client, fd)
    finally:
        client.close()
        if child is not None:
            stop_child(child)


def open_gamepad(path: Path | None) -> int | None:
    """The pad's event device, opened (InputError naming it when it cannot be read)."""
    if path is None:
        return None
    try:
        return os.open(path, os.O_RDONLY | os.O_NONBLOCK)
    except OSError as exc:
        hint = " (is this user in the 'input' group?)" if exc.errno == errno.EACCES else ""
        raise InputError(f"--gamepad {path}: cannot read it: {exc.strerror}{hint}") from None


def run_with_gamepad(app, commands, fd: int | None) -> None:
    """Run the console app, the pad (if any) driving through ``commands`` as long as it runs."""
    from tui.gamepad import Gamepad
    from tui.messages import CommandRefused

    pad = Gamepad(fd, commands.send, lambda reason: app.post_message(CommandRefused("teleop", reason))).start() \
        if fd is not None else None
    try:
        app.run()
    finally:
        if pad is not None:
            pad.close()
            os.close(fd)


def run_fleet_console(endpoint: str, name: str, certs: Path | None, token: str, gamepad: Path | None = None) -> None:
    from fleet.certs import check_name
    from lupin.cli.fleet import tls_for
    from mission.link.fleet_link import FleetLink
    from tui.fleet_app import FleetConsoleApp

    tls = tls_for(certs, check_name(name, "--as"), endpoint)
    fd = open_gamepad(gamepad)
    fleet = FleetLink(endpoint, clock=time.monotonic, tls=tls, token=token)
    try:
        run_with_gamepad(FleetConsoleApp(fleet), fleet, fd)
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
