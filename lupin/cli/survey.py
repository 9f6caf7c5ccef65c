"""`lupin survey`: explore a greenhouse from the dock, find every pot by its tag, and write the
mission (one pot per tag, pose from the tag), the map and the survey's report."""
from __future__ import annotations

import sys
import time
from pathlib import Path
from typing import Optional

import typer

from hw.errors import InputError
from lupin.cli.backend import Backend, announce, backend_option, resolve_backend
from lupin.cli.sim import run_config, world_or_default

DEFAULT_DIR = Path("lupin-survey")


def _output(path: Path, suffixes: tuple[str, ...], what: str, option: str) -> Path:
    if path.suffix.lower() not in suffixes:
        raise InputError(f"{option} {path}: {what} must be a {' or '.join(suffixes)} file")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"{option} {path}: cannot create {path.parent}: {exc.strerror}") from None
    return path


def survey(
    ctx: typer.Context,
    world: Optional[Path] = typer.Option(None, "--world", help="World file for the sim (default: the built-in "
                                         "greenhouse); only builds the sim, the survey never reads its pots."),
    backend: Optional[Backend] = backend_option(),
    output: Path = typer.Option(DEFAULT_DIR / "mission.yaml", "-o", "--output", help="The mission file to write."),
    map_out: Path = typer.Option(DEFAULT_DIR / "map.yaml", "--map-out", help="The map to write (map_server YAML + PGM)."),
    report: Path = typer.Option(DEFAULT_DIR / "survey.json", "--report", help="The survey's report (JSON); "
                                "survey.png beside it."),
) -> None:
    """Explore a greenhouse from the dock and write the mission of the pots it finds by their tags."""
    from mission.jobs.survey import run_to_end, start_hw_survey, write_survey

    config = run_config(ctx)
    backend = resolve_backend(backend, config)
    paths = [_output(output, (".yaml", ".yml"), "the mission", "-o"), _output(map_out, (".yaml", ".yml"), "a map", "--map-out"),
             _output(report, (".json",), "the report", "--report")]
    if backend is Backend.hw:
        if world is not None:
            raise InputError("lupin survey --backend hw: --world is for the sim (the robot surveys its real greenhouse)")
        announce("survey", backend)
        run, name = start_hw_survey(config), "greenhouse-survey"
    else:
        from mission.jobs.sim_survey import start_sim_survey

        w = world_or_default(world)
        announce("survey", backend, w)
        (run, _), name = start_sim_survey(w, config), f"{w.name}-survey"
    t0 = time.perf_counter()
    live = _Progress() if sys.stdout.isatty() else None
    try:
        run_to_end(run, live or (lambda r: None))
    finally:
        if live is not None:
            live.stop()
    try:
        doc = write_survey(run, *paths, name, time.perf_counter() - t0)
    finally:
        run.close()
    print(f"{name}: {doc['pots_found']} pots found by their tags, {doc['explored_m2']:.0f} m2 explored, "
          f"{doc['robot_time_s']:.0f} s robot time ({doc['robot_time_s'] / max(doc['pots_found'], 1):.1f} s a pot), "
          f"{doc['distance_m']:.1f} m driven, {doc['wall_time_s']:.0f} s wall; {doc['ended']}")
    print(f"mission: {output}\nmap: {map_out}\nreport: {report}")
    if doc["pots_found"] == 0:
        raise typer.Exit(1)


class _Progress:
    """A status line: the phase, frontiers driven, looks, pots found, robot and wall time."""

    def __init__(self):
        from rich.console import Console
        from rich.live import Live

        self.wall0 = time.perf_counter()
        self.live = Live(console=Console(), refresh_per_second=8, transient=True)
        self.live.start()

    def __call__(self, run) -> None:
        self.live.update(f"{run.phase.value:<13} frontiers {run.frontiers_driven:<3} looks {run.looked}/{len(run.looks):<4} "
                         f"pots found {len(run.sightings.by_tag):<4} {run.now - run.t0:7.1f} s robot  "
                         f"{time.perf_counter() - self.wall0:6.1f} s wall")

    def stop(self) -> None:
        self.live.stop()
