"""``runtime.cpu_serve``'s pure parts: the per-window CPU rates its median and p95 come from, and
the console's tally (every snapshot asked counts: the ones not answered are ``failed``)."""
from __future__ import annotations

import json

import numpy as np
import pytest

from lupin.bench.operator import CountingLink
from lupin.bench.serve_cpu import _console_figures, cpu_windows


def test_a_steady_load_reads_the_same_in_every_window():
    t = np.arange(0.0, 31.0)  # 1 Hz readings over 30 s
    rates = cpu_windows(t, 0.08 * t, 10.0)
    assert rates.shape == (3,)
    np.testing.assert_allclose(rates, 0.08)


def test_a_busy_stretch_shows_in_its_window_only():
    t = np.arange(0.0, 31.0)
    per_s = np.where((t >= 10) & (t < 20), 0.3, 0.05)  # CPU spent in the second before each reading
    cpu = np.concatenate([[0.0], np.cumsum(per_s[:-1])])
    np.testing.assert_allclose(cpu_windows(t, cpu, 10.0), [0.05, 0.3, 0.05])


def test_the_trailing_part_window_is_left_out():
    t = np.arange(0.0, 25.0)
    assert cpu_windows(t, 0.1 * t, 10.0).size == 2


def test_irregular_readings_divide_by_their_own_span():
    t = np.array([0.0, 4.0, 10.5, 13.0, 21.0])
    cpu = np.array([0.0, 0.4, 1.05, 1.3, 4.5])  # 0.1 core to 13 s, then 0.4
    rates = cpu_windows(t, cpu, 10.0)
    np.testing.assert_allclose(rates, [1.05 / 10.5, (4.5 - 1.05) / (21.0 - 10.5)])


@pytest.mark.parametrize("t", [[], [3.0], [0.0, 5.0]])
def test_less_than_one_window_gives_none(t):
    assert cpu_windows(np.array(t), np.array(t) * 0.1, 10.0).size == 0


class _Client:
    def __init__(self, frames):
        self.frames = iter(frames)
        self.send = self.history = self.view = None

    def snapshot(self, camera):
        return next(self.frames)


def test_every_snapshot_asked_is_counted_and_the_unanswered_are_failed(tmp_path):
    link = CountingLink(_Client([b"x" * 4000, None, b"y" * 6000]))
    got = [link.snapshot("front") for _ in range(3)]
    assert got[1] is None and link.asked == 3 and link.answered == 2 and link.jpeg_bytes == [4000, 6000]
    out = tmp_path / "console.out"
    out.write_text("starting\n" + json.dumps({"connected": True, "presses": 3, "asked": link.asked,
                                               "answered": link.answered, "jpeg_bytes": link.jpeg_bytes,
                                               "cpu_s": 2.0}) + "\n")
    figures = _console_figures(out, 4.0)
    assert figures["failed"] == 1 and figures["asked"] == 3
    assert figures["jpeg_kb_median"] == 5.0 and figures["cpu_per_wall_s"] == 0.5
    assert "cpu_s" not in figures and "jpeg_bytes" not in figures  # said once, as rates


def test_a_console_that_said_nothing_is_an_error_not_zeroes(tmp_path):
    out = tmp_path / "console.out"
    out.write_text("Traceback (most recent call last):\n")
    assert "no tally" in _console_figures(out, 1.0)["error"]
