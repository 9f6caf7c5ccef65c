"""Maps on disk in map_server's format: a YAML file beside a PGM image, so they open in RViz,
Nav2's map_server and any image viewer (DESIGN.md; the seed's maps are
``resolution: 0.05, mode: trinary, occupied_thresh: 0.65, free_thresh: 0.25``).

The YAML holds ``image`` (relative to the YAML's folder, or absolute), ``mode``, ``resolution``,
``origin: [x, y, yaw]`` (the lower-left pixel's pose in ``map``), ``negate``,
``occupied_thresh`` and ``free_thresh``. The image's first row is the map's top (north).

Loading follows Nav2's map_server (``nav2_map_server/src/map_io.cpp``, ``loadMapFromFile``): a
pixel's occupancy probability is ``p = 1 - v / 255`` (``v / 255`` with ``negate: 1``); in
``trinary`` mode ``p > occupied_thresh`` is occupied (100), ``p < free_thresh`` free (0) and
anything else, the thresholds themselves included, unknown (-1). ``raw`` mode takes the pixel
as the value (0..100, anything else unknown) and ignores ``negate``, as Nav2 does. ``scale``
mode is not supported. Colour images are averaged to grey over their colour channels (alpha
ignored, as ROS 1's map_server does). PGM (binary P5 and ASCII P2, maxval 255) is read by the
small parser here; other formats (PNG, ...) through OpenCV.

Saving writes trinary: a cell ``>= occupied_thresh`` (65 %) is 0 (black), ``0 ..
free_thresh`` (25 %) is 254 (white), like Nav2's map_saver, but unknown (and anything between
the thresholds) is **128**, not the 205 both ROS map_savers write. The reason: map_server's
loader thresholds the pixel with the thresholds in the YAML, and 205 is p = 50/255 = 0.196,
*under* the 0.25 ``free_thresh`` we (and Nav2's saver, by default) write. ROS 1's map_saver
got away with 205 only because it hard-codes ``free_thresh: 0.196`` in the YAML (0.196 <
0.19608, so 205 stays unknown by a hair); Nav2's saver writes 205 with ``free_thresh: 0.25``,
so Nav2 reloads its own unknown space as free (slam_toolbox issue #587, navigation2 PR #5138's
discussion). 128 is p = 127/255 = 0.498, strictly between 0.25 and 0.65, so every reader
applying the file's own thresholds, strict (Nav2, ROS 1) or inclusive, sees it unknown, and
image viewers still show it mid-grey. With other thresholds ``save_map`` picks the pixel
nearest the middle of the unknown band instead. The round trip ``save -> load`` is exact for
trinary maps (every value -1, 0 or 100), and so is ``load -> save`` of a file we wrote.

Every problem a user can cause (a missing or unreadable file, bad YAML, a missing or invalid
field, a corrupt image) is one ``InputError`` naming the file and the field.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import yaml

from hw.atomic_file import write_atomic
from hw.errors import InputError
from hw.input_file import read_yaml
from nav.occupancy import FREE, FREE_MAX, OCCUPIED, OCCUPIED_MIN, UNKNOWN, OccupancyMap

OCCUPIED_THRESH = OCCUPIED_MIN / 100
FREE_THRESH = FREE_MAX / 100
PIXEL_OCCUPIED, PIXEL_FREE = 0, 254
PIXEL_UNKNOWN = 128
"""p = 127/255 = 0.498: unknown to map_server under 0.65 / 0.25 (see the module docstring)."""
MODES = ("trinary", "raw")


def save_map(m: OccupancyMap, yaml_path: str | Path, occupied_thresh: float = OCCUPIED_THRESH,
             free_thresh: float = FREE_THRESH) -> Path:
    """Write ``NAME.yaml`` and ``NAME.pgm`` beside it (each atomically: temp file, then rename;
    the PGM first, so the YAML never names a missing image). Returns the YAML's path."""
    yaml_path = Path(yaml_path)
    unknown = unknown_pixel(occupied_thresh, free_thresh)
    yaml_path.parent.mkdir(parents=True, exist_ok=True)
    pgm = yaml_path.with_suffix(".pgm")
    p = m.occupancy.astype(np.float64) / 100.0
    known = (m.occupancy >= 0) & (m.occupancy <= 100)
    pixels = np.full(m.occupancy.shape, unknown, dtype=np.uint8)
    pixels[known & (p >= occupied_thresh)] = PIXEL_OCCUPIED
    pixels[known & (p <= free_thresh)] = PIXEL_FREE
    header = f"P5\n# lupin map, {m.resolution} m/cell\n{m.width} {m.height}\n255\n".encode()
    write_atomic(pgm, header + np.ascontiguousarray(pixels[::-1]).tobytes())
    meta = {"image": pgm.name, "mode": "trinary", "resolution": float(m.resolution),
            "origin": [float(m.origin_x), float(m.origin_y), float(m.origin_yaw)], "negate": 0,
            "occupied_thresh": float(occupied_thresh), "free_thresh": float(free_thresh)}
    write_atomic(yaml_path, yaml.safe_dump(meta, sort_keys=False, default_flow_style=None).encode())
    return yaml_path


def unknown_pixel(occupied_thresh: float = OCCUPIED_THRESH, free_thresh: float = FREE_THRESH) -> int:
    """The grey a trinary save writes for unknown: 128 if map_server reads it unknown under these
    thresholds (it does for the defaults), else the pixel nearest the middle of the unknown band.

    A ``ValueError`` (a bug in the caller, not user input) if the thresholds cannot round-trip:
    black (p = 1) must be above ``occupied_thresh``, 254 (p = 1/255) below ``free_thresh``, and
    some pixel strictly between them."""
    if not (_pixel_p(PIXEL_FREE) < free_thresh < occupied_thresh < _pixel_p(PIXEL_OCCUPIED)):
        raise ValueError(f"save_map thresholds free {free_thresh}, occupied {occupied_thresh}: need "
                         f"1/255 < free_thresh < occupied_thresh < 1")
    between = [v for v in range(256) if free_thresh < _pixel_p(v) < occupied_thresh]
    if not between:
        raise ValueError(f"save_map thresholds free {free_thresh}, occupied {occupied_thresh}: no grey "
                         f"lies strictly between them, so unknown cells cannot be written")
    if PIXEL_UNKNOWN in between:
        return PIXEL_UNKNOWN
    middle = (free_thresh + occupied_thresh) / 2
    return min(between, key=lambda v: abs(_pixel_p(v) - middle))


def _pixel_p(v: int) -> float:
    """map_server's occupancy probability of a grey pixel (negate 0), computed as Nav2 does."""
    return 1.0 - v / 255.0


def load_map(yaml_path: str | Path) -> OccupancyMap:
    """Read a map_server map; an ``InputError`` naming file and field on any problem."""
    yaml_path = Path(yaml_path)
    meta = _read_yaml(yaml_path)
    image = _field(meta, yaml_path, "image", str)
    mode = _field(meta, yaml_path, "mode", str, "trinary")
    if mode not in MODES:
        raise InputError(f"{yaml_path}: mode: {mode!r} is not supported (one of {', '.join(MODES)})")
    resolution = _field(meta, yaml_path, "resolution", float)
    if not resolution > 0:
        raise InputError(f"{yaml_path}: resolution: must be > 0 m per cell, got {resolution}")
    if "origin" not in meta:
        raise InputError(f"{yaml_path}: origin: missing (required by map_server)")
    origin = meta["origin"]
    if (not isinstance(origin, (list, tuple)) or len(origin) != 3
            or not all(_is_number(v) for v in origin)):
        raise InputError(f"{yaml_path}: origin: must be three numbers [x, y, yaw], got {origin!r}")
    negate = _field(meta, yaml_path, "negate", int, 0)
    if negate not in (0, 1):
        raise InputError(f"{yaml_path}: negate: must be 0 or 1, got {negate}")
    occ_t = _field(meta, yaml_path, "occupied_thresh", float, OCCUPIED_THRESH)
    free_t = _field(meta, yaml_path, "free_thresh", float, FREE_THRESH)
    for name, v in (("occupied_thresh", occ_t), ("free_thresh", free_t)):
        if not 0.0 <= v <= 1.0:
            raise InputError(f"{yaml_path}: {name}: must be within [0, 1], got {v}")
    if free_t >= occ_t:
        raise InputError(f"{yaml_path}: free_thresh: {free_t} must be below occupied_thresh {occ_t}")
    image_path = Path(image) if Path(image).is_absolute() else yaml_path.parent / image
    pixels = read_image(image_path, yaml_path)
    if mode == "raw":
        v = np.rint(pixels).astype(np.int64)  # colour averages round as Nav2's raw mode does
        occ = np.where(v <= 100, v, UNKNOWN)
    else:
        shade = pixels / 255.0
        p = shade if negate else 1.0 - shade
        # Nav2's comparisons exactly: strict, so a pixel on a threshold is unknown.
        occ = np.where(occ_t < p, OCCUPIED, np.where(p < free_t, FREE, UNKNOWN))
    return OccupancyMap(np.ascontiguousarray(occ[::-1]).astype(np.int8), resolution,
                        float(origin[0]), float(origin[1]), float(origin[2]))


def read_image(path: Path, yaml_path: Path) -> np.ndarray:
    """The map image as grey, first row on top: PGM (P5/P2) by our own reader (uint8), other
    formats (PNG, ...) through OpenCV (colour averaged over B, G, R to float64, as map_server
    averages channels before thresholding)."""
    where = f"{yaml_path}: image: {path}"
    if not path.is_file():
        raise InputError(f"{where} does not exist" if not path.exists() else f"{where} is not a file")
    try:
        data = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{where}: cannot read ({exc.strerror or exc})") from None
    if data[:2] in (b"P5", b"P2"):
        return _parse_pgm(data, where)
    img = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED) if data else None
    if img is None or img.ndim not in (2, 3):
        raise InputError(f"{where} is not a readable image (PGM, PNG, ...)")
    if img.dtype != np.uint8:
        raise InputError(f"{where} must be 8 bits per channel, got {img.dtype}")
    if img.ndim == 3:
        return img[:, :, :3].mean(axis=2)
    return img


def _parse_pgm(data: bytes, where: str) -> np.ndarray:
    """Netpbm grey: magic, width, height, maxval (255), separated by whitespace and comments."""
    tokens, pos = [], 2
    while len(tokens) < 3:
        while pos < len(data) and data[pos:pos + 1].isspace():
            pos += 1
        if data[pos:pos + 1] == b"#":
            pos = data.find(b"\n", pos)
            pos = len(data) if pos < 0 else pos
            continue
        start = pos
        while pos < len(data) and not data[pos:pos + 1].isspace():
            pos += 1
        if start == pos:
            raise InputError(f"{where}: truncated PGM header (width, height, maxval)")
        tokens.append(data[start:pos])
    try:
        width, height, maxval = (int(t) for t in tokens)
    except ValueError:
        raise InputError(f"{where}: bad PGM header {b' '.join(tokens).decode(errors='replace')!r}") from None
    if width <= 0 or height <= 0 or maxval != 255:
        raise InputError(f"{where}: PGM must be 8-bit (maxval 255) with a positive size, got "
                         f"{width} x {height}, maxval {maxval}")
    n = width * height
    if data[:2] == b"P2":
        try:
            values = np.array(data[pos:].split(), dtype=np.int64)
        except ValueError:
            raise InputError(f"{where}: PGM pixel data is not numbers") from None
        if values.size != n or values.min(initial=0) < 0 or values.max(initial=0) > 255:
            raise InputError(f"{where}: PGM has {values.size} pixels in 0..255, expected {n}")
        return values.astype(np.uint8).reshape(height, width)
    body = data[pos + 1:]  # exactly one whitespace byte after maxval
    if len(body) < n:
        raise InputError(f"{where}: PGM is truncated: {len(body)} of {n} pixel bytes")
    return np.frombuffer(body[:n], dtype=np.uint8).reshape(height, width).copy()


def _read_yaml(path: Path) -> dict:
    meta = read_yaml(path, "map file")  # strict: a duplicate key is an error, not a silent override
    if not isinstance(meta, dict):
        raise InputError(f"{path}: a map file is a YAML mapping (image, resolution, origin, ...)")
    return meta


_MISSING = object()


def _field(meta: dict, path: Path, name: str, kind: type, default: Any = _MISSING) -> Any:
    if name not in meta:
        if default is _MISSING:
            raise InputError(f"{path}: {name}: missing (required by map_server)")
        return default
    value = meta[name]
    ok = (isinstance(value, str) if kind is str else
          _is_number(value) and (kind is float or float(value).is_integer()))
    if not ok:
        raise InputError(f"{path}: {name}: expected {'text' if kind is str else 'a number'}, got {value!r}")
    return value if kind is str else kind(value)


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
