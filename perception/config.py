"""Configuration of perception: the HSV flower detector, the AprilTag reader, camera rates, the
person tracker (its section lives in ``perception.people.config``).

The HSV table starts from the original sim detector (reference/upstream.md, OpenCV H 0..179)
and is retuned on frames the sim renders at ``inspect`` under jittered lighting (the
``perception.flower`` benchmark); every field says which. Override in YAML or
``LUPIN_PERCEPTION__...``; tune on real pictures with ``lupin detect flower IMG... --annotate``.
"""
from __future__ import annotations

from typing import Optional

import numpy as np
from pydantic import Field, model_validator

from hw.camera_model import camera_matrix
from hw.config import Strict
from perception.people.config import PeopleConfig


class HsvRange(Strict):
    """A box in OpenCV HSV (H 0..179, S and V 0..255). ``h_lo > h_hi`` wraps through red
    (e.g. 150..8 means 150..179 or 0..8)."""

    h_lo: int = Field(0, ge=0, le=179)
    """Lowest hue."""
    h_hi: int = Field(179, ge=0, le=179)
    """Highest hue (below ``h_lo``: the range wraps through 0)."""
    s_lo: int = Field(0, ge=0, le=255)
    """Lowest saturation."""
    s_hi: int = Field(255, ge=0, le=255)
    """Highest saturation."""
    v_lo: int = Field(0, ge=0, le=255)
    """Lowest value (brightness)."""
    v_hi: int = Field(255, ge=0, le=255)
    """Highest value."""


def _default_classes() -> dict[str, HsvRange]:
    return {
        "red": HsvRange(h_lo=150, h_hi=8, s_lo=150, v_lo=70),
        "white": HsvRange(s_hi=38, v_lo=140),
        "pink": HsvRange(h_lo=140, h_hi=5, s_lo=40, s_hi=135, v_lo=140),
    }


class FlowerConfig(Strict):
    """The wrist-camera flower detector (a stand-in for the original's YOLO on hardware)."""

    classes: dict[str, HsvRange] = Field(default_factory=_default_classes)
    """Bloom classes, checked in this order (a pixel goes to the first class that takes it).
    Upstream table: red H 150..8, S 150..255, V 70..255; white S 0..38, V 140..255; pink
    H 140..14, S 40..135, V 140..255. Pink's hue stops at 5 instead of 14: under a warm light
    the shaded side of the orange pot reads H 11..13, S ~135, V ~147, i.e. pink, while the pink
    bloom itself sits near H 165 (``perception.flower`` on 240 jittered pots: 2 false pinks at
    14, none at 5, no pink bloom lost)."""
    bug: HsvRange = HsvRange(v_hi=49)
    """The dark pest spot (upstream: any H, any S, V < 50)."""
    leaf: HsvRange = HsvRange(h_lo=35, h_hi=85, s_lo=80, v_lo=50)
    """Leaf green: where a dark spot is a pest *on a leaf* (issue 30: pests sit on leaves at
    least as often as on flowers; upstream looked on blooms only). Not tuned: the green band
    of OpenCV hue (35..85 is 70..170 deg), saturated, and brighter than the pest class so the two
    never share a pixel. The sim's foliage reads H 53..58, S 150..165, V 80..180 at the inspect
    view; a real leaf's hue and its shaded side should be checked on pictures
    (``lupin detect flower --annotate``) before this is trusted on the robot."""
    work_width: int = Field(320, ge=64, le=4096)
    """Frames are shrunk to this width before detection, px. Pixel sizes below are for a
    640-wide frame (seed: 640x480) and are scaled to it. 320 keeps the sim's bloom at
    ``inspect`` above 1,000 px and its pest above 200, at a quarter of the full-size cost
    (``perception.flower`` benchmark: accuracy unchanged, ~4x faster)."""
    kernel_px: int = Field(5, ge=1, le=31)
    """Morphology kernel (open, then close), px (upstream: 5 px kernel)."""
    min_area_px: int = Field(150, ge=1)
    """Blooms smaller than this are dropped, px (upstream: blobs below 150 px are dropped)."""
    confidence_area_px: int = Field(2000, ge=1)
    """Area at which a pure blob reaches confidence 1 (upstream: confidence = area / 2000,
    capped); ours multiplies by the blob's class purity."""
    min_bug_area_px: int = Field(20, ge=1)
    """Smallest dark spot that counts as a pest, px (640-wide frame). The sim's pest at
    ``inspect`` covers ~900 px; 20 px keeps a pest on a far or half-hidden bloom and drops
    speckle. A choice, not a tuned value: on the ``perception.flower`` set pest recall is 100 %
    with no false pest, so there was nothing to tune against."""
    bug_enclosure: float = Field(0.5, ge=0, le=1)
    """Fraction of the ring just outside a dark spot that must be bloom for the spot to be a
    pest *on* that bloom. A spot inside a bloom scores ~1, one on its rim ~0.5, dark soil,
    shadow or a plate's ink beside a bloom ~0 (tests/perception/test_flower_detector.py)."""
    bug_ring_px: int = Field(4, ge=1, le=31)
    """Width of that ring, px."""
    min_leaf_ring: float = Field(0.05, ge=0, le=1)
    """Least share of the ring around a blob (``bug_ring_px`` wide) that must be leaf green for
    the blob to be a bloom: a bloom grows on a plant. Issue 30's view takes in more of what lies
    behind the plant, and the pale wall behind a row by a wall (H 80..87, S 32..36) and a plate's
    sunlit edge (S 24) fall in ``white``. A choice, not tuned: every bloom of the sim sits on
    its foliage, which holds far more than 5 % of its ring; set 0 to turn the rule off."""
    pest_confidence_area_px: int = Field(200, ge=1)
    """Area at which a pest's confidence reaches its enclosure share, px (640-wide frame): its
    confidence = the share of its ring that is its bloom (or leaf) x min(1, area / this). A
    choice, not tuned: ten times the smallest spot that counts, a fifth of the sim's pest at
    the inspect view (~1,000 px), so a whole pest in view is sure and a sliver is not."""


class CameraModelConfig(Strict):
    """Pinhole intrinsics of one camera: from its vertical field of view (the sim's cameras,
    and an uncalibrated robot) or from a calibration (``fx`` .. ``cy`` set)."""

    width: int = Field(640, gt=0)
    """Frame width, px (seed: 640x480 colour streams)."""
    height: int = Field(480, gt=0)
    """Frame height, px."""
    fovy_deg: float = Field(49.5, gt=0, lt=180)
    """Vertical field of view, deg (Astra Mini Pro colour: 60 x 49.5 deg; the sim's front camera)."""
    fx: Optional[float] = Field(None, gt=0)
    """Calibrated focal length x, px; unset: derived from ``fovy_deg`` (square pixels)."""
    fy: Optional[float] = Field(None, gt=0)
    """Calibrated focal length y, px."""
    cx: Optional[float] = None
    """Calibrated principal point x, px; unset: the image centre."""
    cy: Optional[float] = None
    """Calibrated principal point y, px."""
    distortion: tuple[float, ...] = ()
    """OpenCV distortion coefficients (k1, k2, p1, p2[, k3]); empty: none (the sim)."""

    @model_validator(mode="after")
    def _all_or_none(self):
        given = [v is not None for v in (self.fx, self.fy, self.cx, self.cy)]
        if any(given) and not all(given):
            raise ValueError("set all of fx, fy, cx, cy (a calibration) or none (derived from fovy_deg)")
        if len(self.distortion) not in (0, 4, 5, 8):
            raise ValueError("distortion takes 4, 5 or 8 OpenCV coefficients")
        return self

    def matrix(self) -> np.ndarray:
        """The 3x3 camera matrix K (float64, what cv2.solvePnP takes)."""
        if self.fx is None:
            return camera_matrix(self.width, self.height, self.fovy_deg)
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    def dist_coeffs(self) -> np.ndarray:
        return np.asarray(self.distortion, dtype=np.float64)


class TagConfig(Strict):
    """The front-camera AprilTag reader."""

    whitelist: tuple[int, ...] = tuple(range(22))
    """Tag ids read; others are ignored (upstream: 36h11, ids 0..21 whitelisted)."""
    tag_size: float = Field(0.10, gt=0)
    """Edge of the tag's black square, m (upstream: 0.10 m tags on hardware; the sim prints
    the same 0.10 m tag on a 0.14 m plate, sim/config.py GreenhouseGeometry)."""
    camera: CameraModelConfig = CameraModelConfig()
    """Front camera (Astra Mini Pro colour) intrinsics."""
    subpixel: bool = True
    """Refine corners to sub-pixel accuracy (cheap; the AprilTag refinement is far slower,
    reference/upstream.md) so pose error stays under 2 cm / 3 deg at the approach pose."""


class CameraRates(Strict):
    front: float = Field(2.0, gt=0, le=30)
    """Most frames per second the front camera produces, Hz. Seed: the producer-side lesson:
    never produce faster than consumers need (the vendor's native 30 fps cost ~85 % of a core);
    a tag read per approach needs far less than 30."""
    wrist: float = Field(2.0, gt=0, le=30)
    """Most frames per second the wrist camera produces, Hz (one inspection per pot)."""


class PerceptionConfig(Strict):
    """The wrist-camera flower detector and the front-camera tag reader."""

    flower: FlowerConfig = FlowerConfig()
    """HSV classes, morphology, areas and the pest rule."""
    tag: TagConfig = TagConfig()
    """Family 36h11, id whitelist, tag size and front-camera intrinsics."""
    wrist_camera: CameraModelConfig = CameraModelConfig(fovy_deg=50.0)
    """Wrist (USB gripper) camera intrinsics (sim: fovy 50 deg, untuned)."""
    rates: CameraRates = CameraRates()
    """Producer-side frame rate caps per camera."""
    people: PeopleConfig = PeopleConfig()
    """The person tracker on the lidar scan (``perception.people``)."""
    jpeg_quality: int = Field(80, ge=10, le=100)
    """JPEG quality for every frame that leaves the robot (seed: only JPEG crosses the link,
    ~50 kB per 640x480 frame)."""
