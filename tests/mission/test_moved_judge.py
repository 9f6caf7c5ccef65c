"""The moved-pot judge of the benches (lupin.bench.moved_judge): truth from the world file, in
the mission's frame the world gives."""
from __future__ import annotations

import math

import pytest

from lupin.bench.moved_judge import judge_report, mission_offsets, off_pots, shifted, true_poses
from mission.patrol.mission_file import mission_from_world
from sim.generate import generate_world, moved_pots


@pytest.fixture
def world():
    return generate_world(2, 3, 4)


@pytest.fixture
def moved(world):
    return moved_pots(world, 4, 2, shift=(0.1, 0.2))


def _with_pose(mission, pid, x, y, facing):
    pots = [p.model_copy(update={"x": x, "y": y, "facing": facing}) if p.id == pid else p for p in mission.pots]
    return mission.model_copy(update={"pots": pots})


def test_true_poses_put_the_dock_at_the_origin(world):
    poses = true_poses(world)
    first = world.pots[0]
    assert world.spawn.yaw == 0.0
    assert poses[first.id].x == pytest.approx(first.x - world.spawn.x)
    assert poses[first.id].y == pytest.approx(first.y - world.spawn.y)
    # the world's own mission is in that frame: every pot within its rounding of the truth
    assert max(d for d, _ in mission_offsets(mission_from_world(world), world).values()) < 1e-3


def test_shifted_names_only_the_pots_the_world_moved(world, moved):
    changed = {p.id for p, q in zip(world.pots, moved.pots) if (p.x, p.y, p.facing) != (q.x, q.y, q.facing)}
    assert len(changed) == 2
    assert shifted(world, moved) == changed
    assert shifted(world, world) == set()


def test_a_report_is_judged_against_the_moved_pots(world, moved):
    truth = shifted(world, moved)
    hit, missed = sorted(truth)
    unmoved = next(p.id for p in world.pots if p.id not in truth)
    at = true_poses(moved)[hit]
    doc = {"anomalies": [
        {"pot": hit, "kind": "moved", "x": at.x + 0.03, "y": at.y - 0.04, "facing": at.yaw},
        {"pot": unmoved, "kind": "moved", "x": 0.0, "y": 0.0, "facing": 0.0},
        {"pot": missed, "kind": "tag_mismatch"},
    ]}
    judged = judge_report(doc, moved, truth)
    assert judged["reported"] == 2
    assert judged["false"] == [unmoved]
    assert judged["missed"] == [missed]
    assert judged["errors"] == [pytest.approx(0.05)]
    assert judge_report({"anomalies": []}, moved, set()) == {"reported": 0, "false": [], "missed": [], "errors": []}


def test_off_pots_are_the_pots_the_mission_has_wrong(world, moved):
    mission = mission_from_world(world)
    truth = shifted(world, moved)
    assert off_pots(mission, moved, 0.05, 0.15) == truth
    pid = sorted(truth)[0]
    at = true_poses(moved)[pid]
    near = _with_pose(mission, pid, at.x + 0.03, at.y, at.yaw + 2 * math.pi)
    assert off_pots(near, moved, 0.05, 0.15) == truth - {pid}
    assert mission_offsets(near, moved)[pid] == (pytest.approx(0.03), pytest.approx(0.0, abs=1e-9))
    assert off_pots(_with_pose(mission, pid, at.x + 0.06, at.y, at.yaw), moved, 0.05, 0.15) == truth
    assert off_pots(_with_pose(mission, pid, at.x, at.y, at.yaw - 0.2), moved, 0.05, 0.15) == truth
