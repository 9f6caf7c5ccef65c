"""`lupin mission ...`: the mission that patrols every pot of a world (``from-world``), and a
mission brought up to date from a patrol's report (``update``)."""
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
