"""`lupin web`: the grower's web dashboard (spec/web.md), served by uvicorn.

``lupin web [--history URL] [--runs DIR] [--listen HOST:PORT] [--open]`` serves it (default
``127.0.0.1:8080``); ``lupin web --set-password`` stores the password it asks for (from the
terminal, twice; or one line on stdin when it is not a terminal). Without a password it refuses
to start, unless ``--open`` on a loopback address, where only this machine reaches it.
"""
from __future__ import annotations

import getpass
import ipaddress
import sys
from pathlib import Path
from typing import Optional

import typer

from hw.errors import InputError
from lupin.cli.history import HISTORY_HELP, open_for_reading
from lupin.cli.sim import run_config

DEFAULT_LISTEN = "127.0.0.1:8080"


def parse_listen(text: str) -> tuple[str, int]:
    """``HOST:PORT`` (``[::1]:8080`` for IPv6) as (host, port); InputError naming --listen."""
    host, sep, port = text.strip().rpartition(":")
    host = host[1:-1] if host.startswith("[") and host.endswith("]") else host
    if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise InputError(f"--listen {text}: give HOST:PORT, e.g. 127.0.0.1:8080 or 0.0.0.0:8080")
    return host, int(port)


def is_loopback(host: str) -> bool:
    if host == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def password_file(config) -> Path:
    """``web-password`` in the runtime's state directory (the robot's, ``/var/lib/lupin``, or
    ``$XDG_STATE_HOME/lupin``): where it outlives the process, as the soft stop's latch does."""
    from mission.runtime.state_dir import default_hw_state_dir
    from web.auth import FILE

    base = Path(config.runtime.state_dir) if config.runtime.state_dir is not None else default_hw_state_dir()
    return base / FILE


def _ask_password() -> str:
    if not sys.stdin.isatty():
        return sys.stdin.readline().rstrip("\r\n")
    first = getpass.getpass("dashboard password: ")
    if getpass.getpass("again: ") != first:
        raise InputError("--set-password: the two passwords differ; nothing stored")
    return first


def web(
    ctx: typer.Context,
    history: Optional[str] = typer.Option(None, "--history", metavar="URL", help=HISTORY_HELP),
    runs: Optional[Path] = typer.Option(None, "--runs", metavar="DIR",
                                        help="Where the patrols' report directories are, when not where the history "
                                             "says (lupin serve --runs)."),
    listen: str = typer.Option(DEFAULT_LISTEN, "--listen", metavar="HOST:PORT", help="Where to serve it."),
    open_: bool = typer.Option(False, "--open", help="No password (only on a loopback address: 127.0.0.1)."),
    set_password: bool = typer.Option(False, "--set-password", help="Store the dashboard's password (hashed) and exit."),
) -> None:
    """The grower's web dashboard: the greenhouse's pest map, each pot over time with its
    pictures, the patrols, alerts and CSV, read-only, in a browser."""
    from web.auth import Sessions, set_password as store, stored_hash

    config = run_config(ctx)
    secret = password_file(config)
    if set_password:
        store(secret, _ask_password())
        print(f"lupin web: password stored (scrypt, salted) in {secret}")
        return
    host, port = parse_listen(listen)
    if runs is not None and not runs.is_dir():
        raise InputError(f"--runs {runs}: not a directory")
    if open_ and not is_loopback(host):
        raise InputError(f"--open --listen {listen}: a dashboard without a password listens on 127.0.0.1 only "
                         f"(set one with lupin web --set-password to serve the farm network)")
    stored = None if open_ else stored_hash(secret)
    if not open_ and stored is None:
        raise InputError(f"lupin web: no password set ({secret}): run lupin web --set-password, "
                         f"or --open on 127.0.0.1")
    store_ = open_for_reading(ctx, history)
    import uvicorn

    from web.app import freeze_heap, make_app

    app = make_app(store_, runs, Sessions(stored))
    freeze_heap()
    shown = f"[{host}]" if ":" in host else host
    print(f"lupin web: http://{shown}:{port}/ (history {store_.shown}"
          f"{f', reports also under {runs}' if runs else ''}; {'open' if open_ else 'password'}; ctrl+c stops)",
          flush=True)
    try:
        uvicorn.run(app, host=host, port=port, log_level="warning", access_log=False)
    finally:
        store_.close()
