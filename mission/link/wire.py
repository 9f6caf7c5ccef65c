"""The link's wire format: keys, JSON messages and grid deltas.

Keys (Zenoh key expressions), one robot per prefix so several share a router::

    lupin/<robot>/tel/<topic>     telemetry, published (pose, nav, mission, pots, map, ...)
    lupin/<robot>/cmd/<name>      commands, answered as queries (mission.link.view.COMMANDS)

Most messages are UTF-8 JSON. Grids (the SLAM map, the inflated costmap) travel as deltas:
a frame is ``len(header) (4 bytes, big-endian) | JSON header | zlib body``. The first frame,
and any frame after the grid changed size or origin, is ``full``; otherwise only the 32 x 32
tiles that changed since the last frame are sent (``tiles``: [ix, iy, w, h] per tile, bodies
concatenated). Cells are int8: -1 unknown, 0..100.
"""
from __future__ import annotations

import json
import struct
import zlib
from dataclasses import dataclass

import numpy as np

TILE = 32
"""Cells per tile side: a pot-sized change in a 0.05 m map touches one or two tiles."""


def tel_key(robot: str, topic: str) -> str:
    return f"lupin/{robot}/tel/{topic}"


def cmd_key(robot: str, name: str) -> str:
    return f"lupin/{robot}/cmd/{name}"


def dumps(obj) -> bytes:
    return json.dumps(obj, separators=(",", ":"), allow_nan=False, default=_plain).encode()


def _plain(o):
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, np.ndarray):
        return o.tolist()
    raise TypeError(f"{type(o).__name__} is not JSON")


def frame(header: dict, body: bytes) -> bytes:
    h = dumps(header)
    return struct.pack(">I", len(h)) + h + body


def unframe(data: bytes) -> tuple[dict, bytes]:
    if len(data) < 4:
        raise ValueError("grid frame shorter than its header length")
    (n,) = struct.unpack(">I", data[:4])
    if 4 + n > len(data):
        raise ValueError("grid frame truncated")
    return json.loads(data[4:4 + n]), data[4 + n:]


@dataclass
class Grid:
    data: np.ndarray
    """int8 [iy, ix]."""
    resolution: float
    origin_x: float
    origin_y: float

    def same_frame(self, other: "Grid | None") -> bool:
        return (other is not None and other.data.shape == self.data.shape and other.resolution == self.resolution
                and other.origin_x == self.origin_x and other.origin_y == self.origin_y)


class GridSender:
    """Turns successive grids into full or delta frames (None when nothing changed). Every
    ``keyframe``-th frame is full, so a client that lost a delta (the outgoing queue drops the
    oldest when full) or joined late is whole again within that many frames."""

    def __init__(self, keyframe: int = 10):
        self.last: Grid | None = None
        self.keyframe, self._count = keyframe, 0

    def encode(self, grid: Grid) -> bytes | None:
        head = {"resolution": grid.resolution, "origin": [grid.origin_x, grid.origin_y],
                "shape": list(grid.data.shape)}
        self._count += 1
        if not grid.same_frame(self.last) or self._count % self.keyframe == 0:
            self.last = Grid(grid.data.copy(), grid.resolution, grid.origin_x, grid.origin_y)
            return frame({**head, "kind": "full"}, zlib.compress(np.ascontiguousarray(grid.data, np.int8).tobytes(), 1))
        changed = grid.data != self.last.data
        if not changed.any():
            return None
        h, w = grid.data.shape
        ty, tx = np.nonzero(_tiles_any(changed))
        tiles, bodies = [], []
        for iy, ix in zip(ty.tolist(), tx.tolist()):
            y0, x0 = iy * TILE, ix * TILE
            block = grid.data[y0:min(y0 + TILE, h), x0:min(x0 + TILE, w)]
            tiles.append([x0, y0, block.shape[1], block.shape[0]])
            bodies.append(np.ascontiguousarray(block, np.int8).tobytes())
        self.last.data[...] = grid.data
        return frame({**head, "kind": "delta", "tiles": tiles}, zlib.compress(b"".join(bodies), 1))


def _tiles_any(mask: np.ndarray) -> np.ndarray:
    """Per-tile OR of a boolean mask (vectorised: pad to whole tiles, reshape, reduce)."""
    h, w = mask.shape
    ph, pw = -h % TILE, -w % TILE
    padded = np.pad(mask, ((0, ph), (0, pw)))
    return padded.reshape((h + ph) // TILE, TILE, (w + pw) // TILE, TILE).any(axis=(1, 3))


def apply_grid(current: Grid | None, data: bytes) -> Grid | None:
    """The grid after one frame; a delta that does not fit what is held is ignored (a frame
    was dropped: the next full frame, after a change of size, resynchronises)."""
    header, body = unframe(data)
    raw = zlib.decompress(body)
    shape = tuple(int(v) for v in header["shape"])
    ox, oy = (float(v) for v in header["origin"])
    if header["kind"] == "full":
        return Grid(np.frombuffer(raw, np.int8).reshape(shape).copy(), float(header["resolution"]), ox, oy)
    if current is None or current.data.shape != shape:
        return current
    at = 0
    for x0, y0, w, h in header["tiles"]:
        current.data[y0:y0 + h, x0:x0 + w] = np.frombuffer(raw[at:at + w * h], np.int8).reshape(h, w)
        at += w * h
    return current


FLEET_STOP = "lupin/fleet/stop"
"""A query here engages every robot's soft stop (spec/fleet.md, "Names and keys")."""


def stop_key(robot: str) -> str:
    """A query here engages ``robot``'s soft stop: open to every member, unlike its commands."""
    return f"lupin/{robot}/stop"


def alive_key(robot: str) -> str:
    """``robot``'s liveliness token: held while its link is up (who is up, within a second)."""
    return f"lupin/{robot}/alive"


ALIVE = "lupin/*/alive"
