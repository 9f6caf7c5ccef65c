"""The visit order for a patrol: a short open tour through every stop, from a start to an end.

For hundreds of pots the order decides the day: the built-in greenhouse's listed order drives
22 m where 12 m will do. Finding the shortest tour is the travelling salesman problem; a patrol
needs a good one quickly, so this is the textbook recipe (Johnson & McGeoch, "The TSP: a case
study in local optimization", 1997): a nearest-neighbour tour, then 2-opt (reverse a stretch)
and Or-opt (move a run of one to three stops elsewhere, either way round) until neither finds an
improvement. Each improvement strictly shortens the tour, so it ends, and it is never longer
than the nearest-neighbour tour it starts from.

Distances come in as a matrix over ``[start, stops..., end]`` (the planner's path lengths for
a patrol, ``nav.path_lengths``); they need not be Euclidean, only symmetric. Every move is
scored for all its positions at once with numpy, so 200 stops take a fraction of a second.
"""
from __future__ import annotations

import numpy as np


def tour_length(dist: np.ndarray, order: list[int]) -> float:
    """Length of the path visiting ``order`` (node indices) in turn."""
    idx = np.asarray(order)
    return float(dist[idx[:-1], idx[1:]].sum())


def nearest_neighbour(dist: np.ndarray, start: int, stops: list[int]) -> list[int]:
    """Greedy: from ``start``, always the nearest stop not yet visited (ties: the lower index)."""
    left, here, out = list(stops), start, []
    while left:
        k = int(np.argmin(dist[here, left]))
        here = left.pop(k)
        out.append(here)
    return out


def shortest_tour(dist: np.ndarray, start: int = 0, end: int | None = None) -> list[int]:
    """The stops (every node but ``start`` and ``end``) in a short order from ``start``, ending
    at ``end`` when given (the tour's last leg then counts); returned without start and end."""
    stops = [k for k in range(len(dist)) if k not in (start, end)]
    path = [start, *nearest_neighbour(dist, start, stops)] + ([end] if end is not None else [])
    fixed_end = end is not None
    improved = True
    while improved:
        improved = _two_opt(dist, path, fixed_end) or _or_opt(dist, path, fixed_end)
    return path[1:-1] if fixed_end else path[1:]


def _two_opt(dist: np.ndarray, path: list[int], fixed_end: bool) -> bool:
    """Apply the best reversal of a stretch ``path[i:j+1]`` (the start stays first, and the end
    last when fixed); True when one shortened the path."""
    p = np.asarray(path)
    n = len(p)
    last = n - 1 if fixed_end else n  # j may reach the last node only when it may move
    best, move = -1e-9, None
    for i in range(1, n - 1):
        j = np.arange(i + 1, last)
        if not len(j):
            continue
        before = dist[p[i - 1], p[i]] + np.where(j + 1 < n, dist[p[j], p[np.minimum(j + 1, n - 1)]], 0.0)
        after = dist[p[i - 1], p[j]] + np.where(j + 1 < n, dist[p[i], p[np.minimum(j + 1, n - 1)]], 0.0)
        gain = before - after
        k = int(np.argmax(gain))
        if gain[k] > best + 1e-9:
            best, move = gain[k], (i, int(j[k]))
    if move is None:
        return False
    i, j = move
    path[i:j + 1] = path[i:j + 1][::-1]
    return True


def _or_opt(dist: np.ndarray, path: list[int], fixed_end: bool) -> bool:
    """Apply the best move of a run of 1..3 stops to another place in the path, kept or
    reversed; True when one shortened the path."""
    n = len(path)
    last = n - 1 if fixed_end else n  # the movable nodes are path[1:last]
    best, move = 1e-9, None
    for length in (1, 2, 3):
        for i in range(1, last - length + 1):
            seg = path[i:i + length]
            rest = path[:i] + path[i + length:]
            r = np.asarray(rest)
            a, b = seg[0], seg[-1]
            after = dist[path[i - 1], path[i + length]] if i + length < n else 0.0
            removed = dist[path[i - 1], a] + (dist[b, path[i + length]] if i + length < n else 0.0) - after
            # insert between rest[k] and rest[k + 1] (k >= 0; past the end when the end is free)
            k = np.arange(0, len(rest) - (1 if fixed_end else 0))
            nxt = np.minimum(k + 1, len(rest) - 1)
            tail = k + 1 < len(rest)
            old = np.where(tail, dist[r[k], r[nxt]], 0.0)
            fwd = dist[r[k], a] + np.where(tail, dist[b, r[nxt]], 0.0) - old
            rev = dist[r[k], b] + np.where(tail, dist[a, r[nxt]], 0.0) - old
            for cost, reverse in ((fwd, False), (rev, True)):
                gain = removed - cost  # put back where it was: no gain, never chosen
                m = int(np.argmax(gain))
                if gain[m] > best:
                    best, move = gain[m], (i, length, int(k[m]), reverse)
    if move is None:
        return False
    i, length, k, reverse = move
    seg = path[i:i + length]
    rest = path[:i] + path[i + length:]
    path[:] = rest[:k + 1] + (seg[::-1] if reverse else seg) + rest[k + 1:]
    return True
