"""What the detectors report: small frozen records the mission stores as they are.

A flower frame is a tuple of :class:`Bloom` (class, centroid, area, confidence, pest) and a
tuple of :class:`Pest` (on a bloom or on a leaf, centroid, area, confidence) with the per-frame
summary the patrol report needs (dominant class, its count, any pest). A tag read is
a :class:`TagRead`: id, corners, pose in the camera frame (OpenCV axes: x right, y down, z
forward), distance and off-axis angle. ``as_dict`` gives the JSON of spec/cli.md.
"""
from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass

NO_FLOWER = "none"


@dataclass(frozen=True)
class Bloom:
    cls: str
    """HSV class name ('red', 'white', 'pink' by default)."""
    centroid: tuple[float, float]
    """Pixel (x, y) of the blob's centre of mass."""
    area: int
    """Blob area, px, pest spot included."""
    confidence: float
    """0..1: class purity x min(1, area / confidence_area_px)."""
    bug: bool
    """A dark pest spot sits on this bloom."""

    def as_dict(self) -> dict:
        return {"class": self.cls, "centroid": [round(c, 1) for c in self.centroid], "area": self.area,
                "confidence": round(self.confidence, 3), "bug": self.bug}


@dataclass(frozen=True)
class Pest:
    on: str
    """What the dark spot sits on: 'bloom' or 'leaf'."""
    centroid: tuple[float, float]
    """Pixel (x, y) of the spot's centre of mass."""
    area: int
    """Spot area, px."""
    confidence: float
    """0..1: the share of the ring around the spot that is its bloom (or leaf) x
    min(1, area / pest_confidence_area_px)."""

    def as_dict(self) -> dict:
        return {"on": self.on, "centroid": [round(c, 1) for c in self.centroid], "area": self.area,
                "confidence": round(self.confidence, 3)}


@dataclass(frozen=True)
class FlowerFrame:
    """One wrist frame's blooms and pests, largest first."""

    blooms: tuple[Bloom, ...] = ()
    pests: tuple[Pest, ...] = ()
    """Every pest seen, on a bloom (that bloom's ``bug`` is set) or on a leaf."""

    @property
    def flower(self) -> str:
        """The frame's class: the class with the largest total area, or 'none'."""
        if not self.blooms:
            return NO_FLOWER
        area: Counter[str] = Counter()
        for b in self.blooms:
            area[b.cls] += b.area
        return area.most_common(1)[0][0]

    @property
    def count(self) -> int:
        """Blooms of the frame's class."""
        return sum(b.cls == self.flower for b in self.blooms)

    @property
    def bug(self) -> bool:
        """A pest on the plant: on any bloom or on a leaf."""
        return bool(self.pests) or any(b.bug for b in self.blooms)

    @property
    def pest(self) -> Pest | None:
        """The surest pest (None: no pest)."""
        return max(self.pests, key=lambda p: p.confidence, default=None)

    @property
    def confidence(self) -> float:
        """Best confidence among blooms of the frame's class (0 with no bloom)."""
        return max((b.confidence for b in self.blooms if b.cls == self.flower), default=0.0)

    def as_dict(self) -> dict:
        return {"class": self.flower, "count": self.count, "bug": self.bug,
                "detections": [b.as_dict() for b in self.blooms], "pests": [p.as_dict() for p in self.pests]}


@dataclass(frozen=True)
class TagRead:
    id: int
    """AprilTag 36h11 id (whitelisted)."""
    corners: tuple[tuple[float, float], ...]
    """Pixel corners: top-left, top-right, bottom-right, bottom-left of the printed tag."""
    position: tuple[float, float, float]
    """Tag centre in the camera frame, m (OpenCV: x right, y down, z forward)."""
    rotation: tuple[float, float, float]
    """Tag orientation in the camera frame, Rodrigues vector, rad (tag z out of the face)."""
    off_axis: float
    """Angle between the tag's normal and the line from the tag to the camera, rad: 0 head-on."""
    reprojection_px: float
    """RMS corner reprojection error of the pose, px."""

    @property
    def distance(self) -> float:
        return math.dist(self.position, (0.0, 0.0, 0.0))

    def as_dict(self) -> dict:
        return {"id": self.id,
                "pose": {"position": [round(v, 4) for v in self.position],
                         "rotation": [round(v, 4) for v in self.rotation]},
                "distance": round(self.distance, 4),
                "off_axis": round(self.off_axis, 4),
                "off_axis_deg": round(math.degrees(self.off_axis), 2),
                "corners": [[round(c, 1) for c in p] for p in self.corners],
                "reprojection_px": round(self.reprojection_px, 3)}
