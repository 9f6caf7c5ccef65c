"""Which robot a command runs: ``--backend``, else the config's ``runtime.backend``.

The robot's deploy config says ``hw``, so a command typed on the robot without the flag runs
the robot, never a simulation writing real-looking reports and history. Every command that
runs a robot says on its first line which one (and, in the sim, which world), so nobody
mistakes one for the other.
"""
from __future__ import annotations

from enum import Enum
from typing import Optional

import typer


class Backend(str, Enum):
    sim = "sim"
    hw = "hw"


def backend_option(what: str = "sim (the MuJoCo greenhouse) or hw (the robot)") -> Optional[Backend]:
    return typer.Option(None, "--backend", help=f"{what}; default: runtime.backend in the config "
                                                "(hw in the robot's deploy config, else sim).")


def resolve_backend(option: Optional[Backend], config) -> Backend:
    """The backend to run: the option when given, else the config's."""
    return option if option is not None else Backend(config.runtime.backend)


def announce(command: str, backend: Backend, world=None) -> None:
    """The first line of a command's output: the backend, and the world in the sim."""
    if backend is Backend.hw:
        print(f"lupin {command}: hw backend (the robot's devices)", flush=True)
    else:
        name = getattr(world, "name", None)
        print(f"lupin {command}: sim backend" + (f", world {name!r}" if name else ""), flush=True)
