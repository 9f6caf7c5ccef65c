"""`lupin mission from-world WORLD [-o FILE]`: the mission that patrols every pot of a world."""
from __future__ import annotations

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

    text = dump_mission(mission_from_world(load_world(world)))
    if output is None:
        print(text, end="")
        return
    try:
        output.parent.mkdir(parents=True, exist_ok=True)
        write_atomic(output, text.encode())
    except OSError as exc:
        raise InputError(f"-o {output}: cannot write: {exc.strerror}") from None
    print(f"wrote {output}")
