"""A greenhouse world file (spec/world.md) as a MuJoCo model, with the MIRTE Master in it.

The robot is not described here: the generated MJCF ``<include>``s
``sim/models/mirte_master/mirte_master.xml`` by absolute path, so that file stays the single
source of the robot (its README says where its numbers come from). A fleet's greenhouse
attaches the same file once per robot, each copy's names under its prefix (``r1/chassis``;
``build_greenhouse``), all at the origin until the backend sets each robot's pose. This module adds what the
world file describes, with the fixed geometry of :class:`sim.config.GreenhouseGeometry`:

- a floor plane over [0, x] x [0, y] and four 2 m walls around it;
- per pot, a frame ``pot_<id>`` (pot centre on the floor, +x along ``facing``) holding the
  terracotta pot (collides), foliage, 1..3 blooms and the optional pest spot (visual only; on a
  bloom or a back leaf, as ``sim.pests`` places it),
  and, if the pot has a tag, the tag plate ``tag_<id>`` on the facing side, its centre at
  ``plate_height`` (the front camera's optical height), printed with the 36h11 tag. A frame, not
  a body: the pot's geoms belong to the world body, static, so collision's broad phase has no
  body per pot to sort and bound each step (a 180-pot greenhouse stepped 3x slower with one);
- the world's obstacles as boxes ``obstacle_<i>``;
- four parked mocap boxes ``spare_box_<k>`` (geom ``spare_box_<k>_geom``) that the backend
  moves and resizes to place boxes at run time (the ``place_box`` fault);
- per walker (spec/world.md ``walkers``), a mocap body ``walker_<id>`` standing at the start of
  its path: two legs, a torso and a head, as wide as the walker (0.45 m for a person, more for
  one pushing a cart), 1.75 m tall, or for a crouching worker one 0.5 x 0.6 m block to 0.8 m
  and a head to 1.0 m, world collision geoms the lidar and the cameras see and the
  chassis can touch (``sim.walkers`` moves them);
- an orthographic ``overview`` camera looking straight down at the whole floor.

Geom groups: 0 = world collision geoms (floor, walls, pots, obstacles, boxes: what the lidar
sees), 1 = the robots (the lidar sees another robot's arm and lidar puck too), 2 = visual decoration (foliage, blooms, pests, tag plates: the lidar
ignores them). Collision bits: world statics contype = conaffinity = 3 and the floor 1/1, so
the robot's chassis (2/2) is stopped by statics but never touches the floor; a fleet's chassis
also touch each other (2 on 2), which the judges count (``sim.scene``).

Colours are chosen against the flower detector's HSV table (reference/upstream.md, OpenCV
H 0..179) and checked on real renders (tests/sim/test_greenhouse.py): blooms fall in their own
class and no other; nothing else the wrist camera sees at ``inspect`` (foliage, soil, pot,
floor, plate, the robot's fingers) falls in any class, pests included (V < 50 only on the
pest). That is why the floor is a mid grey (V < 140: not "white"), the pot is orange rather
than red-brown (H >= 15: not "pink"), the foliage is bright enough that its shaded side stays
above V 50, and the tag plates are navy on pale blue (see sim/apriltag.py). The patrol's view
(``inspect_plant``, issue 30) takes in more of what lies beyond the plant: under a bright
jittered light the pale wall behind a row by the wall (H 80..87, S 32..36) and a plate's sunlit
edge (S ~24) can fall in ``white``; the detector drops bloom-coloured blobs with no leaf
around them (``perception.config.FlowerConfig.min_leaf_ring``).

Public API: :func:`build_greenhouse`, :func:`greenhouse_xml`, :data:`ROBOT_XML`,
:data:`SPARE_BOXES`.
"""
from __future__ import annotations

import math
import tempfile
from pathlib import Path
from typing import Sequence
from xml.sax.saxutils import quoteattr

import mujoco

from sim.apriltag import PAPER_RGB, write_tag_png
from sim.config import GreenhouseGeometry
from sim.pests import PestSite, pest_site
from sim.walkers import CROUCH_HALF_DEPTH, CROUCH_HALF_WIDTH
from sim.world import Obstacle, Pot, World

ROBOT_XML: Path = Path(__file__).resolve().parent / "models" / "mirte_master" / "mirte_master.xml"
"""The robot model, included (never copied) by every greenhouse."""

ROBOT_SETTINGS = ('<compiler angle="radian" autolimits="true"/>\n'
                  '  <option timestep="0.005" integrator="implicitfast"/>')
"""What the robot file sets for the whole model (its ``<compiler>`` and ``<option>``): a world
that attaches its robots (a fleet's) must say it itself, as attaching takes only the robot."""

SPARE_BOXES = 4
"""Mocap boxes parked under the floor for run-time ``place_box`` faults."""

PARKED_Z = -10.0
"""Where spare boxes wait, m: far below the floor, out of every ray and camera."""

SPARE_BOX_HALF = 2.0
"""Half-size of a parked spare box as compiled, m (see :func:`_spare_box`): placed boxes up to
4 m across collide even with the compiled bounding box; ``SimFaults.place_box`` also sets the
exact ``geom_aabb``, which the broad phase reads."""

WALL_THICKNESS = 0.10
"""Wall thickness, m; walls stand outside [0, x] x [0, y], so the interior is the world's."""

OVERVIEW_MARGIN = 1.06
"""The overview camera shows the floor plus 3 % on each side."""

# Flower colours (linear RGB; MuJoCo renders without gamma). Measured on renders, HSV (OpenCV):
# red ~ (176, 239, V), white ~ (-, 0, V), pink ~ (165, 102, V); see tests/sim/test_greenhouse.py.
BLOOM_RGB = {
    "red": (0.80, 0.05, 0.15),
    "white": (0.95, 0.95, 0.95),
    "pink": (1.00, 0.60, 0.80),
}

# Bloom positions in the pot frame (+x towards the inspection aisle), m. Blooms lean towards
# the aisle, so the wrist camera at ``inspect`` (which sees the pot from the aisle side, and
# whose view sags a few degrees further down under gravity) has them in the middle of its frame.
_BLOOM_XY = {
    1: ((0.045, 0.0),),
    2: ((0.050, 0.040), (0.030, -0.042)),
    3: ((0.055, 0.042), (0.050, -0.045), (-0.010, 0.000)),
}

BLOOM_Z = 0.062
"""Height of the blooms' centres above the pot's rim, m."""

_FOLIAGE = (  # (x, y, z above the pot rim, radius, material): a low mound of leaves, lower
    (0.000, 0.000, 0.012, None, "foliage"),  # on the aisle side (+x) so blooms show over it
    (0.050, 0.038, 0.008, 0.034, "foliage_light"),
    (0.048, -0.040, 0.006, 0.033, "foliage_light"),
    (-0.045, 0.032, 0.030, 0.040, "foliage"),
    (-0.042, -0.036, 0.026, 0.038, "foliage_light"),
)


def build_greenhouse(world: World, geometry: GreenhouseGeometry | None = None,
                     robots: Sequence[str] = ("",)) -> mujoco.MjModel:
    """Compile ``world`` (with the robots at the origin; the backend sets their poses) to a model.

    ``robots``: one name prefix per robot. The default, one robot with no prefix, is the robot
    file ``<include>``d as it is. A fleet's robots (``("r1/", "r2/")``) are attached to the
    compiled world with MjSpec, each copy's names (bodies, joints, geoms, sites, cameras,
    actuators, sensors, materials) under its prefix: ``<include>`` cannot rename, and the
    backend finds each robot's devices by its prefixed names (``sim.scope``)."""
    with tempfile.TemporaryDirectory(prefix="lupin_greenhouse_") as tmp:
        if tuple(robots) == ("",):
            return mujoco.MjModel.from_xml_string(greenhouse_xml(world, geometry, Path(tmp)))
        spec = mujoco.MjSpec.from_string(greenhouse_xml(world, geometry, Path(tmp), robot=False))
        for prefix in robots:
            spec.attach(mujoco.MjSpec.from_file(str(ROBOT_XML)), prefix=prefix, frame=spec.worldbody.add_frame())
        return spec.compile()


def greenhouse_xml(world: World, geometry: GreenhouseGeometry | None, asset_dir: Path, robot: bool = True) -> str:
    """MJCF text of ``world``; writes the tag plate textures (``tag_<n>.png``) into ``asset_dir``.

    The text refers to the robot file and the textures by absolute path, so it compiles from a
    string (``MjModel.from_xml_string``) as long as ``asset_dir`` exists. ``robot`` False leaves
    the robot out (a fleet's are attached after, ``build_greenhouse``) and states the robot
    file's compiler and option settings itself, which the world's numbers (radians) rely on.
    """
    g = geometry or GreenhouseGeometry()
    asset_dir = Path(asset_dir).resolve()
    asset_dir.mkdir(parents=True, exist_ok=True)
    fx, fy = world.floor.x, world.floor.y
    extent = max(1.0, math.hypot(fx, fy) / 2)

    tags = sorted({p.tag for p in world.pots if p.tag is not None})
    tag_assets = []
    for tag in tags:
        png = write_tag_png(tag, asset_dir / f"tag_{tag}.png", margin_modules=_margin_modules(g))
        tag_assets.append(
            f'    <texture name="tag_{tag}" type="2d" file={quoteattr(str(png))}/>\n'
            f'    <material name="tag_{tag}" texture="tag_{tag}" specular="0" shininess="0"/>'
        )

    body = [_floor_and_walls(fx, fy, g)]
    body += [_pot(pot, g, world.name) for pot in world.pots]
    body += [_obstacle(i, box) for i, box in enumerate(world.obstacles)]
    body += [_spare_box(k) for k in range(SPARE_BOXES)]
    body += [_walker(w) for w in world.walkers]
    body.append(_overview_camera(fx, fy, g))

    head = f"<include file={quoteattr(str(ROBOT_XML))}/>" if robot else ROBOT_SETTINGS
    return f"""<mujoco model={quoteattr('greenhouse ' + world.name)}>
  {head}

  <statistic center="{fx / 2:.4f} {fy / 2:.4f} 0.5" extent="{extent:.4f}"/>
  <visual>
    <headlight ambient="0.40 0.40 0.40" diffuse="0.30 0.30 0.30" specular="0.02 0.02 0.02"/>
    <map znear="{0.005 / extent:.6f}" zfar="{(g.wall_height + 3.0 + 2 * extent) * 2 / extent:.4f}"/>
    <quality shadowsize="0"/>
    <global offwidth="1280" offheight="960"/>
    <rgba haze="0.75 0.82 0.85 1"/>
  </visual>

  <asset>
    <texture name="greenhouse_sky" type="skybox" builtin="gradient" rgb1="0.85 0.92 0.97"
             rgb2="0.55 0.68 0.80" width="256" height="1536"/>
    <texture name="greenhouse_floor" type="2d" builtin="checker" mark="edge" width="256" height="256"
             rgb1="0.37 0.38 0.36" rgb2="0.34 0.35 0.33" markrgb="0.27 0.28 0.27"/>
    <material name="greenhouse_floor" texture="greenhouse_floor" texuniform="true" texrepeat="2 2"
              specular="0" shininess="0" reflectance="0"/>
    <material name="greenhouse_wall" rgba="0.62 0.78 0.74 1" specular="0.1"/>
    <material name="terracotta" rgba="0.75 0.53 0.26 1" specular="0.05"/>
    <material name="soil" rgba="0.40 0.30 0.19 1" specular="0"/>
    <material name="foliage" rgba="0.24 0.55 0.20 1" specular="0.05"/>
    <material name="foliage_light" rgba="0.32 0.62 0.24 1" specular="0.05"/>
    <material name="bloom_red" rgba="{_rgb(BLOOM_RGB['red'])} 1" specular="0"/>
    <material name="bloom_white" rgba="{_rgb(BLOOM_RGB['white'])} 1" specular="0"/>
    <material name="bloom_pink" rgba="{_rgb(BLOOM_RGB['pink'])} 1" specular="0"/>
    <material name="pest" rgba="0.05 0.04 0.03 1" specular="0"/>
    <material name="plate_card" rgba="{_rgb(tuple(c / 255 for c in PAPER_RGB))} 1" specular="0"/>
    <material name="obstacle" rgba="0.30 0.40 0.55 1" specular="0.1"/>
    <material name="spare_box" rgba="0.55 0.45 0.30 1" specular="0.05"/>
    <material name="walker_clothes" rgba="0.20 0.25 0.45 1" specular="0.05"/>
    <material name="walker_skin" rgba="0.80 0.62 0.50 1" specular="0.05"/>
{chr(10).join(tag_assets)}
  </asset>

  <worldbody>
    <light name="sun" directional="true" pos="{fx / 2:.3f} {fy / 2:.3f} 6" dir="0 0 -1"
           diffuse="0.35 0.35 0.35" specular="0 0 0" castshadow="false"/>
    <light name="sky" directional="true" pos="{fx / 2:.3f} {fy / 2:.3f} 6" dir="0.4 0.5 -0.75"
           diffuse="0.15 0.15 0.15" specular="0 0 0" castshadow="false"/>
{chr(10).join(body)}
  </worldbody>
</mujoco>
"""


def _margin_modules(g: GreenhouseGeometry) -> float:
    """Quiet zone per side, in tag modules, that makes an 8-module tag fill ``tag_size`` of a
    ``plate_size`` plate."""
    return (g.plate_size - g.tag_size) / 2 / (g.tag_size / 8)


def _rgb(rgb: tuple[float, float, float]) -> str:
    return " ".join(f"{c:.3f}" for c in rgb)


def _static(name: str, extra: str) -> str:
    """A world collision geom: group 0, contype = conaffinity = 3 (hits the chassis)."""
    return f'<geom name={quoteattr(name)} group="0" contype="3" conaffinity="3" {extra}/>'


def _visual(name: str | None, extra: str) -> str:
    """A decoration: group 2, no contact, no mass."""
    named = f"name={quoteattr(name)} " if name else ""
    return f'<geom {named}group="2" contype="0" conaffinity="0" density="0" {extra}/>'


def _floor_and_walls(fx: float, fy: float, g: GreenhouseGeometry) -> str:
    t, h = WALL_THICKNESS, g.wall_height
    walls = {
        "wall_south": (fx / 2, -t / 2, fx / 2 + t, t / 2),
        "wall_north": (fx / 2, fy + t / 2, fx / 2 + t, t / 2),
        "wall_west": (-t / 2, fy / 2, t / 2, fy / 2 + t),
        "wall_east": (fx + t / 2, fy / 2, t / 2, fy / 2 + t),
    }
    lines = [
        '    <geom name="floor" type="plane" group="0" contype="1" conaffinity="1" '
        f'pos="{fx / 2:.4f} {fy / 2:.4f} 0" size="{fx / 2:.4f} {fy / 2:.4f} 0.05" material="greenhouse_floor"/>'
    ]
    for name, (cx, cy, sx, sy) in walls.items():
        lines.append("    " + _static(
            name, f'type="box" pos="{cx:.4f} {cy:.4f} {h / 2:.4f}" size="{sx:.4f} {sy:.4f} {h / 2:.4f}" '
                  'material="greenhouse_wall"'))
    return "\n".join(lines)


def _pest_place(site: PestSite, pot: Pot, h: float) -> str:
    """The pest's shape and place in the pot frame: a dark flat spot (1.3 x 1.1 cm) on the top
    of its first bloom, or lying on its leaf's surface where the leaf faces up, outwards and a
    little towards the aisle (the side the wrist camera sees it from)."""
    shape = 'type="ellipsoid" size="0.013 0.011 0.007" material="pest"'
    if site.on == "bloom":
        x, y = _BLOOM_XY[pot.blooms][site.index]
        return f'{shape} pos="{x + 0.008:.4f} {y:.4f} {h + BLOOM_Z + 0.014:.4f}"'
    x, y, dz, radius, _ = _FOLIAGE[site.index]
    n = (0.5, math.copysign(0.35, y), 0.8)
    norm = math.sqrt(sum(c * c for c in n))
    n = tuple(c / norm for c in n)
    r = radius - 0.002  # half the spot's thickness stands proud of the leaf
    return (f'{shape} pos="{x + r * n[0]:.4f} {y + r * n[1]:.4f} {h + dz + r * n[2]:.4f}" '
            f'zaxis="{n[0]:.4f} {n[1]:.4f} {n[2]:.4f}"')


def _pot(pot: Pot, g: GreenhouseGeometry, world_name: str) -> str:
    r, h = g.pot_radius, g.pot_height
    pid = pot.id
    lines = [f'    <frame name={quoteattr("pot_" + pid)} pos="{pot.x:.4f} {pot.y:.4f} 0" '
             f'euler="0 0 {pot.facing:.6f}">']
    lines.append("      " + _static(
        f"pot_{pid}_geom", f'type="cylinder" size="{r:.4f} {h / 2:.4f}" pos="0 0 {h / 2:.4f}" material="terracotta"'))
    lines.append("      " + _visual(
        f"pot_{pid}_rim",
        f'type="cylinder" size="{r + 0.008:.4f} 0.012" pos="0 0 {h - 0.012:.4f}" material="terracotta"'))
    lines.append("      " + _visual(
        f"pot_{pid}_soil", f'type="cylinder" size="{r - 0.005:.4f} 0.002" pos="0 0 {h + 0.001:.4f}" material="soil"'))
    for k, (x, y, dz, radius, material) in enumerate(_FOLIAGE):
        if radius is None:
            shape = f'type="ellipsoid" size="{0.8 * r:.4f} {0.8 * r:.4f} 0.035"'
        else:
            shape = f'type="sphere" size="{radius:.4f}"'
        lines.append("      " + _visual(
            f"pot_{pid}_leaf_{k}", f'{shape} pos="{x:.4f} {y:.4f} {h + dz:.4f}" material="{material}"'))
    if pot.flower != "none":
        bloom_z = h + BLOOM_Z
        for k, (x, y) in enumerate(_BLOOM_XY[pot.blooms]):
            lines.append("      " + _visual(
                f"pot_{pid}_bloom_{k}",
                f'type="ellipsoid" size="0.032 0.032 0.018" pos="{x:.4f} {y:.4f} {bloom_z:.4f}" '
                f'material="bloom_{pot.flower}"'))
    site = pest_site(world_name, pot, g.leaf_pest_share)
    if site is not None:
        lines.append("      " + _visual(f"pot_{pid}_pest", _pest_place(site, pot, h)))
    if pot.tag is not None:
        # A card tangent to the pot on its facing side (+x), centred at plate_height, with the
        # printed tag as a thin textured skin on its front face (texture row 0 at the top). The
        # skin is 1 mm thick so its textured edges never show; the card's edges are card colour.
        half = g.plate_size / 2
        card, skin = 0.0015, 0.0005
        lines.append("      " + _visual(
            f"tag_{pid}_card",
            f'type="box" size="{card:.4f} {half:.4f} {half:.4f}" pos="{r + card:.4f} 0 {g.plate_height:.4f}" '
            'material="plate_card"'))
        lines.append("      " + _visual(
            f"tag_{pid}",
            f'type="box" size="{skin:.4f} {half:.4f} {half:.4f}" pos="{r + 2 * card + skin:.4f} 0 '
            f'{g.plate_height:.4f}" material="tag_{pot.tag}"'))
    lines.append("    </frame>")
    return "\n".join(lines)


def _obstacle(i: int, box: Obstacle) -> str:
    return "    " + _static(
        f"obstacle_{i}",
        f'type="box" pos="{box.x:.4f} {box.y:.4f} {box.h / 2:.4f}" size="{box.sx / 2:.4f} {box.sy / 2:.4f} '
        f'{box.h / 2:.4f}" euler="0 0 {box.yaw:.6f}" material="obstacle"')


def _spare_box(k: int) -> str:
    """A parked box. Its compiled size (half-sizes SPARE_BOX_HALF) is deliberately bigger than
    any box a fault places: MuJoCo's broad phase tests the geom's compiled bounding box
    (``geom_aabb``), so a backend that only rewrites ``geom_size`` and ``geom_rbound`` still
    gets every contact, as long as the placed box fits inside the compiled one."""
    size = f"{SPARE_BOX_HALF} {SPARE_BOX_HALF} {SPARE_BOX_HALF}"
    return (f'    <body name="spare_box_{k}" mocap="true" pos="{10.0 * k:.1f} 0 {PARKED_Z}">\n'
            "      " + _static(f"spare_box_{k}_geom", f'type="box" size="{size}" material="spare_box"') + "\n"
            "    </body>")


def _walker(w) -> str:
    """A person (or one pushing a cart) facing +x in its body frame, feet on the floor: legs
    0.85 m, torso to 1.5 m, head to 1.75 m; as wide as ``w.width`` across the shoulders, the
    legs apart by half of it, and as deep as a person (0.25 m) unless it pushes a cart (then a
    cart-deep box in front at knee height). A crouching worker is one block (sim.walkers'
    ``CROUCH_HALF_*``) with the head on top: the lidar sees one solid blob, no legs."""
    x0, y0 = w.path[0]
    parts = _crouching(w) if w.posture == "crouching" else _standing(w)
    inner = "\n".join("      " + p for p in parts)
    return f'    <body name="walker_{w.id}" mocap="true" pos="{x0:.4f} {y0:.4f} 0">\n{inner}\n    </body>'


def _standing(w) -> list[str]:
    half, leg = w.width / 2, 0.07
    parts = [
        _static(f"walker_{w.id}_leg_l", f'type="capsule" fromto="0 {half / 2:.3f} 0.08 0 {half / 2:.3f} 0.85" '
                f'size="{leg}" material="walker_clothes"'),
        _static(f"walker_{w.id}_leg_r", f'type="capsule" fromto="0 {-half / 2:.3f} 0.08 0 {-half / 2:.3f} 0.85" '
                f'size="{leg}" material="walker_clothes"'),
        _static(f"walker_{w.id}_torso", f'type="box" pos="0 0 1.18" size="0.12 {half:.3f} 0.32" material="walker_clothes"'),
        _static(f"walker_{w.id}_head", 'type="sphere" pos="0 0 1.64" size="0.11" material="walker_skin"'),
    ]
    if w.pushes_cart:  # the cart: a box in front at knee height, as wide as the walker
        parts.append(_static(f"walker_{w.id}_cart", f'type="box" pos="0.45 0 0.45" size="0.3 {half:.3f} 0.25" '
                             'material="spare_box"'))
    return parts


def _crouching(w) -> list[str]:
    hx, hy = CROUCH_HALF_DEPTH, CROUCH_HALF_WIDTH
    return [
        _static(f"walker_{w.id}_body", f'type="box" pos="0 0 0.4" size="{hx:.3f} {hy:.3f} 0.4" material="walker_clothes"'),
        _static(f"walker_{w.id}_head", 'type="sphere" pos="0.05 0 0.89" size="0.11" material="walker_skin"'),
    ]


def _overview_camera(fx: float, fy: float, g: GreenhouseGeometry) -> str:
    """Orthographic, straight down, image up = north (+y), right = east (+x). ``fovy`` of an
    orthographic camera is the height of the view in metres: the floor's y extent plus a margin,
    so an image with the floor's aspect ratio (x/y, as ``lupin sim snapshot`` renders it)
    shows the whole floor."""
    height = g.wall_height + 3.0
    view = OVERVIEW_MARGIN * fy
    return (f'    <camera name="overview" projection="orthographic" fovy="{view:.4f}" '
            f'pos="{fx / 2:.4f} {fy / 2:.4f} {height:.2f}" xyaxes="1 0 0 0 1 0"/>')


__all__ = ["build_greenhouse", "greenhouse_xml", "ROBOT_XML", "SPARE_BOXES", "PARKED_Z", "SPARE_BOX_HALF"]
