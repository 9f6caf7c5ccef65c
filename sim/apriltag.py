"""AprilTag 36h11 pictures for the simulated tag plates.

A 36h11 marker is 8 x 8 modules: a 6 x 6 data grid inside a one-module black border. The tag's
printed size (0.10 m, :class:`sim.config.GreenhouseGeometry`) is the edge of that black
border; the plate around it (0.14 m) is a light quiet zone the detector needs. The pictures
come from OpenCV's own dictionary (``cv2.aruco.DICT_APRILTAG_36h11``), the same one the
perception code decodes with, so a plate and its reading cannot disagree.

The plates are printed for the sim's flower detector as much as for the tag detector: pure
white paper would fall into the ``white`` HSV class (S <= 38, V >= 140, reference/upstream.md)
and black ink into the ``bug`` class (V < 50) wherever the wrist camera catches a plate, which
it does at ``inspect``. So the card is a pale blue (nearly as bright as white in grey, but S ~ 85)
and the ink a deep navy (as dark as black in grey, but V ~ 110): the tag detector, which works
on grey, reads them as well as black on white, and no plate pixel lands in any flower class,
not even where texture filtering blends card and ink (both are blue, so a blend stays blue; a
cream card with navy ink would blend to grey, i.e. "white").

Public API: :func:`tag_image`, :func:`write_tag_png`, :data:`MODULES`, :data:`PAPER_RGB`.
"""
from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

MODULES = 8
"""Modules across a 36h11 marker, black border included (6 data + 2 border)."""

PAPER_RGB = (160, 195, 240)
"""Colour of the plate's light parts, RGB 0..255: pale blue (HSV H 104, S 85; luma 190). Saturated
enough that a face lit to clipping (the card's top edge under the sun) stays above S 38."""

INK_RGB = (20, 35, 110)
"""Colour of the tag's dark modules, RGB 0..255: navy. It is as dark as black in grey (luma
~ 39, what the tag detector sees) but its HSV value (the largest channel, 110) keeps the lit ink
above the flower detector's pest threshold (V < 50), so the wrist camera, which catches the top
of a plate at ``inspect``, does not report every plate's ink as a pest."""

_DICTIONARY = cv2.aruco.getPredefinedDictionary(cv2.aruco.DICT_APRILTAG_36h11)


def tag_image(
    tag_id: int,
    pixels_per_module: int = 20,
    margin_modules: float = 1.6,
    paper: tuple[int, int, int] = PAPER_RGB,
    ink: tuple[int, int, int] = INK_RGB,
) -> np.ndarray:
    """The plate picture of 36h11 tag ``tag_id``: RGB uint8, square, tag centred in a margin.

    ``margin_modules`` is the quiet zone on each side in modules; the default 1.6 makes the
    picture 11.2 modules across, i.e. a 0.14 m plate around a 0.10 m tag. The margin is rounded
    to whole pixels. Row 0 is the top of the printed tag.
    """
    if not 0 <= tag_id < _DICTIONARY.bytesList.shape[0]:
        raise ValueError(f"AprilTag 36h11 ids are 0..{_DICTIONARY.bytesList.shape[0] - 1}, got {tag_id}")
    if pixels_per_module < 1:
        raise ValueError(f"pixels_per_module must be >= 1, got {pixels_per_module}")
    side = MODULES * pixels_per_module
    marker = cv2.aruco.generateImageMarker(_DICTIONARY, tag_id, side, borderBits=1)
    margin = int(round(margin_modules * pixels_per_module))
    gray = np.pad(marker, margin, constant_values=255)
    dark = gray < 128
    out = np.empty(gray.shape + (3,), dtype=np.uint8)
    out[dark] = ink
    out[~dark] = paper
    return out


def write_tag_png(tag_id: int, path: str | Path, **kwargs) -> Path:
    """Write :func:`tag_image` of ``tag_id`` to ``path`` as a PNG; returns the path."""
    path = Path(path)
    image = tag_image(tag_id, **kwargs)
    if not cv2.imwrite(str(path), cv2.cvtColor(image, cv2.COLOR_RGB2BGR)):
        raise OSError(f"could not write {path}")
    return path


__all__ = ["tag_image", "write_tag_png", "MODULES", "PAPER_RGB", "INK_RGB"]
