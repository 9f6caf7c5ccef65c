"""The HSV flower detector for wrist-camera frames (the original sim's stand-in for YOLO).

Per frame (reference/upstream.md, retuned on sim renders, see perception/config.py):

1. BGR -> HSV; each pixel goes to the first bloom class whose HSV box takes it (three table
   look-ups per pixel, see :func:`_lookup_tables`).
2. The union of the class masks is opened then closed (5 px kernel), so a red bloom whose lit
   top reads pink, or whose rim falls between classes, stays one blob; blobs below 150 px are
   dropped, and so are blobs with no leaf green around them (a bloom grows on a plant: the pale
   wall behind a row or a plate's sunlit edge reads ``white`` but is not one). Each blob's class
   is the majority of its pixels' classes, and its purity (that majority's share) scales its
   confidence = purity x min(1, area / 2000).
3. Dark pixels (the pest class, V < 50) form spots; a spot is a pest *on a bloom* when most of
   the thin ring around it is that bloom, and a pest *on a leaf* (issue 30: aphids, whitefly
   and thrips sit on leaves as often as on flowers) when, failing that, most of the ring is
   plant: leaf green (the ``leaf`` HSV box) or bloom. A hole in a bloom or a leaf is enclosed;
   dark soil, a shadow on the floor or a plate's ink is not. Each pest gets a confidence (its
   ring's share x min(1, area / ``pest_confidence_area_px``)); a plant with no bloom can have one.

Everything is whole-image OpenCV / numpy (bincounts over labelled pixels), no per-pixel or
per-blob Python loop beyond building the few result records. Frames are shrunk to
``work_width`` (320 px: a bloom at ``inspect`` still covers > 1,000 px and the pest ~200, and
every step costs a quarter of full size); config pixel sizes are for 640-wide frames and are
scaled to match, and results come back in the caller's pixels (a 4000 px photo works too).
"""
from __future__ import annotations

import cv2
import numpy as np

from perception.config import FlowerConfig, HsvRange
from perception.detections import Bloom, FlowerFrame, Pest
from perception.frames import as_bgr, fit_width

REFERENCE_WIDTH = 640
"""Pixel sizes in the config are for a 640-wide frame (seed: 640x480 cameras); the detector
scales them to the width it works at."""


def _boxes(r: HsvRange) -> list[tuple[tuple[int, int], tuple[int, int], tuple[int, int]]]:
    """``r`` as one or two plain boxes ((h), (s), (v) inclusive ranges): a wrapping hue splits."""
    hues = [(r.h_lo, r.h_hi)] if r.h_lo <= r.h_hi else [(r.h_lo, 179), (0, r.h_hi)]
    return [(h, (r.s_lo, r.s_hi), (r.v_lo, r.v_hi)) for h in hues]


def _lookup_tables(classes: list[HsvRange], bug: HsvRange,
                   leaf: HsvRange | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per-channel bit tables: bit j of ``lut[x, c]`` says channel c's value x is inside box j.
    ANDing the three channels' bits leaves the boxes a pixel is in, in three ``cv2.LUT`` calls
    instead of a mask per box; ``label_lut`` maps those bits to the first class that has one,
    ``bug_lut`` and ``leaf_lut`` to 255 where the pest box (the leaf box) is set. At most 8 boxes
    (uint8 bits)."""
    owners = ([(i + 1, box) for i, r in enumerate(classes) for box in _boxes(r)] + [(0, b) for b in _boxes(bug)]
              + [(-1, b) for b in (_boxes(leaf) if leaf is not None else [])])
    if len(owners) > 8:
        raise ValueError(f"at most 8 HSV boxes (a wrapping hue counts twice), got {len(owners)}")
    x = np.arange(256)
    lut = np.zeros((1, 256, 3), np.uint8)
    label_lut = np.zeros(256, np.uint8)
    masks = {0: np.zeros(256, np.uint8), -1: np.zeros(256, np.uint8)}
    bits = np.arange(256)
    for j, (owner, ranges) in enumerate(owners):
        for ch, (lo, hi) in enumerate(ranges):
            lut[0, :, ch] |= (((x >= lo) & (x <= hi)) << j).astype(np.uint8)
        has = (bits >> j) & 1 == 1
        if owner > 0:
            label_lut[has & (label_lut == 0)] = owner  # boxes run in class order: first class wins
        else:
            masks[owner][has] = 255
    return lut, label_lut, masks[0], masks[-1]


class FlowerDetector:
    def __init__(self, config: FlowerConfig | None = None):
        self.config = c = config or FlowerConfig()
        self.names = tuple(c.classes)
        self._lut, self._label_lut, self._bug_lut, self._leaf_lut = _lookup_tables(
            [c.classes[n] for n in self.names], c.bug, c.leaf)
        self._kernels: dict[int, tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def detect(self, frame: object) -> FlowerFrame:
        """Blooms in a BGR frame; an unusable frame (empty, wrong type) gives no bloom."""
        bgr = as_bgr(frame)
        if bgr is None:
            return FlowerFrame()
        c = self.config
        bgr, scale = fit_width(bgr, c.work_width)
        f = bgr.shape[1] / REFERENCE_WIDTH  # config pixels -> working pixels
        kernel, speck, ring = self._kernels_for(bgr.shape[1])
        classes, dark, leaf = self._classify(cv2.cvtColor(bgr, cv2.COLOR_BGR2HSV))
        bloom = cv2.morphologyEx(cv2.morphologyEx(cv2.threshold(classes, 0, 255, cv2.THRESH_BINARY)[1],
                                                  cv2.MORPH_OPEN, kernel), cv2.MORPH_CLOSE, kernel)
        n, labels, stats, centroids = cv2.connectedComponentsWithStats(bloom, connectivity=8)
        k = len(self.names) + 1
        fg = np.flatnonzero(classes)
        votes = np.bincount(labels.ravel()[fg] * k + classes.ravel()[fg], minlength=n * k).reshape(n, k)[:, 1:]
        area = stats[:, cv2.CC_STAT_AREA] / (f * f)  # in config (640-wide) pixels, pests not yet included
        keep = (np.arange(n) > 0) & (area >= c.min_area_px) & (votes.sum(1) > 0) & self._on_a_plant(labels, n, leaf, ring)
        labels[~keep[labels]] = 0  # a blob too small to be a bloom holds no pest either
        spots = self._pests(dark, leaf, labels, n, speck, ring, c.min_bug_area_px * f * f)
        pests = tuple(Pest(on, (float((x + 0.5) * scale - 0.5), float((y + 0.5) * scale - 0.5)), int(round(a * scale * scale)), conf)
                      for on, _, x, y, a, conf in spots)
        bug_area = np.zeros(n, np.int64)
        for on, owner, _, _, a, _ in spots:
            if on == "bloom":
                bug_area[owner] += a
        area = area + bug_area / (f * f)
        keep = np.flatnonzero(keep)
        if keep.size == 0:
            return FlowerFrame(pests=pests)
        cls = votes[keep].argmax(1)
        purity = votes[keep].max(1) / np.maximum(votes[keep].sum(1), 1)
        conf = purity * np.minimum(1.0, area[keep] / c.confidence_area_px)
        xy = (centroids[keep] + 0.5) * scale - 0.5  # working pixels -> the caller's pixels
        px = stats[keep, cv2.CC_STAT_AREA] + bug_area[keep]
        order = np.argsort(-px, kind="stable")
        return FlowerFrame(tuple(
            Bloom(cls=self.names[cls[i]], centroid=(float(xy[i, 0]), float(xy[i, 1])),
                  area=int(round(px[i] * scale * scale)), confidence=float(conf[i]), bug=bool(bug_area[keep[i]] > 0))
            for i in order), pests)

    __call__ = detect

    def _kernels_for(self, width: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Morphology kernel, speckle kernel and pest ring, scaled from 640-wide pixels."""
        if width not in self._kernels:
            c, f = self.config, width / REFERENCE_WIDTH

            def disc(d: float) -> np.ndarray:
                d = max(1, int(round(d))) | 1  # odd
                return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (d, d))

            self._kernels[width] = (disc(c.kernel_px * f), disc(3 * f), disc((2 * c.bug_ring_px + 1) * f))
        return self._kernels[width]

    def _classify(self, hsv: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(class image: 0 background, i + 1 for the i-th class, first class wins; pest mask;
        leaf mask)."""
        h, s, v = cv2.split(cv2.LUT(hsv, self._lut))
        boxes = cv2.bitwise_and(cv2.bitwise_and(h, s), v)
        return cv2.LUT(boxes, self._label_lut), cv2.LUT(boxes, self._bug_lut), cv2.LUT(boxes, self._leaf_lut)

    def _on_a_plant(self, labels: np.ndarray, n: int, leaf: np.ndarray, ring: np.ndarray) -> np.ndarray:
        """Per blob: at least ``min_leaf_ring`` of the ring around it is leaf. A bloom grows on a
        plant; a pale wall behind the row or a plate's sunlit edge reads ``white`` too, but has
        no leaf around it."""
        grown = cv2.dilate(labels.astype(np.uint16), ring)
        band = (grown > 0) & (labels == 0)
        owner = grown[band].astype(np.int64)
        total = np.bincount(owner, minlength=n)
        leafy = np.bincount(owner, weights=leaf[band] > 0, minlength=n)
        return leafy >= self.config.min_leaf_ring * np.maximum(total, 1)

    def _pests(self, dark: np.ndarray, leaf: np.ndarray, blooms: np.ndarray, n: int, speck: np.ndarray,
               ring: np.ndarray, min_area: float) -> list[tuple[str, int, float, float, int, float]]:
        """The pests, largest first, as (on, bloom label (0 on a leaf), centroid x, y, area,
        confidence), in working pixels: dark spots ringed by one bloom, or else by plant."""
        c = self.config
        dark = cv2.morphologyEx(dark, cv2.MORPH_OPEN, speck)
        m, spots, stats, centroids = cv2.connectedComponentsWithStats(dark, connectivity=8, ltype=cv2.CV_16U)
        if m <= 1:
            return []
        grown = cv2.dilate(spots, ring)
        band = (grown > 0) & (dark == 0)
        ring_spot = grown[band].astype(np.int64)
        total = np.bincount(ring_spot, minlength=m)
        on_leaf = np.bincount(ring_spot, weights=leaf[band] > 0, minlength=m)
        on_any_bloom = np.bincount(ring_spot, weights=blooms[band] > 0, minlength=m)
        # (spot, bloom label under its ring) pairs, counted sparsely: a textured photo can have
        # thousands of spots and blobs, too many for a dense spots x blobs table.
        keys, counts = np.unique(ring_spot * n + blooms[band], return_counts=True)
        spot, bloom = keys // n, keys % n
        on = bloom > 0
        spot, bloom, counts = spot[on], bloom[on], counts[on]
        order = np.lexsort((-counts, spot))  # per spot, the bloom holding most of its ring first
        spot, bloom, counts = spot[order], bloom[order], counts[order]
        first = np.r_[True, spot[1:] != spot[:-1]] if spot.size else np.zeros(0, bool)
        best_bloom, best_count = np.zeros(m, np.int64), np.zeros(m)
        best_bloom[spot[first]], best_count[spot[first]] = bloom[first], counts[first]
        area = stats[:, cv2.CC_STAT_AREA]
        big = (area >= min_area) & (np.arange(m) > 0) & (total > 0)
        share_bloom = best_count / np.maximum(total, 1)
        share_plant = (on_leaf + on_any_bloom) / np.maximum(total, 1)
        is_bloom = big & (share_bloom >= c.bug_enclosure)
        is_leaf = big & ~is_bloom & (on_leaf > 0) & (share_plant >= c.bug_enclosure)
        f2 = (dark.shape[1] / REFERENCE_WIDTH) ** 2
        size = np.minimum(1.0, area / (c.pest_confidence_area_px * f2))
        out = [("bloom", int(best_bloom[i]), *centroids[i], int(area[i]), float(share_bloom[i] * size[i]))
               for i in np.flatnonzero(is_bloom)]
        out += [("leaf", 0, *centroids[i], int(area[i]), float(share_plant[i] * size[i])) for i in np.flatnonzero(is_leaf)]
        return sorted(out, key=lambda p: -p[4])
