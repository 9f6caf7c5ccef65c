"""The runtime's warm-up (``mission.runtime.warm_up``) compiles every kernel its loop calls: in a
fresh process, after it, a sim patrol among walkers (people tracked, costmaps, plans, MPPI, the
collision monitor) calls no compiled kernel with arguments it has not already been compiled for.

A fresh process, because numba keeps what a process compiled or loaded; each kernel's count of
signatures is what is compared, so a warm cache on disk does not hide a miss."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
RUNTIME = ("hw", "nav", "perception", "mission", "arm", "behaviours")
"""The packages the runtime's process runs (SLAM's worker is another process, with its own warm-up)."""
PATROL_S = 40.0


def _kernels() -> dict[str, int]:
    from numba.core.registry import CPUDispatcher

    out = {}
    for name, module in list(sys.modules.items()):
        if name.split(".")[0] not in RUNTIME or name.startswith("nav.slam"):
            continue
        for attr, value in list(vars(module).items()):
            if isinstance(value, CPUDispatcher) and value.__module__ == name:
                out[f"{name}.{attr}"] = len(value.signatures)
    return out


def _measure() -> None:
    """In this process: the kernels' signatures after the warm-up and after a patrol, as JSON."""
    import tempfile
    import time

    from mission.jobs.sim_patrol import start_sim_patrol
    from mission.patrol.mission_file import mission_from_world
    from mission.runtime.config import LupinConfig, with_overrides
    from mission.runtime.warm_up import warm_up
    from sim.generate import generate_world

    config = with_overrides(LupinConfig(), {"sim": {"realtime": False}})
    warm_up(config)
    warmed = _kernels()
    world = generate_world(2, 4, 5, bays=1, walkers=2)
    with tempfile.TemporaryDirectory() as tmp:
        run = start_sim_patrol(world, mission_from_world(world), config, Path(tmp) / "report.json", time.perf_counter)
        try:
            while not run.done and run.robot.scheduler.clock.now() < PATROL_S:
                run.step()
        finally:
            run.close()
    print(json.dumps({"warmed": warmed, "after": _kernels()}))


def test_after_the_warm_up_a_patrol_among_walkers_compiles_nothing():
    env = {**os.environ, "MUJOCO_GL": "egl", "PYTHONPATH": str(ROOT)}
    done = subprocess.run([sys.executable, "-c", "from tests.mission.test_warm_up import _measure; _measure()"],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-3000:]
    out = json.loads(done.stdout.strip().splitlines()[-1])
    warmed, after = out["warmed"], out["after"]
    compiled = {k for k, n in warmed.items() if n}
    assert {"perception.people.tracker._step", "perception.people.returns._returns", "nav.mppi.motion_models._rollout",
            "nav.costmap.inflation.inflate", "nav.planner.propagate", "hw.robot_outline._inside"} <= compiled
    missed = {k: (warmed.get(k, 0), n) for k, n in after.items() if n > warmed.get(k, 0)}
    assert missed == {}, f"compiled during the patrol, not by the warm-up: {missed}"
    assert len([k for k, n in after.items() if n]) >= 15  # the patrol ran the loop's kernels
