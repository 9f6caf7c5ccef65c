"""Runtime settings: which robot this is (the simulated one or the real one) and where the
runtime keeps what must outlive its process.

The backend is config, not only a flag: the robot's deploy config says ``hw``, so a ``lupin
patrol`` typed on the robot without ``--backend`` runs the robot, never a simulation that
writes real-looking reports and history (issue: "the robot knows it is the robot").
"""
from __future__ import annotations

from pathlib import Path
from typing import Literal, Optional

from pydantic import BaseModel, ConfigDict

Backend = Literal["sim", "hw"]


class RuntimeConfig(BaseModel):
    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)

    backend: Backend = "sim"
    """What ``lupin patrol``, ``survey`` and ``serve`` run on when ``--backend`` is not given:
    ``sim`` (the MuJoCo greenhouse) or ``hw`` (the robot's devices). The deploy's config on the
    robot sets ``hw``."""
    state_dir: Optional[Path] = None
    """Where the runtime keeps what must survive a restart (the soft e-stop's latch, the
    history's spool): ``/var/lib/lupin`` in the deploy files, never the install directory.
    Unset: on the hw backend ``$XDG_STATE_HOME/lupin`` (``~/.local/state/lupin``); in the sim a
    fresh directory per run (a simulation has nothing to carry over to the next one)."""
