"""Maps on disk in map_server's format: a YAML file beside a PGM image, so they open in RViz,
Nav2's map_server and any image viewer (DESIGN.md; the seed's maps are
``resolution: 0.05, mode: trinary, occupied_thresh: 0.65, free_thresh: 0.25``).

The YAML holds ``image`` (relative to the YAML's folder, or absolute), ``mode``, ``resolution``,
``origin: [x, y, yaw]`` (the lower-left pixel's pose in ``map``), ``negate``,
``occupied_thresh`` and ``free_thresh``. The image's first row is the map's top (north).

Loading follows map_server: a pixel's occupancy probability is ``p = (255 - v) / 255``
(``v / 255`` with ``negate: 1``); in ``trinary`` mode ``p >= occupied_thresh`` is occupied
(100), ``p <= free_thresh`` free (0) and anything between unknown (-1); ``raw`` mode takes the
pixel as the value (0..100, anything else unknown). Colour images are averaged to grey.

Saving writes trinary: occupied 0 (black), free 254 (white) and unknown **128**, not the 205 of
ROS's map_saver. 205 is p = 0.196, under the 0.25 free threshold this file carries, so a
reader applying the thresholds as written would take unknown space for free; 128 (p = 0.498)
is unknown under any thresholds either side of one half, inclusive or not. The round trip
``save -> load`` is exact for trinary maps (every value -1, 0 or 100), and so is
``load -> save`` of a file we wrote.

Every problem a user can cause (a missing or unreadable file, bad YAML, a missing or invalid
field, a corrupt image) is one ``InputError`` naming the file and the field.
"""
from __future__ import annotations

import math
import os
import tempfile
from pathlib import Path
from typing import Any

import cv2
import numpy as np
import yaml

from hw.errors import InputError
from nav.occupancy import FREE, OCCUPIED, UNKNOWN, OccupancyMap

OCCUPIED_THRESH = 0.65
FREE_THRESH = 0.25
PIXEL_OCCUPIED, PIXEL_FREE, PIXEL_UNKNOWN = 0, 254, 128
MODES = ("trinary", "raw")


def save_map(m: OccupancyMap, yaml_path: str | Path, occupied_thresh: float = OCCUPIED_THRESH,
             free_thresh: float = FREE_THRESH) -> Path:
    """Write ``NAME.yaml`` and ``NAME.pgm`` (each atomically: temp file, then rename)."""
    yaml_path = Path(yaml_path)
    yaml_path.parent.mkdir(parents=True, exist_ok=True)
    pgm = yaml_path.with_suffix(".pgm")
    p = m.occupancy.astype(np.float64) / 100.0
    known = (m.occupancy >= 0) & (m.occupancy <= 100)
    pixels = np.full(m.occupancy.shape, PIXEL_UNKNOWN, dtype=np.uint8)
    pixels[known & (p >= occupied_thresh)] = PIXEL_OCCUPIED
    pixels[known & (p <= free_thresh)] = PIXEL_FREE
    header = f"P5\n# lupin map, {m.resolution} m/cell\n{m.width} {m.height}\n255\n".encode()
    _atomic_write(pgm, header + np.ascontiguousarray(pixels[::-1]).tobytes())
    meta = {"image": pgm.name, "mode": "trinary", "resolution": float(m.resolution),
            "origin": [float(m.origin_x), float(m.origin_y), float(m.origin_yaw)], "negate": 0,
            "occupied_thresh": float(occupied_thresh), "free_thresh": float(free_thresh)}
    _atomic_write(yaml_path, yaml.safe_dump(meta, sort_keys=False, default_flow_style=None).encode())
    return yaml_path


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
    origin = meta.get("origin")
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
        occ = np.where(pixels <= 100, pixels, UNKNOWN)
    else:
        v = pixels.astype(np.float64) / 255.0
        p = v if negate else 1.0 - v
        occ = np.where(p >= occ_t, OCCUPIED, np.where(p <= free_t, FREE, UNKNOWN))
    return OccupancyMap(np.ascontiguousarray(occ[::-1]).astype(np.int8), resolution,
                        float(origin[0]), float(origin[1]), float(origin[2]))


def read_image(path: Path, yaml_path: Path) -> np.ndarray:
    """The map image as uint8 grey, first row on top: PGM (P5/P2) by our own reader, other
    formats (PNG, ...) through OpenCV."""
    if not path.is_file():
        raise InputError(f"{yaml_path}: image: {path} does not exist")
    data = path.read_bytes()
    if data[:2] in (b"P5", b"P2"):
        return _parse_pgm(data, path)
    img = cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED)
    if img is None or img.ndim not in (2, 3):
        raise InputError(f"{yaml_path}: image: {path} is not a readable image")
    if img.dtype != np.uint8:
        raise InputError(f"{yaml_path}: image: {path} must be 8 bits per channel, got {img.dtype}")
    if img.ndim == 3:
        img = img[:, :, :3].mean(axis=2).round().astype(np.uint8)
    return img


def _parse_pgm(data: bytes, path: Path) -> np.ndarray:
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
            raise InputError(f"{path}: truncated PGM header")
        tokens.append(data[start:pos])
    try:
        width, height, maxval = (int(t) for t in tokens)
    except ValueError:
        raise InputError(f"{path}: bad PGM header {b' '.join(tokens)!r}") from None
    if width <= 0 or height <= 0 or maxval != 255:
        raise InputError(f"{path}: PGM must be 8-bit (maxval 255) with a positive size, got "
                         f"{width} x {height}, maxval {maxval}")
    n = width * height
    if data[:2] == b"P2":
        try:
            values = np.array(data[pos:].split(), dtype=np.int64)
        except ValueError:
            raise InputError(f"{path}: PGM pixel data is not numbers") from None
        if values.size != n or values.min(initial=0) < 0 or values.max(initial=0) > 255:
            raise InputError(f"{path}: PGM has {values.size} pixels in 0..255, expected {n}")
        return values.astype(np.uint8).reshape(height, width)
    body = data[pos + 1:]  # exactly one whitespace byte after maxval
    if len(body) < n:
        raise InputError(f"{path}: PGM is truncated: {len(body)} of {n} pixel bytes")
    return np.frombuffer(body[:n], dtype=np.uint8).reshape(height, width).copy()


def _read_yaml(path: Path) -> dict:
    try:
        text = path.read_text()
    except FileNotFoundError:
        raise InputError(f"{path}: map file does not exist") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{path}: cannot read the map file ({exc})") from None
    try:
        meta = yaml.safe_load(text)
    except yaml.YAMLError as exc:
        where = getattr(exc, "problem_mark", None)
        line = f" (line {where.line + 1})" if where is not None else ""
        raise InputError(f"{path}: not valid YAML{line}") from None
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


def _atomic_write(path: Path, data: bytes) -> None:
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.chmod(tmp, 0o644)  # mkstemp makes 0600; a map is for other tools to read
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
