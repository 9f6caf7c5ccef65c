"""Patrol settings: the beat of the tree, the waits around the cameras, what counts as a pot's tag."""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class PatrolConfig(BaseModel):
    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)

    tick_rate: float = Field(10.0, gt=0)
    """Tree ticks per second, Hz: the controllers' 10 Hz beat; every leaf only polls, so a
    faster tick buys nothing but Python time."""
    travel_pose: str = "home"
    """Arm preset between pots: ``home``, the measured minimum-gravity rest pose. Not the seed's
    ``tuck`` ("folded for travel"): folded, the arm hangs in front of the front camera and hides
    the tag plate at every approach pose (seen in the sim's front frames)."""
    arm_timeout: float = Field(15.0, gt=0)
    """Seconds for one arm move to arrive (a full-span move at 0.6 rad/s takes ~3 s)."""
    settle: float = Field(0.3, ge=0)
    """Seconds after the arm (or the base) stopped before a frame counts, so nothing is judged
    on a frame still swinging."""
    frame_timeout: float = Field(3.0, gt=0)
    """Seconds to wait for a fresh camera frame before the step fails (a 2 Hz camera gives one
    in 0.5 s)."""
    startup_timeout: float = Field(30.0, gt=0)
    """Seconds for the start-up gate (heal, readiness cascade) before the patrol fails: above
    the cascade's own 20 s ceiling, which names the missing stage first."""
    aim_xy: float = Field(0.03, gt=0)
    """The robot stopped this far (m) from its ideal approach pose, by its own belief: aim the
    wrist camera with IK at where ``inspect`` would have looked, instead of taking ``inspect``.
    Inside the goal checker's 0.25 m tolerance a bloom can leave the inspect frame (the
    perception bench shows it at the tolerance's edge)."""
    aim_yaw: float = Field(0.05, gt=0)
    """The same, for the heading error, rad."""
    bloom_height: float = Field(0.26, gt=0)
    """Height of the blooms above base_link, m: the plane the inspect view is aimed at (sim: pot
    0.25 m + bloom 0.062 m, base_link 0.051 m above the floor)."""
    tag_max_distance: float = Field(0.6, gt=0)
    """A tag read nearer than this from the approach pose is the pot's own (its plate is ~0.27 m
    from the front camera there; the next pot's is >= 0.9 m away)."""
    front_camera_mount: tuple[float, float, float] = (0.1625, 0.0, 0.15)
    """Front camera optical centre in base_link, m (the model's mount; on the robot: its URDF),
    looking along +x: places the tags it reads in the map."""
    discovered_max_distance: float = Field(1.5, gt=0)
    """Tags seen en route are placed on the map only when read nearer than this, m: further
    away the pose from a 10 cm tag is too coarse to say which pot it is on."""
    discovered_merge: float = Field(0.3, gt=0)
    """Two sightings of the same tag id within this distance, m, are one discovered tag
    (their positions are averaged)."""
