"""The runtime's state directory: one place for what must outlive the process (DESIGN.md).

The soft e-stop's latch, the history's spool and anything else a restarted runtime must find
again live here. On the robot it is a fixed, writable directory (``/var/lib/lupin`` in the
deploy files); a simulation gets a fresh temporary one per run unless the config names one,
so two sim runs (or two tests) never share a latch.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

from hw.errors import InputError
from mission.runtime.settings import RuntimeConfig


def default_hw_state_dir(env: dict[str, str] | None = None) -> Path:
    """``$XDG_STATE_HOME/lupin``, or ``~/.local/state/lupin``: the XDG base directory for state."""
    env = os.environ if env is None else env
    base = env.get("XDG_STATE_HOME") or str(Path.home() / ".local" / "state")
    return Path(base) / "lupin"


def state_directory(config: RuntimeConfig, backend: str) -> Path:
    """The directory to keep state in, created if missing; an unusable one is an ``InputError``
    naming it (bad input: the robot must not start without a place to keep its latch)."""
    if config.state_dir is not None:
        path = Path(config.state_dir)
    elif backend == "hw":
        path = default_hw_state_dir()
    else:
        return Path(tempfile.mkdtemp(prefix="lupin-state-"))
    try:
        path.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"runtime.state_dir {path}: cannot create it ({exc.strerror or exc})") from None
    if not os.access(path, os.W_OK | os.X_OK):
        raise InputError(f"runtime.state_dir {path}: not writable by this user")
    return path
