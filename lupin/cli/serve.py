"""`lupin serve`: the runtime as a long-running service that consoles attach to over Zenoh.

``--backend sim`` (the default unless the config's ``runtime.backend`` says ``hw``) runs the simulated greenhouse at wall-clock pace; ``--backend hw``
the robot's devices. ``--listen ENDPOINT`` (default ``link.listen``) is where consoles connect;
no multicast scouting. The operator token is ``link.token`` or, when that is empty, a random
one printed at start-up. In a fleet, ``--robot NAME --connect ENDPOINT`` joins the fleet's
router as a client instead (spec/fleet.md): keys under ``lupin/NAME/``, a liveliness token, and
with ``--certs DIR`` (a ``tls/`` router) mutual TLS as NAME and no operator token: the router's
access control lets only consoles command it. Ctrl-C or SIGTERM stops it cleanly (a running patrol is finished
``aborted``, its report written).
"""
from __future__ import annotations

import logging
import secrets
import signal
import threading
import time
from pathlib import Path
from typing import Optional

import typer

from hw.errors import InputError
from lupin.cli.backend import Backend, announce, backend_option, resolve_backend
from lupin.cli.sim import run_config, world_or_default
from mission.runtime.config import with_overrides

DEFAULT_RUNS = Path("lupin-runs")


def serve(
    ctx: typer.Context,
    backend: Optional[Backend] = backend_option("sim (MuJoCo greenhouse, real time) or hw (the robot)"),
    world: Optional[Path] = typer.Option(None, "--world", help="World file for the sim (default: the built-in greenhouse)."),
    listen: Optional[str] = typer.Option(None, "--listen", help="Zenoh endpoint to listen on, e.g. tcp/0.0.0.0:7447 (default: link.listen)."),
    robot: Optional[str] = typer.Option(None, "--robot", help="The robot's name in the fleet (default: link.robot)."),
    connect: Optional[str] = typer.Option(None, "--connect", help="Join the fleet's router at this endpoint, e.g. "
                                                                  "tls/192.168.1.2:7447, instead of listening."),
    certs: Optional[Path] = typer.Option(None, "--certs", help="With a tls/ --connect: the fleet's certificates "
                                                               "(lupin fleet certs -o DIR); this robot's are ROBOT.pem/.key."),
    runs: Path = typer.Option(DEFAULT_RUNS, "--runs", help="Each patrol's report goes to RUNS/<mission>-<k>/."),
    fast: bool = typer.Option(False, "--fast", help="Sim only: run as fast as the machine allows instead of real time."),
    foxglove: Optional[int] = typer.Option(None, "--foxglove", min=0, max=65535,
                                           help="Also serve the robot live to Foxglove on this WebSocket port (8765 when "
                                                "given without one; 0: any free port)."),
    history: Optional[str] = typer.Option(None, "--history", metavar="URL",
                                          help="Record every patrol in this history (spec/history.md): a SQLite file, "
                                               "postgresql://user@host/db, or none (default: history.url)."),
    no_collision_monitor: bool = typer.Option(False, "--no-collision-monitor",
                                              help="hw only: run without the collision monitor (logged at ERROR every "
                                                   "minute, a red chip on every console); a config turning it off is "
                                                   "refused on the robot without this."),
) -> None:
    """Run the robot runtime as a service that consoles attach to."""
    from lupin.cli.patrol import open_patrol_history
    from mission.jobs.serve import run_service, start_hw_service
    from lupin.cli.fleet import tls_for
    from mission.link.server import LinkServer, check_endpoint

    config = run_config(ctx)
    if robot is not None:
        from fleet.certs import check_name

        config = with_overrides(config, {"link": {"robot": check_name(robot, "--robot")}})
    backend = resolve_backend(backend, config)
    if connect is not None and listen is not None:
        raise InputError("lupin serve: give --listen (a robot alone) or --connect (a fleet's router), not both")
    check_endpoint(connect or listen or config.link.listen, "--connect" if connect else "--listen")
    if certs is not None and connect is None:
        raise InputError("lupin serve: --certs goes with --connect tls/... (the fleet's router)")
    tls = tls_for(certs, config.link.robot, connect) if connect is not None else None
    if backend is Backend.hw and (world is not None or fast):
        raise InputError("lupin serve --backend hw: --world and --fast are for the sim")
    if backend is Backend.sim and no_collision_monitor:
        raise InputError("lupin serve: --no-collision-monitor is for the robot (--backend hw); in the sim set "
                         "hw.collision_monitor.enabled: false in the config")
    if backend is Backend.sim:
        world_file = world_or_default(world)  # checked before anything starts
    announce("serve", backend, world_file if backend is Backend.sim else None)
    store = open_patrol_history(config, history)
    if backend is Backend.hw:
        service = start_hw_service(config, runs, time.perf_counter, store, monitor_off=no_collision_monitor)
    else:
        from mission.jobs.sim_serve import start_sim_service  # the robot's service never loads the simulator

        config = with_overrides(config, {"sim": {"realtime": not fast}})
        service = start_sim_service(world_file, config, runs, time.perf_counter, store)
    token = None if tls is not None else config.link.token or secrets.token_urlsafe(12)
    try:
        server = LinkServer(service, config.link, token, listen, connect=connect, tls=tls)
    except BaseException:
        service.close()
        raise
    logging.getLogger().setLevel(min(logging.getLogger().level, logging.INFO))
    how = "through the router at" if connect else "on"
    print(f"lupin serve: robot {config.link.robot!r} {how} {server.endpoint}"
          f"{'' if config.link.token or token is None else f'; operator token {token}'}", flush=True)
    print(f"lupin serve: patrols recorded in {store.shown if store is not None else 'no history (--history none)'}",
          flush=True)
    on_close = server.close
    if foxglove is not None:
        from mission.record.live import serve_foxglove

        try:
            live = serve_foxglove(service, foxglove)
        except Exception as exc:
            server.close()
            service.close()
            raise InputError(f"--foxglove {foxglove}: cannot serve there: {exc}") from None
        service.on_run.append(lambda run: live.channels.follow(run.tree if run is not None else None))
        print(f"lupin serve: Foxglove on ws://127.0.0.1:{live.port}", flush=True)

        def on_close() -> None:
            live.stop()
            server.close()
    stop = threading.Event()
    previous = {s: signal.signal(s, lambda *_: stop.set()) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        run_service(service, stop, on_close)
    finally:
        for s, handler in previous.items():
            signal.signal(s, handler)
    print("lupin serve: stopped", flush=True)
