"""`lupin sim ...`: generate worlds, drive a route, render snapshots."""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path
from typing import Optional

import typer

from hw.atomic_file import write_atomic
from hw.errors import InputError
from mission.runtime.config import LupinConfig, load_config, save_config, with_seed
from mission.jobs.route import ROUTES

sim_app = typer.Typer(help="The simulated greenhouse.", no_args_is_help=True)


def run_config(ctx: typer.Context) -> LupinConfig:
    """The validated config of this invocation (--config file + LUPIN_* environment)."""
    obj = ctx.find_root().obj or {}
    return load_config(obj.get("config_path"))


def world_or_default(path: Optional[Path]):
    from sim.world import load_default_world, load_world

    return load_default_world() if path is None else load_world(path)


def parse_pose(text: str, option: str = "--pose") -> tuple[float, float, float]:
    """'X,Y,YAW' in metres and radians, world frame."""
    parts = text.split(",")
    try:
        x, y, yaw = (float(p) for p in parts)
    except ValueError:
        raise InputError(f"{option} {text!r}: expected X,Y,YAW (metres, metres, radians), e.g. 1.0,0.5,0") from None
    if not all(math.isfinite(v) for v in (x, y, yaw)):
        raise InputError(f"{option} {text!r}: values must be finite numbers")
    return x, y, yaw


def _png_output(path: Path, what: str) -> Path:
    if path.suffix.lower() != ".png":
        raise InputError(f"{path}: {what} must be a .png file")
    if not path.parent.is_dir():
        raise InputError(f"{path}: directory {path.parent} does not exist")
    return path


@sim_app.command("generate")
def generate(
    rows: int = typer.Option(..., "--rows", help="Rows of pots."),
    pots_per_row: int = typer.Option(..., "--pots-per-row", help="Pots in each row."),
    seed: int = typer.Option(..., "--seed", help="Random seed (same seed, same world)."),
    bays: int = typer.Option(1, "--bays", help="Bays side by side, each ROWS x POTS-PER-ROW, behind divider walls with doorways."),
    walkers: int = typer.Option(0, "--walkers", help="People walking the aisles."),
    robots: int = typer.Option(1, "--robots", help="A fleet's robots: one dock each at the aisles' west ends (spawns:)."),
    output: Optional[Path] = typer.Option(None, "-o", "--output", help="Write here instead of stdout."),
) -> None:
    """Write a generated world file: rows of pots with ~0.8 m aisles (in bays, with --bays; people in the aisles, with --walkers; a dock per robot, with --robots)."""
    from sim.generate import generate_world
    from sim.world import dump_world

    try:
        text = dump_world(generate_world(rows, pots_per_row, seed, bays=bays, walkers=walkers, robots=robots))
    except ValueError as exc:
        raise InputError(f"sim generate: {exc}") from None
    if output is None:
        sys.stdout.write(text)
        return
    try:
        write_atomic(output, text.encode())
    except OSError as exc:
        raise InputError(f"cannot write {output}: {exc.strerror}") from None
    print(f"wrote {output}")


@sim_app.command("drive")
def drive(
    ctx: typer.Context,
    world: Optional[Path] = typer.Option(None, "--world", help="World file (default: the built-in greenhouse)."),
    route: str = typer.Option("tour", "--route", help=f"Route: {', '.join(ROUTES)}."),
    seed: Optional[int] = typer.Option(None, "--seed", help="Sim seed (overrides config)."),
    out: Path = typer.Option(Path("lupin-drive"), "--out", help="Directory for drive.json and config.yaml."),
) -> None:
    """Drive a scripted route and print wheel odometry against the sim's ground truth."""
    if route not in ROUTES:
        raise InputError(f"--route {route!r}: unknown route; known: {', '.join(ROUTES)}")
    config = run_config(ctx) if seed is None else with_seed(run_config(ctx), seed)
    w = world_or_default(world)
    from mission.jobs.drive import drive as run_drive
    from mission.jobs.drive_report import format_results, results_json

    run = run_drive(w, config, route)
    try:
        print(format_results(run))
        out.mkdir(parents=True, exist_ok=True)
        save_config(config, out)
        write_atomic(out / "drive.json", json.dumps(results_json(run), indent=2).encode())
    finally:
        run.close()  # the sim and its temporary state directory
    if run.held:
        print(f"route {route!r} stopped: {run.held}", file=sys.stderr)
        raise typer.Exit(1)
    if not run.driver.done:
        print(f"route {route!r} did not finish within the time limit", file=sys.stderr)
        raise typer.Exit(1)


@sim_app.command("snapshot")
def snapshot(
    ctx: typer.Context,
    output: Path = typer.Option(..., "-o", "--output", help="PNG file to write."),
    world: Optional[Path] = typer.Option(None, "--world", help="World file (default: the built-in greenhouse)."),
    pose: Optional[str] = typer.Option(None, "--pose", help="Robot pose X,Y,YAW in the world frame (default: spawn)."),
    camera: str = typer.Option("front", "--camera", help="front | wrist | overview"),
) -> None:
    """Render a camera with the robot at a pose (arm at the patrol's inspect pose for the wrist camera) to PNG."""
    if camera not in ("front", "wrist", "overview"):
        raise InputError(f"--camera {camera!r}: expected front, wrist or overview")
    xyyaw = parse_pose(pose) if pose is not None else None
    _png_output(output, "snapshot output")
    from hw.atomic_file import write_png
    from sim.snapshot import render_snapshot

    config = run_config(ctx)
    from arm.presets import preset

    arm = preset(config.patrol.inspect_pose) if camera == "wrist" else None
    image = render_snapshot(world_or_default(world), config.sim, config.hw, camera, xyyaw, arm)
    write_png(output, image)
    print(f"wrote {output} ({image.shape[1]}x{image.shape[0]}, {camera} camera)")


@sim_app.command("navigate")
def navigate(
    ctx: typer.Context,
    to: str = typer.Option(..., "--to", help="Goal X,Y,YAW in the world frame (metres, radians)."),
    world: Optional[Path] = typer.Option(None, "--world", help="World file (default: the built-in greenhouse)."),
    seed: Optional[int] = typer.Option(None, "--seed", help="Sim seed (overrides config)."),
    timeout: Optional[float] = typer.Option(None, "--timeout", help="Seconds of sim time for the goal (default: config)."),
    picture: Optional[Path] = typer.Option(None, "--picture", help="Draw costmap, plan and driven path to this PNG."),
    as_json: bool = typer.Option(False, "--json", help="Print one JSON object with the outcome."),
) -> None:
    """Navigate from the spawn pose to a goal through the whole navigation stack."""
    import time

    from hw.odometry import Pose2D
    from mission.jobs.navigate import start_navigate
    from hw.atomic_file import write_png
    from mission.jobs.nav_picture import draw_navigation
    from sim.world_checks import robot_circle_problems

    goal = Pose2D(*parse_pose(to, "--to"))
    if timeout is not None and not (math.isfinite(timeout) and timeout > 0):
        raise InputError(f"--timeout {timeout}: must be a positive number of seconds")
    if picture is not None:
        _png_output(picture, "--picture")
    config = run_config(ctx) if seed is None else with_seed(run_config(ctx), seed)
    w = world_or_default(world)
    problems = robot_circle_problems(w, goal.x, goal.y, config.sim.geometry.pot_radius, config.nav.costmap.robot_radius)
    if problems:
        raise InputError(f"--to {to}: bad goal, the robot there{problems[0]}")

    run = start_navigate(w, config)
    tty = sys.stdout.isatty() and not as_json

    def progress(r) -> None:
        fb = r.nav.feedback(r.now)
        print(f"  t {r.now:6.1f} s  {fb.state.value:<10} {fb.distance_remaining:5.2f} m to go", flush=True)

    t0 = time.perf_counter()
    try:
        outcome = run.go(goal, timeout, progress if tty else None)
        wall = time.perf_counter() - t0
        xy, yaw = run.truth_error(goal)
        result = {"outcome": outcome, "reason": run.nav.reason, "sim_time_s": round(run.now, 2),
                  "wall_time_s": round(wall, 2), "distance_m": round(run.distance, 3),
                  "truth_error": {"xy": round(xy, 4), "yaw": round(yaw, 4)}}
        if picture is not None:
            write_png(picture, draw_navigation(run.nav.global_costmap.grid, run.plans,
                                            [run.to_map(p) for p in run.odom_path],
                                            [run.to_map(p) for p in run.truth_path], run.to_map(goal),
                                            config.nav.goal_checker.xy_tolerance))
    finally:
        run.close()
    if as_json:
        print(json.dumps(result))
    else:
        why = f" ({result['reason']})" if result["reason"] else ""
        print(f"{outcome}{why}: {result['sim_time_s']:.1f} s sim, {wall:.1f} s wall, {run.distance:.2f} m driven; "
              f"truth error {xy:.3f} m, {math.degrees(yaw):.1f} deg")
        if run.bumps:
            print(f"bumped into: {', '.join(run.bumps)}")
        if picture is not None:
            print(f"wrote {picture}")
    if outcome != "succeeded":
        raise typer.Exit(1)
