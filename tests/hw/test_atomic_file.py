"""Outputs are replaced whole: never half a file, never a stray temporary."""
from __future__ import annotations

import os
import stat

import cv2
import numpy as np
import pytest

from hw.atomic_file import write_atomic, write_png
from hw.errors import InputError


def test_write_atomic_replaces_whole_and_leaves_nothing_else(tmp_path):
    path = tmp_path / "x.json"
    write_atomic(path, b"first")
    write_atomic(path, b"second")
    assert path.read_bytes() == b"second" and [p.name for p in tmp_path.iterdir()] == ["x.json"]
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o644  # readable by the tools it is for


def test_a_failed_write_keeps_the_old_file_and_cleans_up(tmp_path, monkeypatch):
    path = tmp_path / "report.json"
    write_atomic(path, b"old")

    def boom(fd):
        raise OSError(28, "No space left on device")

    monkeypatch.setattr(os, "fsync", boom)
    with pytest.raises(OSError):
        write_atomic(path, b"new")
    assert path.read_bytes() == b"old" and [p.name for p in tmp_path.iterdir()] == ["report.json"]


def test_write_png_round_trips_and_names_the_file_it_could_not_write(tmp_path):
    img = np.zeros((20, 30, 3), np.uint8)
    img[5:10, 5:10] = (255, 0, 255)
    write_png(tmp_path / "run.png", img)
    assert np.array_equal(cv2.imread(str(tmp_path / "run.png")), img)
    with pytest.raises(InputError, match="missing/run.png: cannot write the PNG"):
        write_png(tmp_path / "missing" / "run.png", img)
    with pytest.raises(InputError, match="x.png: cannot write the PNG"):
        write_png(tmp_path / "x.png", np.zeros((0, 0, 3), np.uint8))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.png"]
