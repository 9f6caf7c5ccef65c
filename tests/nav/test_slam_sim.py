"""SLAM in the simulated greenhouse: the whole stack live, SLAM in its worker process owning
``map -> odom``, ground truth read only to judge."""
from __future__ import annotations

import math
import os
import signal

import numpy as np
import pytest

from hw.odometry import Pose2D
from mission.jobs.map_quality import map_quality
from mission.jobs.navigate import start_navigate
from mission.jobs.slam_drive import drifted, survey
from mission.runtime.config import load_config
from mission.runtime.navigation import MapResetError, clear_map
from nav.costmap.grid import INSCRIBED, UNKNOWN
from nav.slam.config import SlamConfig
from nav.slam.mapper import Mapper
from sim.world import load_default_world

pytestmark = pytest.mark.slow


def rms(est: np.ndarray, truth: np.ndarray) -> float:
    return float(np.sqrt(np.mean(np.sum((est[:, :2] - truth[:, :2]) ** 2, axis=1))))


@pytest.fixture(scope="module")
def surveyed():
    """One drive through every aisle of the default greenhouse: every pot, then home."""
    world = load_default_world()
    run, log = survey(world, load_config(env={}))
    out = {"world": world, "spawn": run.spawn, "log": log.arrays(), "angles": log.angles,
           "outcomes": log.outcomes, "occupancy": run.nav.localisation.occupancy,
           "loops": run.nav.localisation.last_reply.loop_closures, "spawned": run.nav.localisation.spawned}
    run.close()
    return out


def test_the_survey_drives_every_aisle_on_slam_with_centimetre_trajectory_error(surveyed):
    log = surveyed["log"]
    assert surveyed["outcomes"] == ["succeeded"] * 13
    assert len(log["stamps"]) > 700  # a reply for (almost) every revolution of a ~85 s drive
    ours, odom = rms(log["slam"], log["truth"]), rms(log["odom"], log["truth"])
    assert ours <= 0.03, ours
    assert ours < odom / 5, (ours, odom)
    assert surveyed["loops"] >= 1  # the return home revisits the start
    assert surveyed["spawned"] == 1  # nothing crashed


def test_the_survey_map_holds_the_greenhouse(surveyed):
    q = map_quality(surveyed["occupancy"], surveyed["world"], surveyed["spawn"])
    assert q.recall >= 0.95 and q.precision >= 0.95, q


def test_a_loop_closure_reduces_the_error_after_a_loop_with_injected_odometry_drift(surveyed):
    """Replay the survey's scans with wheel odometry made 2 % long and turning 0.03 rad per
    metre, and a front end that keeps only 1 m of local map (so, as in a long greenhouse, it
    cannot see back to where it started): the loop closures must pull the end of the drive back."""
    log, angles = surveyed["log"], surveyed["angles"]
    odom = drifted(log["odom"], scale=1.02, yaw_per_m=0.03)
    ends = {}
    for closing in (False, True):
        mapper = Mapper(SlamConfig(local_map_range=1.0, loop_closure=closing), Pose2D(0.115, 0.0, 0.0))
        for r, o in zip(log["ranges"], odom):
            mapper.process(angles, r, o)
        idx, poses = mapper.trajectory()
        truth = log["truth"][idx]
        ends[closing] = (rms(poses, truth), float(np.hypot(*(poses[-1, :2] - truth[-1, :2]))))
        if closing:
            assert mapper.loop_closures >= 1
    assert ends[True][1] < ends[False][1] / 2, ends
    assert ends[True][0] < ends[False][0], ends


def test_clear_map_mid_drive_kills_and_respawns_the_worker_and_the_robot_drives_on():
    world = load_default_world()
    run = start_navigate(world, load_config(env={}))
    assert run.wait_ready()
    slam, sched = run.nav.localisation, run.robot.scheduler
    run.nav.navigate_to(run.to_map(Pose2D(5.5, 0.5, 0.0)), run.now, 60.0)
    sched.run_until(run.now + 4.0)
    assert slam.occupancy is not None and (run.nav.global_costmap.grid.data != UNKNOWN).any()
    x0, t_reset = run.sim.truth().x, run.now
    assert clear_map(run.nav, run.now) == 1
    assert slam.pid is None and slam.occupancy is None
    # both costmaps were cleared at once: no obstacle left, and the global one forgot the map
    assert not (run.nav.local_costmap.grid.data >= INSCRIBED).any()
    assert (run.nav.global_costmap.grid.data == UNKNOWN).all()
    sched.run_until(t_reset + 0.95)
    assert slam.pid is None  # the gap: respawn_delay 1.0 s
    assert run.nav.active  # ... bridged by odometry
    sched.run_until(t_reset + 2.0)
    assert slam.spawned == 2 and slam.pid is not None
    assert slam.last_reply.stamp > t_reset + 1.0  # mapping resumed within 2 s ...
    assert slam.last_reply.keyframes < 10  # ... from an empty graph
    sched.run_until(t_reset + 3.0)
    assert slam.occupancy is not None and (run.nav.global_costmap.grid.data != UNKNOWN).any()
    while run.nav.active and run.now < 60.0:
        sched.step()
    assert run.nav.state.value == "succeeded", run.nav.reason
    assert run.sim.truth().x > x0 + 1.0
    t = run.sim.truth()
    assert math.hypot(t.x - 5.5, t.y - 0.5) < 0.25 + 0.05  # the map frame survived the reset
    run.close()


def test_a_worker_that_dies_on_its_own_is_respawned():
    run = start_navigate(load_default_world(), load_config(env={}))
    assert run.wait_ready()
    slam, sched = run.nav.localisation, run.robot.scheduler
    run.nav.navigate_to(run.to_map(Pose2D(4.5, 0.5, 0.0)), run.now, 60.0)
    sched.run_until(run.now + 2.0)
    os.kill(slam.pid, signal.SIGKILL)
    t_crash = run.now
    sched.run_until(t_crash + 2.5)
    assert slam.deaths == 1 and slam.spawned == 2
    assert slam.last_reply.stamp > t_crash + 1.0
    while run.nav.active and run.now < 60.0:
        sched.step()
    assert run.nav.state.value == "succeeded", run.nav.reason
    run.close()


def test_with_the_lidar_absent_navigation_stays_inactive_and_says_why_then_activates():
    run = start_navigate(load_default_world(), load_config(env={}))
    run.sim.faults.lidar_dropout(25.0)
    sched = run.robot.scheduler
    assert not run.wait_ready()  # gives up waiting at the 20 s ceiling ...
    assert 20.0 <= run.now < 21.0
    readiness = run.nav.readiness
    assert readiness.waiting_for == "scans" and "no lidar scans" in readiness.status(run.now)
    run.nav.navigate_to(run.to_map(Pose2D(3.0, 0.5, 0.0)), run.now, 30.0)
    assert run.nav.state.value == "failed" and "scans" in run.nav.reason
    assert run.sim.truth().x == pytest.approx(1.0, abs=0.01)  # nothing moved
    sched.run_until(26.5)  # ... but never wedges: scans return at 25 s
    assert readiness.active
    assert run.go(Pose2D(3.0, 0.5, 0.0), 30.0) == "succeeded", run.nav.reason
    run.close()


@pytest.mark.parametrize("error", [(0.4, 0.3, 0.3), (-0.3, -0.4, -0.3)])
def test_localisation_on_the_saved_survey_map_converges_from_half_a_metre_and_navigates(surveyed, tmp_path, error):
    """``nav.slam: false``: AMCL on the map the survey saved, started 0.5 m / 0.3 rad off."""
    from nav.map_io import save_map

    map_file = save_map(surveyed["occupancy"].cropped(), tmp_path / "greenhouse.yaml")
    config = load_config(env={"LUPIN_NAV__SLAM": "false", "LUPIN_NAV__MAP_FILE": str(map_file),
                              "LUPIN_NAV__AMCL__INITIAL_POSE": str(list(error))})
    run = start_navigate(load_default_world(), config)
    assert (run.nav.global_costmap.grid.data != UNKNOWN).any()  # the saved map is the static layer
    assert run.wait_ready(), run.nav.readiness.status(run.now)
    assert run.now < 5.0  # converged standing still, before moving
    assert math.hypot(run.sim.truth().x - 1.0, run.sim.truth().y - 0.5) < 0.005  # nothing moved meanwhile

    def error_now():
        b, t = run.nav.map_pose(), run.to_map(run.sim.truth())
        return math.hypot(b.x - t.x, b.y - t.y), abs(math.remainder(b.yaw - t.yaw, math.tau))

    xy, yaw = error_now()
    assert xy < 0.05 and yaw < 0.05, (xy, yaw)
    assert run.go(Pose2D(5.0, 2.5, math.pi), 60.0) == "succeeded", run.nav.reason
    xy, yaw = error_now()
    assert xy < 0.05 and yaw < 0.03, (xy, yaw)  # SLAM, the live mode, holds ~1 cm
    assert not run.bumps
    with pytest.raises(MapResetError):
        clear_map(run.nav, run.now)  # no live map to reset on a saved one
    run.close()
