"""The perception evaluation harness: randomized pots rendered in the sim, scored against truth.

Each pot of a generated greenhouse (3 x 5 pots) is redrawn at random: a colour (red, white,
pink) or none, a pest on half the flowering pots, 1..3 blooms, a whitelisted tag. The
robot is placed at the pot's approach pose (spec/mission.md) plus noise drawn uniformly inside
the goal tolerance (a disc of 0.25 m, +-0.12 rad; seed: the goal checker), never nearer the pot
than its chassis allows, the lighting is jittered (sim/lighting.py), and the front camera
(arm wherever, it does not block it) and the wrist camera (arm at ``inspect``) are rendered.

Truth is what each camera can see: a segmentation render of the wrist frame counts the visible
pixels of every bloom and of the pest, and the tag's corners are projected through the front
camera's true pose. At the edge of the tolerance the pot leaves the wrist frame entirely; the
harness reports how often (``flower_in_view``, ``tag_in_view``), so a mission can tell the
detector's misses from the approach's.

Benchmarks: ``perception.flower`` (ms per 640x480 wrist frame, accuracy, bug recall, false-bug
rate, plus precision / recall per class, the confusion matrix and count accuracy) and
``perception.tag`` (ms per front frame, id accuracy on frames with the tag in view, pose error
median / p95 / max, wrong ids read nearer than 0.6 m); both come from one evaluation run,
cached per config.
"""
from __future__ import annotations

import math
import random
import time
from dataclasses import dataclass
from typing import Iterator, Optional

import mujoco
import numpy as np

from arm.presets import preset
from hw.odometry import Pose2D
from mission.approach import STANDOFF
from mission.approach import approach_pose as ideal_approach
from lupin.bench import Sample, benchmark
from mission.runtime.config import LupinConfig
from nav.frames import compose
from perception.evaluation import rotation_error, score_flowers, score_tags
from perception.flower_detector import FlowerDetector
from perception.tag_reader import TagReader
from sim.backend import SimRobot
from sim.generate import generate_world
from sim.lighting import Lighting, LightingJitter
from sim.world import World

POTS = 240
"""Pots rendered by the benchmark (16 generated greenhouses of 15)."""
ROWS, PER_ROW = 3, 5
"""Approach standoff, m (spec/mission.md)."""
XY_TOLERANCE, YAW_TOLERANCE = 0.25, 0.12
"""Goal tolerance the approach noise stays inside (seed: 0.25 m, 0.12 rad)."""
CLEARANCE = 0.35
"""Nearest the base centre may come to a pot centre, m: robot radius 0.22 + pot 0.10 + margin."""
VISIBLE_PX = 400
"""A bloom counts as in view with at least this many visible pixels (min blob 150 px, plus
margin for the morphology); fewer but some pixels is marginal and not scored."""
PEST_PX = 100
"""A pest counts as in view with at least this many visible pixels, about a tenth of the
~900 px it covers from the approach pose; 1..99 px (a sliver at the frame's edge) is marginal
and not scored, 0 is not in view."""
EDGE_PX = 3
"""A tag counts as in view when all four corners are this far inside the frame."""
NEAR_M = 0.6
"""A read nearer than this is one the mission would take for the pot's own tag (the plate is
~0.23 m from the front camera at the approach pose); a wrong id that near is a misread."""
_CV_FROM_GL = np.diag([1.0, -1.0, -1.0])
"""MuJoCo cameras look down -z with y up; OpenCV's look down +z with y down."""


@dataclass(frozen=True)
class Shot:
    pot_id: str
    flower: str
    bug: bool
    blooms: int
    tag: int
    noise: tuple[float, float, float]
    lighting: Lighting
    wrist: np.ndarray
    front: np.ndarray
    flower_truth: Optional[str]
    """What the wrist camera can see: the pot's flower, 'none', or None (marginal)."""
    count_truth: Optional[int]
    bug_truth: Optional[bool]
    tag_in_view: bool
    tag_rotation: np.ndarray
    """True tag rotation in the front camera (OpenCV axes)."""
    tag_position: np.ndarray


def random_world(seed: int) -> World:
    """A generated greenhouse with every pot's plant and tag redrawn."""
    rng = random.Random(seed)
    world = generate_world(ROWS, PER_ROW, seed)
    tags = rng.sample(range(22), len(world.pots))
    pots = []
    for pot, tag in zip(world.pots, tags):
        flower = rng.choice(("red", "white", "pink", "none"))
        bug = flower != "none" and rng.random() < 0.5
        pots.append(pot.model_copy(update={"flower": flower, "bug": bug, "blooms": rng.randint(1, 3), "tag": tag}))
    return world.model_copy(update={"pots": pots, "climate": {}})


def approach_noise(rng: np.random.Generator) -> tuple[float, float, float]:
    """(forward, left, yaw) offset, uniform in the tolerance disc; forward stays clear of the pot."""
    while True:
        r = XY_TOLERANCE * math.sqrt(rng.uniform())
        a = rng.uniform(-math.pi, math.pi)
        fwd, left = r * math.cos(a), r * math.sin(a)
        if STANDOFF - fwd >= CLEARANCE:
            return fwd, left, float(rng.uniform(-YAW_TOLERANCE, YAW_TOLERANCE))


def render_shots(config: LupinConfig, count: int, seed: int) -> Iterator[Shot]:
    """``count`` evaluation shots, the same for the same seed."""
    rng = np.random.default_rng(seed)
    done, world_seed = 0, seed * 1000
    while done < count:
        world_seed += 1
        world = random_world(world_seed)
        sim = SimRobot(world, config.sim, config.hw)
        seg = mujoco.Renderer(sim.engine.model, config.sim.camera.height, config.sim.camera.width)
        seg.enable_segmentation_rendering()
        try:
            sim.servos.place(preset("inspect"))
            jitter = LightingJitter(sim.engine.model)
            for pot in world.pots[: count - done]:
                yield _shot(sim, seg, jitter, pot, rng, config)
                done += 1
        finally:
            seg.close()
            sim.close()


def approach_pose(pot, noise: tuple[float, float, float] = (0.0, 0.0, 0.0)) -> tuple[float, float, float]:
    """World pose of the robot at ``pot``'s approach pose (spec/mission.md) plus
    ``noise`` = (forward, left, yaw) in the robot's frame."""
    p = compose(ideal_approach(pot.x, pot.y, pot.facing, STANDOFF), Pose2D(*noise))
    return p.x, p.y, p.yaw


def _shot(sim: SimRobot, seg: mujoco.Renderer, jitter: LightingJitter, pot, rng, config) -> Shot:
    noise = approach_noise(rng)
    sim.place(*approach_pose(pot, noise))
    lighting = jitter.apply(rng)
    wrist, front = sim.hal.cameras["wrist"].capture(), sim.hal.cameras["front"].capture()
    flower_truth, count_truth, bug_truth = flower_truth_of(sim, seg, pot)
    rot, pos, in_view = tag_truth(sim, pot, config)
    return Shot(pot.id, pot.flower, pot.bug, pot.blooms, pot.tag, noise, lighting, wrist, front,
                flower_truth, count_truth, bug_truth, in_view, rot, pos)


def _geom(sim: SimRobot, name: str) -> int:
    return mujoco.mj_name2id(sim.engine.model, mujoco.mjtObj.mjOBJ_GEOM, name)


def flower_truth_of(sim: SimRobot, seg: mujoco.Renderer, pot) -> tuple[Optional[str], Optional[int], Optional[bool]]:
    """(class, bloom count, pest) the wrist camera can see of ``pot`` now, None where marginal;
    ``seg`` is a segmentation renderer of the sim's model."""
    seg.update_scene(sim.engine.data, camera="wrist_camera")
    ids = seg.render()
    geoms = ids[..., 0][ids[..., 1] == int(mujoco.mjtObj.mjOBJ_GEOM)]
    pixels = np.bincount(geoms.ravel(), minlength=sim.engine.model.ngeom)
    blooms = [pixels[g] for g in (_geom(sim, f"pot_{pot.id}_bloom_{k}") for k in range(3)) if g >= 0]
    pest = _geom(sim, f"pot_{pot.id}_pest")
    pest_px = int(pixels[pest]) if pest >= 0 else 0
    visible = int(sum(b >= VISIBLE_PX for b in blooms))
    marginal = any(0 < b < VISIBLE_PX for b in blooms)
    if visible:
        flower = pot.flower
    else:
        flower = None if marginal else "none"
    count = None if marginal else visible
    bug = True if pest_px >= PEST_PX and visible else (None if pest_px > 0 else False)
    return flower, count, bug


def tag_truth(sim: SimRobot, pot, config: LupinConfig) -> tuple[np.ndarray, np.ndarray, bool]:
    """The tag's rotation and centre in the front camera (OpenCV axes), and whether all four
    corners are inside the frame. The tag is printed on the front face of geom ``tag_<pot>``:
    seen from the aisle its right is the geom's +y, its up +z, its normal +x."""
    d, m = sim.engine.data, sim.engine.model
    g = _geom(sim, f"tag_{pot.id}")
    axes = d.geom_xmat[g].reshape(3, 3)
    centre = d.geom_xpos[g] + axes[:, 0] * m.geom_size[g][0]
    cam = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_CAMERA, "front_camera")
    to_cam = _CV_FROM_GL @ d.cam_xmat[cam].reshape(3, 3).T
    rot = to_cam @ np.column_stack([axes[:, 1], axes[:, 2], axes[:, 0]])
    pos = to_cam @ (centre - d.cam_xpos[cam])
    h = config.perception.tag.tag_size / 2
    corners = pos[:, None] + rot @ np.array([[-h, h, h, -h], [h, h, -h, -h], [0, 0, 0, 0]])
    k = config.perception.tag.camera.matrix()
    uv = (k @ corners)[:2] / corners[2]
    w, hgt = config.sim.camera.width, config.sim.camera.height
    in_view = bool(np.all(corners[2] > 0) and np.all((uv[0] >= EDGE_PX) & (uv[0] <= w - 1 - EDGE_PX)
                                                      & (uv[1] >= EDGE_PX) & (uv[1] <= hgt - 1 - EDGE_PX)))
    return rot, pos, in_view


@dataclass(frozen=True)
class Evaluation:
    flower_ms: list[float]
    tag_ms: list[float]
    flower: dict
    tag: dict


def evaluate(config: LupinConfig, count: int = POTS, seed: int = 0) -> Evaluation:
    """Render ``count`` shots and score both detectors on them (wall time per detector call)."""
    flowers, tags = FlowerDetector(config.perception.flower), TagReader(config.perception.tag)
    f_ms, t_ms, rows = [], [], []
    for shot in render_shots(config, count, seed):
        if not rows:  # warm-up: OpenCV's first call allocates
            flowers(shot.wrist), tags(shot.front)
        t0 = time.perf_counter()
        frame = flowers(shot.wrist)
        t1 = time.perf_counter()
        reads = tags(shot.front)
        t2 = time.perf_counter()
        f_ms.append((t1 - t0) * 1e3)
        t_ms.append((t2 - t1) * 1e3)
        rows.append((shot, frame, reads[0] if reads else None))
    fs = score_flowers([s.flower_truth for s, _, _ in rows], [f.flower for _, f, _ in rows],
                       [s.bug_truth for s, _, _ in rows], [f.bug for _, f, _ in rows],
                       [s.count_truth for s, _, _ in rows], [f.count for _, f, _ in rows])
    seen = [(s, r) for s, _, r in rows if s.tag_in_view]
    ts = score_tags([s.tag for s, _ in seen], [r.id if r else None for _, r in seen],
                    [float(np.linalg.norm(np.subtract(r.position, s.tag_position))) if r else None for s, r in seen],
                    [rotation_error(r.rotation, s.tag_rotation) if r else None for s, r in seen])
    n = len(rows)
    flower = {"accuracy": round(fs.accuracy, 4),
              "bug_recall": None if fs.bug_recall is None else round(fs.bug_recall, 4),
              "false_bug_rate": None if fs.false_bug_rate is None else round(fs.false_bug_rate, 4),
              "count_accuracy": None if fs.count_accuracy is None else round(fs.count_accuracy, 4),
              "precision": {k: None if v is None else round(v, 3) for k, v in fs.precision.items()},
              "recall": {k: None if v is None else round(v, 3) for k, v in fs.recall.items()},
              "confusion": fs.confusion, "frames": n, "scored": fs.frames, "bug_frames": fs.bug_frames,
              "flower_in_view": round(sum(s.flower_truth not in (None, "none") for s, _, _ in rows)
                                      / max(1, sum(s.flower != "none" for s, _, _ in rows)), 4)}
    tag = {"accuracy": round(ts.accuracy, 4), "frames": n, "scored": ts.frames,
           "tag_in_view": round(ts.frames / max(1, n), 4),
           "near_misreads": sum(r is not None and r.id != s.tag and r.distance < NEAR_M for s, _, r in rows),
           "position_error_m": [round(v, 4) for v in ts.position_error_m],
           "rotation_error_deg": [round(v, 2) for v in ts.rotation_error_deg]}
    return Evaluation(f_ms, t_ms, flower, tag)


_CACHE: dict[str, Evaluation] = {}


def _cached(config: LupinConfig) -> Evaluation:
    key = config.model_dump_json()
    if key not in _CACHE:
        _CACHE[key] = evaluate(config, POTS, config.sim.seed)
    return _CACHE[key]


@benchmark("perception.flower")
def flower(config: LupinConfig) -> Sample:
    """HSV detector ms per 640x480 wrist frame over the evaluation set, and its scores."""
    ev = _cached(config)
    return Sample(ev.flower_ms, ev.flower)


@benchmark("perception.tag")
def tag(config: LupinConfig) -> Sample:
    """Tag reader ms per 640x480 front frame over the evaluation set, id accuracy and pose error."""
    ev = _cached(config)
    return Sample(ev.tag_ms, ev.tag)
