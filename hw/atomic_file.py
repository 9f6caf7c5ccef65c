"""Files other programs read while we run: written whole, or not at all.

Every output a person or a tool may open at any moment (a patrol report rewritten after each pot,
a map, a picture, a mission) goes to a temporary sibling first, is flushed to disk, and then
replaces the target with ``os.replace`` (atomic on POSIX): a reader, or a power cut, sees the old
file or the new one, never half of either. The temporary name starts with a dot, so directory
listings of outputs stay clean, and it is removed if anything fails.
"""
from __future__ import annotations

import os
import tempfile
from pathlib import Path

import cv2
import numpy as np

from hw.errors import InputError


def write_atomic(path: str | Path, data: bytes) -> None:
    """Replace ``path`` with ``data`` atomically (``OSError`` when the directory is unusable)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
            f.flush()
            os.fsync(f.fileno())
        os.chmod(tmp, 0o644)  # mkstemp makes 0600; outputs are for other tools and people to read
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def write_png(path: str | Path, image: np.ndarray) -> None:
    """Write a BGR (or grey) uint8 image as PNG, atomically; a user error names the file."""
    try:
        ok, buf = cv2.imencode(".png", image)
    except cv2.error:
        ok = False
    if not ok:
        raise InputError(f"{path}: cannot write the PNG (not an 8-bit image: {getattr(image, 'shape', '?')})")
    try:
        write_atomic(path, buf.tobytes())
    except OSError as exc:
        raise InputError(f"{path}: cannot write the PNG ({exc.strerror or exc})") from None
