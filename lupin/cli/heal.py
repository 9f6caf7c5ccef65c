"""`lupin heal [--backend sim|hw]`: the boot one-shot (spec/cli.md, mission/runtime/heal.py).

Exit 0 healed and homed, 1 when a controller did not reach active (or the arm did not park),
0 with a loud message when the controller states could not be read at all; with
``LUPIN_AUTO_HOME=false`` nothing is done and the exit is 0.

On the sim the boot race is simulated: each of the five controllers comes up broken (missing,
unconfigured or inactive) with even odds, at least one always, drawn from the sim seed, through
the sim's own fault hook, and the heal repairs them. ``--backend hw`` runs on the hardware
backend when ``hw.backend`` provides one.
"""
from __future__ import annotations

import importlib
import importlib.util
import os
import sys
from typing import Optional

import numpy as np
import typer

from hw.controller_manager import ControllerManager, ControllerState
from hw.errors import InputError
from lupin.cli.backend import Backend, announce, backend_option, resolve_backend
from mission.runtime.config import LupinConfig
from mission.runtime.heal import AUTO_HOME_ENV, HealReport, auto_home_enabled, boot_heal

BROKEN = (ControllerState.MISSING, ControllerState.UNCONFIGURED, ControllerState.INACTIVE)


def sim_boot_race(names: tuple[str, ...], seed: int) -> dict[str, ControllerState]:
    """Which controllers the simulated cold boot breaks, and how (deterministic per seed)."""
    rng = np.random.default_rng([seed, 0x4EA1])
    race = {n: BROKEN[int(rng.integers(len(BROKEN)))] for n in names if rng.random() < 0.5}
    if not race:
        race[names[int(rng.integers(len(names)))]] = BROKEN[int(rng.integers(len(BROKEN)))]
    return race


def _sim_runtime(config: LupinConfig):
    from mission.runtime.sim_runtime import start_sim_runtime
    from sim.world import load_default_world

    rt = start_sim_runtime(load_default_world(), config)
    for name, state in sim_boot_race(tuple(config.hw.controllers), config.sim.seed).items():
        rt.sim.faults.controller_race([name], state.value)
    return rt.robot, rt.close


def _hw_runtime(config: LupinConfig):
    """The robot on real devices (hw.backend opens them; a missing device is an InputError)."""
    if importlib.util.find_spec("hw.backend") is None:
        raise InputError("lupin heal --backend hw: hardware backend not available (no hw.backend)")
    backend_cls = getattr(importlib.import_module("hw.backend"), "HwBackend", None)
    if backend_cls is None:
        raise InputError("lupin heal --backend hw: hardware backend not available (hw.backend has no HwBackend)")
    from mission.runtime.robot import build_robot

    backend = backend_cls(config.hw)
    robot = build_robot(config, backend.hal, ControllerManager(config.hw.controllers))
    robot.start()
    return robot, backend.close


def print_report(report: HealReport) -> None:
    for name, state in report.before.items():
        acts = [a for n, a in report.actions if n == name]
        after = report.after.get(name)
        line = f"{name:<34} {state.value:<12}"
        if acts:
            line += f" {' -> '.join(acts)}"
        if after is not None:
            line += f"  => {after.value}"
        typer.echo(line)
    if report.healed is None and not report.skipped:
        bar = "!" * 72
        print(f"{bar}\n{report.message}\n{bar}", file=sys.stderr)
    elif report.exit_code:
        print(f"lupin heal: {report.message}", file=sys.stderr)
    else:
        typer.echo(report.message)


def heal(
    ctx: typer.Context,
    backend: Optional[Backend] = backend_option(),
) -> int:
    """Heal the five controllers to active, then park the arm at home (boot one-shot)."""
    from lupin.cli.sim import run_config

    if not auto_home_enabled(os.environ):
        typer.echo(f"{AUTO_HOME_ENV}=false: heal and home skipped")
        raise typer.Exit(0)
    config = run_config(ctx)
    backend = resolve_backend(backend, config)
    announce("heal", backend)
    robot, close = (_sim_runtime if backend is Backend.sim else _hw_runtime)(config)
    try:
        report = boot_heal(robot, os.environ)
    finally:
        close()
    print_report(report)
    raise typer.Exit(report.exit_code)
