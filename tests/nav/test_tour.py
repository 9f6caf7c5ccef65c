"""The tour heuristic: every stop once, never longer than nearest-neighbour, optimal where the
optimum is known, and respecting the fixed start and end."""
from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from nav.tour import nearest_neighbour, shortest_tour, tour_length


def lengths(pts):
    pts = np.asarray(pts, dtype=float)
    return np.hypot(*(pts[:, None] - pts[None]).transpose(2, 0, 1))


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.floats(0, 50), st.floats(0, 50)), min_size=3, max_size=40), st.booleans())
def test_every_stop_once_and_never_longer_than_nearest_neighbour(pts, closed):
    d = lengths(pts)
    end = len(pts) - 1 if closed else None
    order = shortest_tour(d, 0, end)
    stops = [k for k in range(len(pts)) if k not in (0, end)]
    assert sorted(order) == stops
    nn = nearest_neighbour(d, 0, stops)
    tail = [end] if closed else []
    assert tour_length(d, [0, *order, *tail]) <= tour_length(d, [0, *nn, *tail]) + 1e-9


@pytest.mark.parametrize("seed", range(6))
def test_small_tours_are_optimal(seed):
    """Up to 7 stops, the brute-force optimum: 2-opt + Or-opt find it on these."""
    rng = np.random.default_rng(seed)
    pts = rng.uniform(0, 10, (9, 2))
    d = lengths(pts)
    best = min(tour_length(d, [0, *p, 8]) for p in itertools.permutations(range(1, 8)))
    assert tour_length(d, [0, *shortest_tour(d, 0, 8), 8]) == pytest.approx(best, rel=0.02)


def test_the_fixed_end_is_last_and_an_open_tour_ends_anywhere():
    pts = [(0, 0), (1, 0), (2, 0), (3, 0), (0, 0.1)]  # end back beside the start
    d = lengths(pts)
    assert shortest_tour(d, 0, 4) in ([1, 2, 3], [3, 2, 1])
    assert shortest_tour(d, 0, None) == [4, 1, 2, 3]  # open: pick up the one beside the start first
