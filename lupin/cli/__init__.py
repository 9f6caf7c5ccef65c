"""The `lupin` command (spec/cli.md): one console script, every subcommand has --help.

Exit codes: 0 success, 1 the job ran and failed, 2 bad input (unreadable or invalid file,
unknown option, unreachable device) with a one-line message on stderr and no traceback.
Subcommand groups live in their own modules; this file only wires them and maps errors.
"""
from __future__ import annotations

import logging
import sys
from pathlib import Path
from typing import Optional

import typer

try:  # typer >= 0.26 vendors click; older releases depend on it
    from typer._click import exceptions as cx
except ImportError:  # pragma: no cover
    import click.exceptions as cx

from hw.errors import InputError
from hw.interfaces import DeviceError
from lupin import bench as bench_mod
from lupin.cli.detect import detect
from lupin.cli.fleet import fleet_app, router
from lupin.cli.heal import heal
from lupin.cli.history import history_app
from lupin.cli.hw import hw_app
from lupin.cli.map import map_app
from lupin.cli.mission import mission_app
from lupin.cli.patrol import patrol
from lupin.cli.scenario import scenario_app
from lupin.cli.console import console
from lupin.cli.serve import serve
from lupin.cli.sim import run_config, sim_app
from lupin.cli.survey import survey
from lupin.cli.web import web

app = typer.Typer(
    name="lupin",
    help="Lupin: a greenhouse patrol robot (MIRTE Master V2), on hardware or in a MuJoCo greenhouse.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)
app.add_typer(sim_app, name="sim")
app.add_typer(hw_app, name="hw")
app.add_typer(map_app, name="map")
app.add_typer(mission_app, name="mission")
app.add_typer(history_app, name="history")
app.add_typer(scenario_app, name="scenario")
app.add_typer(fleet_app, name="fleet")
app.command("detect")(detect)
app.command("heal")(heal)
app.command("patrol")(patrol)
app.command("survey")(survey)
app.command("serve")(serve)
app.command("console")(console)
app.command("router")(router)
app.command("web")(web)


@app.callback()
def root(
    ctx: typer.Context,
    config: Optional[Path] = typer.Option(None, "--config", help="YAML config override file (see README)."),
    verbose: bool = typer.Option(False, "--verbose", "-v", help="Log at INFO level."),
) -> None:
    """Lupin robot stack."""
    ctx.obj = {"config_path": config}
    logging.basicConfig(level=logging.INFO if verbose else logging.WARNING,
                        format="%(levelname)s %(name)s: %(message)s")


@app.command("bench")
def bench(
    ctx: typer.Context,
    names: Optional[list[str]] = typer.Argument(None, help="Benchmarks (or groups, e.g. 'sim') to run; all if none."),
    as_json: bool = typer.Option(False, "--json", help="One JSON object per benchmark per line."),
) -> None:
    """Run the benchmarks and report median and p95."""
    bench_mod.run(names or [], as_json=as_json, config=run_config(ctx))


OPTIONAL_VALUES = {"--foxglove": "8765"}
"""Options whose value may be left out (spec/cli.md ``--foxglove [PORT]``) and the value they
then take; typer has no such options, so the command line is completed before parsing."""


def complete_optional_values(argv: list[str]) -> list[str]:
    out = []
    for i, arg in enumerate(argv):
        out.append(arg)
        nxt = argv[i + 1] if i + 1 < len(argv) else None
        if arg in OPTIONAL_VALUES and (nxt is None or nxt.startswith("-")):
            out.append(OPTIONAL_VALUES[arg])
    return out


def main(argv: list[str] | None = None) -> int:
    """Console-script entry: run the app and turn user errors into one line + exit 2."""
    command = typer.main.get_command(app)
    argv = complete_optional_values(sys.argv[1:] if argv is None else list(argv))
    try:
        result = command.main(args=argv, prog_name="lupin", standalone_mode=False)
    except cx.NoArgsIsHelpError as exc:
        print(exc.ctx.get_help() if exc.ctx else "")
        return 0
    except cx.UsageError as exc:
        where = exc.ctx.command_path if exc.ctx else "lupin"
        print(f"{where}: {exc.format_message()}", file=sys.stderr)
        return 2
    except (InputError, DeviceError) as exc:
        # A file with several problems lists them all, still on one line (spec/cli.md).
        print("lupin: " + "; ".join(str(exc).splitlines()), file=sys.stderr)
        return 2
    except cx.ClickException as exc:
        print(f"lupin: {exc.format_message()}", file=sys.stderr)
        return exc.exit_code
    except (typer.Abort, KeyboardInterrupt):
        print("lupin: aborted", file=sys.stderr)
        return 1
    except typer.Exit as exc:
        return exc.exit_code
    return result if isinstance(result, int) else 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
