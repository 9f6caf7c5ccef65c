"""`lupin history ...`: the patrol history (spec/history.md) as a grower asks it.

``patrols`` (newest first), ``pot ID`` (one pot's timeline), ``changes`` (between the last two
patrols of a mission), ``pests`` (pest pressure over the last N patrols; ``-o FILE.png`` draws
it on the map), ``export --csv DIR``; ``status`` (where the history is, whether it answers, what
waits in the robot's spool) and ``sync`` (send the spool now). Human-readable by default,
``--json`` for tools: one JSON document on stdout. The history is ``--history URL`` or
``history.url``; a database that is not there, not a history, or newer than this Lupin is exit 2
with one line. ``pot``, ``changes`` and ``pests`` compare within one greenhouse (the latest
patrol's: its sim world, or the robot's) unless ``--all``.
"""
from __future__ import annotations

import json
from pathlib import Path
from typing import Optional

import typer

from hw.errors import InputError
from lupin.cli.sim import run_config

history_app = typer.Typer(help="The patrol history: patrols, a pot's timeline, changes, pests, export.",
                          no_args_is_help=True)

HISTORY_HELP = "The history database: a SQLite file or postgresql://user@host/db (default: history.url)."
MISSION_HELP = "Only this mission's patrols (default: the mission of the latest patrol)."
ALL_HELP = ("Compare across every greenhouse: sim worlds and the robot's patrols together (default: only the "
            "latest patrol's greenhouse).")


def every_option():
    return typer.Option(False, "--all", help=ALL_HELP)


def open_for_reading(ctx: typer.Context, url: Optional[str]):
    """The history to read: exit 2 when it is off, missing, or not usable."""
    from mission.history.store import open_history

    config = run_config(ctx)
    option = "--history" if url is not None else "history.url"
    store = open_history(url if url is not None else config.history.url, option, create=False,
                         connect_timeout=config.history.connect_timeout)
    if store is None:
        raise InputError(f"{option} none: the history is off; give --history URL to read one")
    return store


def _check_mission(store, mission: Optional[str]) -> None:
    if mission is None:
        return
    from mission.history.queries import missions

    with store.reading() as conn:
        known = missions(conn)
    if mission not in known:
        raise InputError(f"--mission {mission}: no patrol of it in {store.shown} "
                         f"(missions: {', '.join(known[:10]) or 'none'})")


def _print_json(data) -> None:
    print(json.dumps(data, indent=2))


def _when(t) -> str:
    from mission.history.records import as_utc

    return "-" if t is None else as_utc(t).strftime("%Y-%m-%d %H:%M")


@history_app.command("patrols")
def patrols(
    ctx: typer.Context,
    history: Optional[str] = typer.Option(None, "--history", metavar="URL", help=HISTORY_HELP),
    mission: Optional[str] = typer.Option(None, "--mission", help="Only this mission's patrols."),
    robot: Optional[str] = typer.Option(None, "--robot", help="Only this robot's patrols."),
    limit: int = typer.Option(20, "--limit", min=1, help="At most this many, newest first."),
    as_json: bool = typer.Option(False, "--json", help="One JSON document."),
) -> None:
    """The patrols recorded, newest first: when, which robot and mission, how it ended, pots, pests."""
    store = open_for_reading(ctx, history)
    _check_mission(store, mission)
    rows = store.patrols(mission, robot, limit)
    if as_json:
        _print_json({"database": store.shown, "patrols": [p.as_json() for p in rows]})
        return
    if not rows:
        print(f"no patrols recorded in {store.shown}")
        return
    print(f"{'id':>5}  {'started (UTC)':<16}  {'robot':<10} {'mission':<24} {'outcome':<11} {'pots':>9} {'pests':>5} "
          f"{'distance':>9}")
    for p in rows:
        pots = f"{p.observed}/{p.pots}" if p.pots is not None else f"{p.observed}"
        outcome = p.outcome or ("running" if p.ended_at is None else "-")
        dist = f"{p.distance_m:.1f} m" if p.distance_m is not None else "-"
        print(f"{p.id:>5}  {_when(p.started_at):<16}  {p.robot[:10]:<10} {p.mission[:24]:<24} {outcome:<11} "
              f"{pots:>9} {p.pests:>5} {dist:>9}")


@history_app.command("pot")
def pot(
    ctx: typer.Context,
    pot_id: str = typer.Argument(..., metavar="ID", help="The pot's id, as its missions name it (e.g. P04)."),
    history: Optional[str] = typer.Option(None, "--history", metavar="URL", help=HISTORY_HELP),
    mission: Optional[str] = typer.Option(None, "--mission", help="Only this mission's patrols (default: all)."),
    every: bool = every_option(),
    as_json: bool = typer.Option(False, "--json", help="One JSON document."),
) -> None:
    """One pot's timeline, oldest first: flower colour, blooms, pest and anomalies, with dates
    (in the greenhouse of its latest observation unless --all)."""
    store = open_for_reading(ctx, history)
    _check_mission(store, mission)
    rows = store.pot_timeline(pot_id, mission, every)
    if not rows:
        known = store.pots_known(mission)
        raise InputError(f"pot {pot_id}: not in {store.shown}{f' (mission {mission})' if mission else ''} "
                         f"(pots: {', '.join(known) or 'none'}{', ...' if len(known) >= 20 else ''})")
    if as_json:
        _print_json({"database": store.shown, "pot": pot_id, "timeline": [r.as_json() for r in rows]})
        return
    print(f"pot {pot_id}: {len(rows)} observation(s) in {store.shown}")
    print(f"{'observed (UTC)':<16}  {'patrol':>6}  {'status':<9} {'flower':<6} {'blooms':>6} {'pest':<4}  anomalies")
    for r in rows:
        o = r.observation
        pest = "-" if o.bug is None else ("YES" if o.bug else "no")
        blooms = "-" if o.blooms is None else str(o.blooms)
        print(f"{_when(o.observed_at):<16}  {r.patrol:>6}  {o.status:<9} {o.flower_color or '-':<6} {blooms:>6} "
              f"{pest:<4}  {', '.join(o.anomalies) or '-'}")


@history_app.command("changes")
def changes(
    ctx: typer.Context,
    history: Optional[str] = typer.Option(None, "--history", metavar="URL", help=HISTORY_HELP),
    mission: Optional[str] = typer.Option(None, "--mission", help=MISSION_HELP),
    every: bool = every_option(),
    as_json: bool = typer.Option(False, "--json", help="One JSON document."),
) -> None:
    """What changed between the last two patrols of a mission in one greenhouse: new and cleared
    pests, colour and bloom-count changes, newly failed pots. Only what changed."""
    store = open_for_reading(ctx, history)
    _check_mission(store, mission)
    cs = store.changes(mission, every)
    if as_json:
        _print_json({"database": store.shown, **cs.as_json()})
        return
    if cs.after is None:
        print(f"no patrols recorded in {store.shown}")
        return
    if cs.before is None:
        print(f"{cs.after.mission}: only one patrol ({cs.after.id}, {_when(cs.after.started_at)}): nothing to compare")
        return
    print(f"{cs.after.mission}: patrol {cs.before.id} ({_when(cs.before.started_at)}) -> patrol {cs.after.id} "
          f"({_when(cs.after.started_at)}): {len(cs.changes) or 'no'} change(s)")
    for c in cs.changes:
        print(f"  {c.pot:<8} {c.kind:<13} {c.detail}")


@history_app.command("pests")
def pests(
    ctx: typer.Context,
    history: Optional[str] = typer.Option(None, "--history", metavar="URL", help=HISTORY_HELP),
    mission: Optional[str] = typer.Option(None, "--mission", help=MISSION_HELP),
    last: int = typer.Option(10, "--last", min=1, help="Over the last N patrols of the mission."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Also draw the pest map to this PNG file."),
    every: bool = every_option(),
    as_json: bool = typer.Option(False, "--json", help="One JSON document."),
) -> None:
    """Pest pressure per pot over the last N patrols (how often a pest was seen, the current
    streak); with -o, the map with each pot shaded by it, so a spread is visible."""
    if output is not None and output.suffix.lower() != ".png":
        raise InputError(f"-o {output}: must name a .png file")
    store = open_for_reading(ctx, history)
    _check_mission(store, mission)
    pm = store.pest_map(last, mission, every)
    if output is not None:
        from hw.atomic_file import write_png
        from mission.history.pest_map import draw_pests, saved_map

        background = saved_map(pm.patrols[0].report_path) if pm.patrols else None
        try:
            output.parent.mkdir(parents=True, exist_ok=True)
            write_png(output, draw_pests(pm, background))
        except OSError as exc:
            raise InputError(f"-o {output}: cannot write: {exc.strerror}") from None
    if as_json:
        _print_json({"database": store.shown, "last": last, **pm.as_json(),
                     "picture": str(output) if output is not None else None})
        return
    if not pm.patrols:
        print(f"no patrols recorded in {store.shown}")
        return
    hit = sorted((p for p in pm.pots if p.pests), key=lambda p: (-p.pressure, -p.streak, p.pot_id))
    print(f"{pm.mission}: {len(hit)} of {len(pm.pots)} pots with a pest in the last {len(pm.patrols)} patrol(s) "
          f"({_when(pm.patrols[-1].started_at)} .. {_when(pm.patrols[0].started_at)})")
    if hit:
        print(f"  {'pot':<8} {'pests':>7} {'pressure':>8} {'streak':>6}")
    for p in hit:
        print(f"  {p.pot_id:<8} {f'{p.pests}/{p.observed}':>7} {p.pressure:>8.2f} {p.streak:>6}")
    if output is not None:
        plain = not pm.patrols or saved_map(pm.patrols[0].report_path) is None
        print(f"wrote {output}{' (no saved map: a plain plot)' if plain else ''}")


@history_app.command("export")
def export(
    ctx: typer.Context,
    csv_dir: Path = typer.Option(..., "--csv", metavar="DIR", help="Write patrols.csv and observations.csv here."),
    history: Optional[str] = typer.Option(None, "--history", metavar="URL", help=HISTORY_HELP),
    mission: Optional[str] = typer.Option(None, "--mission", help="Only this mission's patrols (default: all)."),
    as_json: bool = typer.Option(False, "--json", help="Say what was written as one JSON document."),
) -> None:
    """Export the history as CSV files (the tables' columns, ISO 8601 UTC times)."""
    from mission.history.export import export_csv

    if csv_dir.exists() and not csv_dir.is_dir():
        raise InputError(f"--csv {csv_dir}: is a file (give a directory)")
    store = open_for_reading(ctx, history)
    _check_mission(store, mission)
    try:
        counts = export_csv(store, csv_dir, mission)
    except OSError as exc:
        raise InputError(f"--csv {csv_dir}: cannot write: {exc.strerror}") from None
    if as_json:
        _print_json({"database": store.shown, "directory": str(csv_dir), "rows": counts})
        return
    for name, n in counts.items():
        print(f"wrote {csv_dir / name} ({n} rows)")


NO_SPOOL = "none (a sim run without runtime.state_dir keeps its spool in memory)"


def _spool(config):
    """The spool of this machine's runtime: ``history.spool`` in the state directory of
    ``runtime.backend`` (the robot's fixed one, or ``runtime.state_dir``); a sim without one
    keeps its spool in memory, so there is none to read here."""
    from mission.history.spool import runtime_spool

    return runtime_spool(config.runtime, config.runtime.backend)


def _target(ctx: typer.Context, url: Optional[str]):
    config = run_config(ctx)
    option = "--history" if url is not None else "history.url"
    url = url if url is not None else config.history.url
    from mission.history.url import parse_history_url

    if parse_history_url(url, option) is None:
        raise InputError(f"{option} none: the history is off; give --history URL")
    return config, url, option


@history_app.command("status")
def status(
    ctx: typer.Context,
    history: Optional[str] = typer.Option(None, "--history", metavar="URL", help=HISTORY_HELP),
    as_json: bool = typer.Option(False, "--json", help="One JSON document."),
) -> None:
    """Where the history is, whether it answers now, and how many rows wait in the local spool
    (what the robot recorded while the database did not answer)."""
    from mission.history.store import open_history

    config, url, option = _target(ctx, history)
    spool = _spool(config)
    try:
        store = open_history(url, option, create=False, connect_timeout=config.history.connect_timeout, spool=spool)
        shown, why = store.shown, store.outbox.down or store.reachable()
        store.close()
    except InputError as exc:  # a local file not there (yet), or one that is not a history
        from mission.history.url import parse_history_url

        shown, why = parse_history_url(url, option).shown, str(exc).split(": ", 1)[-1]
    waiting, rows, others = spool.count(shown), spool.rows(shown), {
        db: n for db, n in spool.databases().items() if db != shown}
    spool.close()
    if as_json:
        _print_json({"database": shown, "reachable": why is None, "reason": why,
                     "spool": None if spool.path is None else str(spool.path),
                     "waiting": waiting, "rows_waiting": rows, "other_databases": others})
        return
    print(f"history: {shown}")
    print(f"reachable: {'yes' if why is None else f'no ({why})'}")
    print(f"spool: {spool.path or NO_SPOOL}: {rows} row(s) waiting ({waiting} write(s))")
    for db, n in others.items():
        print(f"  also {n} write(s) waiting for {db} (another database: lupin history sync --history URL)")


@history_app.command("sync")
def sync(
    ctx: typer.Context,
    history: Optional[str] = typer.Option(None, "--history", metavar="URL", help=HISTORY_HELP),
    as_json: bool = typer.Option(False, "--json", help="One JSON document."),
) -> None:
    """Send what waits in the local spool to the database now, in order (a resend is a no-op).
    Exit 0 when the spool is empty after it, 1 when the database did not take everything."""
    from mission.history.store import open_history

    config, url, option = _target(ctx, history)
    spool = _spool(config)
    store = open_history(url, option, connect_timeout=config.history.connect_timeout, spool=spool)
    left = store.outbox.flush()
    sent, why = store.outbox.delivered, store.outbox.down
    store.close()
    spool.close()
    if as_json:
        _print_json({"database": store.shown, "sent_rows": sent, "waiting": left, "reason": why})
    else:
        print(f"history {store.shown}: {sent} row(s) sent from {spool.path or NO_SPOOL}; "
              + ("nothing waits" if not left else f"{left} write(s) still wait ({why})"))
    if left:
        raise typer.Exit(1)
