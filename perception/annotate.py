"""Detections drawn on their image, for people tuning thresholds (``lupin detect --annotate``).

Blooms: an outline circle of the blob's equivalent area at its centroid, in the class colour,
with class, confidence and a "BUG" mark. Tags: the decoded outline, the id, and the pose as
3-axis arrows (x red, y green, z blue: z out of the tag) so a wrong pose is obvious at a glance.
"""
from __future__ import annotations

import math

import cv2
import numpy as np

from perception.detections import FlowerFrame, TagRead

_CLASS_BGR = {"red": (40, 40, 230), "white": (250, 250, 250), "pink": (200, 120, 255)}
_OTHER_BGR = (0, 220, 255)
_BUG_BGR = (0, 0, 0)


def _label(image: np.ndarray, text: str, org: tuple[int, int], colour: tuple[int, int, int]) -> None:
    scale = max(0.4, image.shape[1] / 1200)
    thick = max(1, round(scale * 2))
    cv2.putText(image, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, (0, 0, 0), thick + 2, cv2.LINE_AA)
    cv2.putText(image, text, org, cv2.FONT_HERSHEY_SIMPLEX, scale, colour, thick, cv2.LINE_AA)


def draw_blooms(image: np.ndarray, frame: FlowerFrame) -> np.ndarray:
    """A copy of ``image`` (BGR) with ``frame``'s blooms drawn on it."""
    out = image.copy()
    thick = max(2, out.shape[1] // 320)
    for b in frame.blooms:
        colour = _CLASS_BGR.get(b.cls, _OTHER_BGR)
        centre = (int(round(b.centroid[0])), int(round(b.centroid[1])))
        radius = max(3, int(round(math.sqrt(b.area / math.pi))))
        cv2.circle(out, centre, radius, colour, thick, cv2.LINE_AA)
        text = f"{b.cls} {b.confidence:.2f}" + (" BUG" if b.bug else "")
        _label(out, text, (centre[0] - radius, max(12, centre[1] - radius - 6)), colour)
        if b.bug:
            cv2.circle(out, centre, radius + 2 * thick, _BUG_BGR, thick, cv2.LINE_AA)
    for p in frame.pests:  # every pest, on a bloom or on a leaf, ringed where it is
        centre = (int(round(p.centroid[0])), int(round(p.centroid[1])))
        radius = max(3, int(round(math.sqrt(p.area / math.pi)))) + 2 * thick
        cv2.circle(out, centre, radius, _BUG_BGR, thick, cv2.LINE_AA)
        _label(out, f"pest {p.confidence:.2f}", (centre[0] + radius, centre[1]), _BUG_BGR)
    _label(out, f"{frame.flower} x{frame.count}" + (" bug" if frame.bug else ""), (8, out.shape[0] - 10), _OTHER_BGR)
    return out


def draw_tags(image: np.ndarray, reads: tuple[TagRead, ...], camera_matrix: np.ndarray,
              tag_size: float) -> np.ndarray:
    """A copy of ``image`` (BGR) with each tag's outline, id, distance and pose axes."""
    out = image.copy()
    thick = max(2, out.shape[1] // 320)
    for r in reads:
        pts = np.array(r.corners, dtype=np.float64)
        cv2.polylines(out, [np.round(pts).astype(np.int32)], True, (0, 255, 0), thick, cv2.LINE_AA)
        cv2.drawFrameAxes(out, camera_matrix, np.zeros(5), np.array(r.rotation), np.array(r.position),
                          tag_size / 2, thick)
        top = pts[np.argmin(pts[:, 1])]
        _label(out, f"id {r.id}  {r.distance:.3f} m  {math.degrees(r.off_axis):.1f} deg",
               (int(pts[:, 0].min()), max(12, int(top[1]) - 8)), (0, 255, 0))
    return out
