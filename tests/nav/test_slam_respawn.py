"""A SLAM worker in trouble mid-patrol costs seconds, not the map (issue 29, item 4).

Four pots of the default greenhouse, the whole stack live; 15 s in, on the way between pots,
the worker is made to wedge for real (a call that never returns, inside the worker process) or
is starved of CPU for real (pinned to one core beside a busy process, at a lower priority,
while it works a while without answering). Either way the patrol completes with every pot right;
the wedged worker is replaced by one that goes on from the checkpoint (the map it hands back
covers every cell known before the wedge), the starved one is waited for.
"""
from __future__ import annotations

import os
import subprocess
import sys

import pytest

from lupin.bench.patrol import correct_pots
from lupin.bench.slam import stalled_patrol
from mission.patrol.mission_file import mission_from_world
from mission.runtime.config import load_config
from nav.slam.supervisor import SlamSupervisor
from sim.world import load_default_world

pytestmark = [pytest.mark.slow, pytest.mark.skipif(not os.path.exists("/proc/self/stat"), reason="needs /proc")]

POTS = 4
AT = 15.0
"""Runtime seconds into the patrol: the robot is driving between its first pots."""
TIMEOUT = "1.0"
"""reply_timeout for these runs (5 s by default): the smallest run that proves the point."""


def patrol_with(stall):
    world = load_default_world()
    base = mission_from_world(world)
    mission = base.model_copy(update={"pots": base.pots[:POTS]})
    config = load_config(env={"LUPIN_NAV__MAPPING__REPLY_TIMEOUT": TIMEOUT})
    return world, stalled_patrol(world, mission, config, AT, stall)


def test_a_worker_wedged_mid_patrol_is_replaced_from_the_checkpoint_and_the_patrol_goes_on(capfd):
    world, r = patrol_with(lambda sup: sup.stall("block"))
    err = capfd.readouterr().err  # the wedged worker said where it was stuck before it died
    assert "in stall" in err and "nav/slam/worker.py" in err
    assert r.doc["outcome"] == "completed"
    assert correct_pots(world, r.doc) == POTS
    assert r.deaths == 1 and r.spawned == 2 and r.restored == 1
    # runtime seconds: the exchange that found it (lock-step waits on the wall clock, not the
    # runtime's), respawn_delay 1.0 s, and the new worker's first exchange
    assert r.first_reply_at - r.stalled_at <= 1.5
    assert len(r.before) > 5000  # a real map was at stake
    assert r.before <= r.after  # the new worker's first map covers every cell known before
    assert r.before <= r.end


def starve(sup: SlamSupervisor, hogs: list) -> None:
    """Starve the worker for real: pinned to one core beside a busy process, five nice levels
    below it (about a quarter of the core), while it works 0.6 CPU s without answering: silent
    for seconds, more than the 1 s limit, but never hung nor spinning."""
    core = max(os.sched_getaffinity(0))
    hogs.append(subprocess.Popen([sys.executable, "-c",
                                  f"import os, time\nos.sched_setaffinity(0, {{{core}}})\n"
                                  "end = time.monotonic() + 8.0\nwhile time.monotonic() < end: pass\n"]))
    os.sched_setaffinity(sup.pid, {core})
    os.setpriority(os.PRIO_PROCESS, sup.pid, 5)
    sup.stall("work", 0.6)


def test_a_worker_only_starved_of_cpu_mid_patrol_is_waited_for_and_keeps_its_map():
    hogs: list = []
    try:
        world, r = patrol_with(lambda sup: starve(sup, hogs))
    finally:
        for h in hogs:
            h.kill()
            h.wait()
    assert r.doc["outcome"] == "completed"
    assert correct_pots(world, r.doc) == POTS
    assert r.spared >= 1  # it was late past the limit ...
    assert r.deaths == 0 and r.spawned == 1 and r.restored == 0  # ... and never replaced
    assert r.before <= r.end
