"""Every MuJoCo scene loads, steps without a warning and behaves like a planar mecanum base.

mujoco_menagerie's rule: a test loads and steps every scene and fails on any MuJoCo warning.
The scenes are the robot's own flat-floor scene and the greenhouse built from the default world
and from a generated world.
"""
from __future__ import annotations

import os

os.environ.setdefault("MUJOCO_GL", "egl")

import math  # noqa: E402

import mujoco  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

from sim.greenhouse import ROBOT_XML, build_greenhouse  # noqa: E402
from sim.world import World, load_default_world  # noqa: E402

pytestmark = pytest.mark.slow

try:
    from sim.generate import generate_world
except ImportError:  # pragma: no cover - the generator is optional for these tests
    generate_world = None

SCENE_XML = ROBOT_XML.parent / "scene.xml"
BASE_JOINTS = ("base_x", "base_y", "base_yaw")
ARM = ("shoulder_pan", "shoulder_lift", "elbow", "wrist")
HOME = (0.04, -0.01, 0.01, -1.57)


def _scene_model() -> tuple[mujoco.MjModel, tuple[float, float, float]]:
    return mujoco.MjModel.from_xml_path(str(SCENE_XML)), (0.0, 0.0, 0.0)


def _world_model(world: World) -> tuple[mujoco.MjModel, tuple[float, float, float]]:
    return build_greenhouse(world), (world.spawn.x, world.spawn.y, world.spawn.yaw)


SCENES = {
    "scene.xml": _scene_model,
    "greenhouse-default": lambda: _world_model(load_default_world()),
}
if generate_world is not None:
    SCENES["greenhouse-generated"] = lambda: _world_model(generate_world(3, 3, 5))


def _warnings(data: mujoco.MjData) -> dict[str, int]:
    return {
        name: int(data.warning[int(w)].number)
        for name, w in mujoco.mjtWarning.__members__.items()
        if name != "mjNWARNING" and data.warning[int(w)].number
    }


def _setup(model: mujoco.MjModel, pose, arm=HOME) -> tuple[mujoco.MjData, np.ndarray]:
    """Data with the base at ``pose`` and the arm holding ``arm`` (qpos and servo targets)."""
    data = mujoco.MjData(model)
    base = np.array([model.joint(j).qposadr[0] for j in BASE_JOINTS])
    data.qpos[base] = pose
    for joint, q in zip(ARM, arm):
        data.qpos[model.joint(joint).qposadr[0]] = q
        data.ctrl[model.actuator(joint).id] = q
    mujoco.mj_forward(model, data)
    return data, base


@pytest.fixture(scope="module", params=list(SCENES))
def scene(request):
    model, pose = SCENES[request.param]()
    return request.param, model, pose


def test_scene_steps_3s_without_warnings_and_rests(scene):
    name, model, pose = scene
    assert model.opt.timestep == pytest.approx(0.005)
    assert model.opt.integrator == mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    data, base = _setup(model, pose)
    mujoco.mj_step(model, data, nstep=round(3.0 / model.opt.timestep))
    assert _warnings(data) == {}, name
    assert np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(data.qvel))
    # Zero drive ctrl: the base stays where it was put (and nothing touches the chassis).
    assert np.allclose(data.qpos[base], pose, atol=1e-4), data.qpos[base]
    assert data.ncon == 0
    # The arm holds home up to a little gravity sag.
    for joint, q in zip(ARM, HOME):
        assert data.qpos[model.joint(joint).qposadr[0]] == pytest.approx(q, abs=0.02), joint


def test_drive_vx_moves_the_base_along_its_heading(scene):
    name, model, pose = scene
    yaw = 0.7
    data, base = _setup(model, (pose[0], pose[1], yaw))
    data.ctrl[model.actuator("drive_vx").id] = 0.3
    mujoco.mj_step(model, data, nstep=round(1.0 / model.opt.timestep))
    dx, dy = data.qpos[base[0]] - pose[0], data.qpos[base[1]] - pose[1]
    assert math.hypot(dx, dy) == pytest.approx(0.3, abs=0.02)
    assert math.atan2(dy, dx) == pytest.approx(yaw, abs=0.01)
    assert data.qpos[base[2]] == pytest.approx(yaw, abs=0.01)
    assert _warnings(data) == {}


def test_strafe_and_turn_servos_act_in_the_body_frame():
    model, _ = _scene_model()
    data, base = _setup(model, (0.0, 0.0, math.pi / 2))
    data.ctrl[model.actuator("drive_vy").id] = 0.2  # body +y = world -x at yaw pi/2
    mujoco.mj_step(model, data, nstep=200)
    assert data.qpos[base[0]] == pytest.approx(-0.2, abs=0.02)
    assert data.qpos[base[1]] == pytest.approx(0.0, abs=0.01)
    data, base = _setup(model, (0.0, 0.0, 0.0))
    data.ctrl[model.actuator("drive_wz").id] = 0.5
    mujoco.mj_step(model, data, nstep=200)
    assert data.qpos[base[2]] == pytest.approx(0.5, abs=0.03)
    assert np.allclose(data.qpos[base[:2]], 0.0, atol=0.005)


def test_a_wall_stops_the_chassis():
    """Driving west into the west wall (inner face x = 0) stops the 0.33 m chassis short of it."""
    model, _ = _world_model(load_default_world())
    data, base = _setup(model, (0.8, 2.5, math.pi))
    data.ctrl[model.actuator("drive_vx").id] = 0.3
    mujoco.mj_step(model, data, nstep=round(4.0 / model.opt.timestep))  # 1.2 m of free travel
    x = data.qpos[base[0]]
    assert 0.16 <= x <= 0.17, x  # half the chassis length (0.165 m) from the wall
    assert abs(data.qvel[model.joint("base_x").dofadr[0]]) < 0.01
    assert data.qpos[base[1]] == pytest.approx(2.5, abs=0.01)
    assert _warnings(data) == {}


def test_a_pot_stops_the_chassis_but_the_floor_never_touches_it():
    world = load_default_world()
    pot = world.pots[0]
    model, _ = _world_model(world)
    # From the pot's approach pose, drive straight at it.
    x = pot.x + 0.5 * math.cos(pot.facing)
    y = pot.y + 0.5 * math.sin(pot.facing)
    data, base = _setup(model, (x, y, pot.facing + math.pi))
    data.ctrl[model.actuator("drive_vx").id] = 0.3
    mujoco.mj_step(model, data, nstep=round(3.0 / model.opt.timestep))
    gap = math.hypot(data.qpos[base[0]] - pot.x, data.qpos[base[1]] - pot.y)
    assert gap == pytest.approx(0.165 + 0.10, abs=0.005)  # chassis front against the pot
    floor = model.geom("floor").id
    touching = np.concatenate([data.contact.geom1[: data.ncon], data.contact.geom2[: data.ncon]])
    assert data.ncon > 0 and floor not in touching
    assert _warnings(data) == {}


def test_a_spare_box_placed_at_run_time_stops_the_chassis():
    """The backend's place_box fault moves a parked mocap box and rewrites only its size and
    bounding radius; the box must then stop the chassis like any other static."""
    model, _ = _world_model(load_default_world())
    data, base = _setup(model, (5.0, 0.5, 0.0))  # east end of the south aisle, looking east
    body, geom = model.body("spare_box_2"), model.geom("spare_box_2_geom")
    sx, sy, h = 0.3, 0.6, 0.5
    model.geom_size[geom.id] = (sx / 2, sy / 2, h / 2)
    model.geom_rbound[geom.id] = math.sqrt((sx / 2) ** 2 + (sy / 2) ** 2 + (h / 2) ** 2)
    data.mocap_pos[body.mocapid[0]] = (6.0, 0.5, h / 2)
    data.ctrl[model.actuator("drive_vx").id] = 0.3
    mujoco.mj_step(model, data, nstep=round(4.0 / model.opt.timestep))
    assert data.qpos[base[0]] == pytest.approx(6.0 - sx / 2 - 0.165, abs=0.005)
    assert _warnings(data) == {}
