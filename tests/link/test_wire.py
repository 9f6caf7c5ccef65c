"""The link's wire format: grid deltas rebuild the grid exactly; lost deltas heal at a keyframe."""
from __future__ import annotations

import numpy as np
import pytest

from mission.link.wire import Grid, GridSender, apply_grid, frame, unframe


def grid(data):
    return Grid(np.asarray(data, np.int8), 0.05, -1.0, -2.0)


def test_full_then_deltas_rebuild_the_grid_and_only_changed_tiles_travel():
    rng = np.random.default_rng(1)
    g = grid(rng.integers(-1, 101, (100, 130)))
    sender, held = GridSender(keyframe=1000), None
    first = sender.encode(g)
    held = apply_grid(held, first)
    assert np.array_equal(held.data, g.data) and (held.resolution, held.origin_x, held.origin_y) == (0.05, -1.0, -2.0)
    assert sender.encode(g) is None  # nothing changed: nothing sent
    g.data[40, 70] = 100
    g.data[99, 129] = 0  # the ragged last tile
    delta = sender.encode(g)
    header, _ = unframe(delta)
    assert header["kind"] == "delta" and len(header["tiles"]) == 2
    assert len(delta) < len(first) / 10
    held = apply_grid(held, delta)
    assert np.array_equal(held.data, g.data)


def test_a_lost_delta_is_healed_by_the_next_keyframe_and_a_resize_is_sent_whole():
    g = grid(np.zeros((64, 64)))
    sender = GridSender(keyframe=3)
    held = apply_grid(None, sender.encode(g))
    g.data[0, 0] = 100
    sender.encode(g)  # lost on the way
    g.data[63, 63] = 100
    held = apply_grid(held, sender.encode(g))  # the 3rd frame: a keyframe
    assert np.array_equal(held.data, g.data)
    bigger = grid(np.ones((80, 64)))
    header, _ = unframe(sender.encode(bigger))
    assert header["kind"] == "full"


def test_a_delta_for_another_size_is_ignored_and_garbage_is_an_error():
    sender = GridSender()
    small = apply_grid(None, sender.encode(grid(np.zeros((10, 10)))))
    other = GridSender()
    other.encode(grid(np.zeros((20, 20))))
    delta = other.encode(grid(np.eye(20)))
    assert apply_grid(small, delta) is small and not small.data.any()
    with pytest.raises(ValueError):
        unframe(b"\x00\x00\x01\x00{}")
    assert unframe(frame({"a": 1}, b"xyz")) == ({"a": 1}, b"xyz")
