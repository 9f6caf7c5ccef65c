"""`lupin mission ...`: the mission that patrols every pot of a world (``from-world``), a
mission brought up to date from a patrol's report (``update``), the pots a patrol left undone
(``resume``), and a directed re-scouting mission from the patrol history (``rescout``)."""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Optional

import typer

from hw.errors import InputError
from hw.atomic_file import write_atomic

mission_app = typer.Typer(help="Patrol mission files (spec/mission.md).", no_args_is_help=True)


@mission_app.command("from-world")
def from_world(
    world: Path = typer.Argument(..., help="World file (spec/world.md)."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Write here instead of stdout."),
) -> None:
    """Write the mission that patrols every pot of WORLD, in the map frame of a robot starting
    at the world's spawn pose."""
    from mission.patrol.mission_file import dump_mission, mission_from_world
    from sim.world import load_world

    _write(dump_mission(mission_from_world(load_world(world))), output)


@mission_app.command("update")
def update(
    mission: Path = typer.Argument(..., help="The mission file the patrol ran."),
    report: Path = typer.Option(..., "--report", help="The patrol's report.json."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Write here instead of stdout."),
) -> None:
    """Write MISSION with every pot the report found moved at its measured pose and every tag it
    discovered added as a new pot, flagged for review."""
    from mission.patrol.mission_file import load_mission
    from mission.patrol.mission_update import read_report, update_mission

    result = update_mission(load_mission(mission), read_report(report), str(report))
    _write(result.text(), output)
    print(f"{len(result.moved)} moved ({', '.join(result.moved) or 'none'}), {len(result.added)} added for review "
          f"({', '.join(result.added) or 'none'})", file=sys.stderr if output is None else sys.stdout)


@mission_app.command("resume")
def resume(
    report: Path = typer.Argument(..., help="The report.json of a patrol that ended early."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Write here instead of stdout."),
) -> None:
    """Write the mission of the pots REPORT left undone (skipped, or never reached), in the
    shortest order, from the mission written beside it."""
    from mission.patrol.mission_file import dump_mission
    from mission.patrol.mission_resume import resume_mission

    mission = resume_mission(report)
    _write(dump_mission(mission), output)
    print(f"{len(mission.pots)} pot(s) left undone: {_some(tuple(p.id for p in mission.pots))}",
          file=sys.stderr if output is None else sys.stdout)


@mission_app.command("rescout")
def rescout(
    ctx: typer.Context,
    history: Optional[str] = typer.Option(None, "--history", metavar="URL",
                                          help="The history database (default: history.url)."),
    last: int = typer.Option(3, "--last", min=1, help="Pots with a pest in any of the last N patrols."),
    radius: float = typer.Option(1.0, "--radius", min=0.0, help="Plus every pot within R metres of one, m."),
    mission: Optional[str] = typer.Option(None, "--mission", help="Of this mission's patrols (default: the latest "
                                          "patrol's mission)."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Write here instead of stdout."),
    every: bool = typer.Option(False, "--all", help="Over the patrols of every greenhouse (default: only the latest "
                               "patrol's: its sim world, or the robot's)."),
) -> None:
    """Write a directed re-scouting mission: the pots with a pest in the last N patrols and their
    neighbours within R metres, in the shortest order. Exit 1 when no pot had a pest."""
    import math

    from lupin.cli.history import _check_mission, open_for_reading
    from mission.history.rescout import rescout as make_rescout
    from mission.patrol.mission_file import dump_mission

    if not math.isfinite(radius):
        raise InputError(f"--radius {radius}: must be a finite number of metres")
    store = open_for_reading(ctx, history)
    _check_mission(store, mission)
    pests = store.pest_map(last, mission, every)
    if not pests.patrols:
        raise InputError(f"{store.shown}: no patrols recorded: nothing to re-scout from")
    plan = make_rescout(pests, radius)
    say = sys.stderr if output is None else sys.stdout
    if plan is None:
        print(f"{pests.mission}: no pest in the last {len(pests.patrols)} patrol(s): nothing to re-scout",
              file=sys.stderr)
        raise typer.Exit(1)
    _write(dump_mission(plan.mission), output)
    print(f"{plan.mission.name}: {len(plan.mission.pots)} pots: {len(plan.pests)} with a pest in the last "
          f"{len(pests.patrols)} patrol(s) ({_some(plan.pests)}), {len(plan.neighbours)} within {radius:g} m "
          f"({_some(plan.neighbours)})", file=say)


def _some(ids: tuple[str, ...], most: int = 12) -> str:
    """Pot ids for a line of output: the first ``most``, then how many more."""
    if not ids:
        return "none"
    return ", ".join(ids[:most]) + (f" and {len(ids) - most} more" if len(ids) > most else "")


def _write(text: str, output: Optional[Path]) -> None:
    if output is None:
        print(text, end="")
        return
    try:
        output.parent.mkdir(parents=True, exist_ok=True)
        write_atomic(output, text.encode())
    except OSError as exc:
        raise InputError(f"-o {output}: cannot write: {exc.strerror}") from None
    print(f"wrote {output}")
