"""The people the robot tracks as a Foxglove scene: one entity per track, replacing the last.

Each track (``hw.people.Person``, odom frame) is a cylinder of its body's radius and a person's
height, an arrow to where it will be in ``STRIDE_S`` while it walks, and a label with its id,
speed and confidence; the same numbers are in the entity's metadata (``id``, ``speed``,
``confidence``, ``vx``, ``vy``, ``walked``), which Foxglove's panels can filter and plot. The
frame is ``odom``, the tracker's own: ``/tf`` carries ``map -> odom``, so Foxglove places them
on the map as exactly as the robot itself, with no second rounding.

Every update first deletes all the entities before it, so a track the tracker dropped vanishes
with the next update instead of standing where it was last seen; an update with no entities
(only the deletion) is how the scene empties when the last person leaves.
"""
from __future__ import annotations

import math
from typing import Collection, Sequence

from foxglove.messages import (ArrowPrimitive, Color, CylinderPrimitive, KeyValuePair, SceneEntity,
                               SceneEntityDeletion, SceneEntityDeletionType, SceneUpdate, TextPrimitive, Timestamp,
                               Vector3)

from hw.people import Person
from mission.record.messages import point_pose

FRAME = "odom"
"""The tracker's frame (``hw.people``)."""
HEIGHT = 1.7
"""Drawn height of a person, m (display only: the lidar sees legs at 0.16 m)."""
STRIDE_S = 1.0
"""The arrow reaches where the person will be in this long, s (the console's tick, too)."""
STILL = 0.1
"""m/s below which no arrow is drawn (the tracker's filter never reads exactly 0)."""
WALKED = Color(r=0.67, g=0.39, b=1.0, a=0.8)
"""Violet, as on the console: a person the distance rules act on (they have walked)."""
TRACK = Color(r=0.43, g=0.31, b=0.59, a=0.5)
"""Dim violet: a track the rules do not act on yet (standing since first seen, or a box)."""


def people_update(t: Timestamp, people: Sequence[Person], walked: Collection[int]) -> SceneUpdate:
    """Everything earlier deleted, then one entity per person in ``people``; ``walked``: the ids
    the rules act on."""
    return SceneUpdate(deletions=[SceneEntityDeletion(timestamp=t, type=SceneEntityDeletionType.All, id="")],
                       entities=[_entity(t, p, p.id in walked) for p in people])


def _entity(t: Timestamp, p: Person, walked: bool) -> SceneEntity:
    speed = math.hypot(p.vx, p.vy)
    colour = WALKED if walked else TRACK
    arrows = []
    if speed >= STILL:
        arrows.append(ArrowPrimitive(pose=point_pose(p.x, p.y, HEIGHT / 2, yaw=math.atan2(p.vy, p.vx)),
                                     shaft_length=speed * STRIDE_S, shaft_diameter=0.04, head_length=0.12,
                                     head_diameter=0.12, color=colour))
    label = f"person {p.id} {speed:.1f} m/s {p.confidence:.0%}"
    metadata = {"id": str(p.id), "speed": f"{speed:.2f}", "confidence": f"{p.confidence:.2f}",
                "vx": f"{p.vx:.2f}", "vy": f"{p.vy:.2f}", "walked": str(walked).lower()}
    return SceneEntity(
        timestamp=t, frame_id=FRAME, id=f"person-{p.id}", frame_locked=True,
        metadata=[KeyValuePair(key=k, value=v) for k, v in metadata.items()],
        cylinders=[CylinderPrimitive(pose=point_pose(p.x, p.y, HEIGHT / 2),
                                     size=Vector3(x=2 * p.radius, y=2 * p.radius, z=HEIGHT),
                                     bottom_scale=1.0, top_scale=1.0, color=colour)],
        arrows=arrows,
        texts=[TextPrimitive(pose=point_pose(p.x, p.y, HEIGHT + 0.15), billboard=True, font_size=14.0,
                             scale_invariant=True, color=colour, text=label)])
