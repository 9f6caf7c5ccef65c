"""`lupin map ...`: save a SLAM map in map_server format, and look at a saved one."""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from hw.errors import InputError
from lupin.cli.sim import run_config, world_or_default
from mission.runtime.config import with_seed

map_app = typer.Typer(help="SLAM maps in map_server format (YAML + PGM).", no_args_is_help=True)


def summary(m) -> str:
    occ = m.occupancy
    n = occ.size
    free, occupied = int(((occ >= 0) & (occ <= 25)).sum()), int(((occ >= 65) & (occ <= 100)).sum())
    unknown = n - free - occupied
    return (f"{m.width} x {m.height} cells ({m.width * m.resolution:.2f} x {m.height * m.resolution:.2f} m) at "
            f"{m.resolution:g} m, origin ({m.origin_x:g}, {m.origin_y:g}, {m.origin_yaw:g}); "
            f"free {free} ({100 * free / n:.1f} %), occupied {occupied} ({100 * occupied / n:.1f} %), "
            f"unknown {unknown} ({100 * unknown / n:.1f} %)")


def _yaml_output(path: Path) -> Path:
    if path.suffix.lower() not in (".yaml", ".yml"):
        raise InputError(f"-o {path}: a map is written as NAME.yaml (with NAME.pgm beside it)")
    return path


@map_app.command("show")
def show(
    map_file: Path = typer.Argument(..., help="A map_server YAML file."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Render the map to this PNG."),
) -> None:
    """Print what a saved map holds; with -o, render it (free white, occupied black, unknown grey)."""
    from hw.atomic_file import write_png
    from nav.map_io import load_map
    from nav.map_render import render_map

    if output is not None:
        if output.suffix.lower() != ".png":
            raise InputError(f"-o {output}: must be a .png file")
        if not output.parent.is_dir():
            raise InputError(f"-o {output}: directory {output.parent} does not exist")
    m = load_map(map_file)
    print(f"{map_file}: {summary(m)}")
    if output is not None:
        write_png(output, render_map(m))
        print(f"wrote {output}")


@map_app.command("save")
def save(
    ctx: typer.Context,
    output: Path = typer.Option(..., "-o", "--output", help="NAME.yaml to write (NAME.pgm beside it)."),
    world: Optional[Path] = typer.Option(None, "--world", help="World file to map (default: the built-in greenhouse)."),
    seed: Optional[int] = typer.Option(None, "--seed", help="Sim seed (overrides config)."),
    connect: Optional[str] = typer.Option(None, "--connect", help="Save the SLAM map of a running lupin serve at this endpoint instead."),
) -> None:
    """Map the simulated greenhouse with SLAM (a survey: every pot's approach pose, then home)
    and save the map; its frame is the robot's start pose, as a patrol's. With --connect, save
    the map a running runtime holds now (as its link sends it)."""
    from mission.jobs.slam_drive import map_world
    from nav.map_io import save_map

    _yaml_output(output)
    if connect is not None and (world is not None or seed is not None):
        raise InputError("lupin map save --connect: --world and --seed are for mapping the sim here")
    if not output.parent.exists():
        output.parent.mkdir(parents=True)
    if connect is not None:
        m = map_over_link(connect, run_config(ctx).link.robot)
        print(f"{save_map(m.cropped(), output)}: {summary(m.cropped())}")
        return
    config = run_config(ctx) if seed is None else with_seed(run_config(ctx), seed)
    mapped = map_world(world_or_default(world), config)
    path = save_map(mapped.occupancy.cropped(), output)
    failed = [o for o in mapped.outcomes if o != "succeeded"]
    print(f"mapped in {mapped.sim_time_s:.1f} s sim: {mapped.keyframes} keyframes, {mapped.loop_closures} loop closures"
          + (f", {len(failed)} survey goals not reached" if failed else ""))
    print(f"{path}: {summary(mapped.occupancy.cropped())}")
    if failed:
        raise typer.Exit(1)


LINK_MAP_WAIT = 15.0
"""Seconds to wait for the map over the link: a full map frame comes at least every 10 s."""


def map_over_link(endpoint: str, robot: str):
    """The SLAM map a running runtime publishes, as an ``OccupancyMap`` (reading telemetry needs
    no token)."""
    import time

    from mission.link.client import LinkClient
    from mission.link.server import check_endpoint
    from nav.occupancy import OccupancyMap

    client = LinkClient(check_endpoint(endpoint, "--connect"), robot, clock=time.monotonic)
    try:
        end = time.monotonic() + LINK_MAP_WAIT
        while time.monotonic() < end:
            g = client.view().grid
            if g is not None:
                return OccupancyMap(g.data.copy(), g.resolution, g.origin_x, g.origin_y)
            time.sleep(0.1)
    finally:
        client.close()
    raise InputError(f"--connect {endpoint}: no map from robot {robot!r} within {LINK_MAP_WAIT:g} s "
                     "(is lupin serve running there, and mapping?)")
