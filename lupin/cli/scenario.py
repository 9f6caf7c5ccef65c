"""`lupin scenario run FILE... [--json]`: scenario files (spec/scenario.md) in the sim.

Every file, and every world, mission and events list it names, is read and checked before the
first one runs: one bad file is exit 2 with its file, entry and field named, and nothing moved.
Then each runs in turn and prints each expectation with pass or fail and, for a failure, what
was expected and what happened (``--json``: one object per scenario per line, with the e-stop
figures and each event's fired time and effect). Each run's report
directory is ``--out/<scenario name>/``. Exit 0 when every expectation held, else 1.
"""
from __future__ import annotations

import json
import re
from pathlib import Path

import typer

from lupin.cli.sim import run_config

scenario_app = typer.Typer(help="Scenario files: a simulated patrol with scripted events and the outcome it must have.",
                           no_args_is_help=True)

DEFAULT_OUT = Path("lupin-scenarios")


def report_dir(out: Path, name: str) -> Path:
    """A directory named after the scenario (anything but letters, digits, '-', '_' and '.'
    becomes '_', so a name cannot climb out of ``out``)."""
    return out / (re.sub(r"[^A-Za-z0-9._-]", "_", name).lstrip(".") or "scenario")


@scenario_app.command("run")
def run(
    ctx: typer.Context,
    files: list[Path] = typer.Argument(..., help="Scenario files (YAML)."),
    as_json: bool = typer.Option(False, "--json", help="One JSON object per scenario per line."),
    out: Path = typer.Option(DEFAULT_OUT, "--out", help="Each scenario's report goes in OUT/<name>/."),
) -> None:
    """Run scenario files and print pass / fail per expectation."""
    from fleet.scenario_runner import run_any
    from mission.scenario.scenario_file import load_scenario

    config = run_config(ctx)
    scenarios = [load_scenario(f, config) for f in files]  # all checked before any runs
    failed = 0
    for s in scenarios:
        result = run_any(s, report_dir(out, s.name))
        failed += not result.passed
        if as_json:
            print(json.dumps(result.as_json()), flush=True)
        else:
            print(f"{s.name}: {'PASS' if result.passed else 'FAIL'} ({result.sim_time_s:.1f} s sim, "
                  f"{result.wall_time_s:.1f} s wall)  report: {result.report}")
            print("\n".join(c.line() for c in result.checks), flush=True)
    if not as_json and len(scenarios) > 1:
        print(f"{len(scenarios) - failed} of {len(scenarios)} scenarios passed")
    if failed:
        raise typer.Exit(1)
