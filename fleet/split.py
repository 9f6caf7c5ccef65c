"""The fleet's split: which robot inspects which pots, so that the last robot is home soonest.

spec/fleet.md "The fleet patrol": the pots go to the robots that are up, each robot driving a
tour from its own dock through its pots and back and stopping at each, and the figure that
counts is the longest of those (the makespan; a stop costs ``PER_POT_M`` of driving). That is
the min-max multiple-depot travelling salesman problem; a dispatcher needs a good answer in
seconds, so this is the usual local search on it (Golden, Laporte & Taillard, "An adaptive
memory heuristic for a class of vehicle routing problems with minmax objective", 1997, its
improvement step): start each pot at its nearest dock, then keep moving a piece from the robot
with the longest tour to another robot, or trading it for one of theirs, while that shortens the
makespan. Each robot's tour is ``nav.tour``'s (nearest neighbour, 2-opt, Or-opt); a trial move
is scored by cutting the piece out of one tour and inserting it whole, both ways round, at its
cheapest place in the other (exact for the orders tried, and an upper bound on the tour the
robot will drive).

A piece is an aisle (spec/fleet.md "Aisles": robots must not criss-cross, and two robots in one
aisle wait on each other's lock), so the split first moves whole aisles; then, from that
answer, single pots. The pot-level answer is taken only when it brings the fleet home more than
``KEEP_WHOLE`` sooner, counting the waits at the locks the path lengths do not see: a robot
with pots in an aisle another robot also works in may wait, at worst, for all of the other's
stops there and a pass along it (one robot at a time in an aisle). Measured without that count
on ``fleet.patrol_small``'s 24 pots: the middle aisle's 12 pots went 10 to one robot and one
each to the other two, who waited 60 s apiece outside it, and three robots were home later
than the 5 % the split had won.

Distances are the planner's path lengths (``nav.path_lengths`` between the pots,
``nav.path_lengths.lengths_from`` from each dock), in metres; any symmetric lengths do.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

import numpy as np

from nav.tour import shortest_tour, tour_length

KEEP_WHOLE = 0.05
"""An aisle is split between robots only when that brings the last robot home more than 5 %
sooner: below that, the lock waits and the crossing in the aisle's ends cost more than the
metres saved (the issue: "aisles kept whole per robot where that costs little")."""
PER_POT_M = 2.4
"""What a pot costs beyond driving, in metres of driving at the robot's pace: the default
greenhouse's 12 pots take about 107 s of robot time (README) on a ~14 m tour driven at ~0.4 m/s
on average (MPPI's vx_max 0.5 less the turns), ~6 s a pot at a stop (read the tag, arm out,
detect, arm back), which is ~2.4 m. It makes a robot of many pots in a short aisle as late as
one of few pots far away. Not tuned: a first figure from one run, to refine from fleet runs."""
NO_AISLE = -1
"""The aisle label of a pot that stands in no aisle (open floor): a piece of its own."""


@dataclass(frozen=True)
class Split:
    """Each robot's pots (indices into the mission's pots) in their visiting order, its tour
    length from its dock back to it, m, and what a pot costs on top (``PER_POT_M``)."""

    parts: dict[str, list[int]]
    lengths: dict[str, float]
    per_pot: float = PER_POT_M

    def cost(self, robot: str) -> float:
        """The robot's tour and its stops, in metres of driving."""
        return self.lengths[robot] + self.per_pot * len(self.parts[robot])

    @property
    def makespan(self) -> float:
        """The costliest robot's, m of driving: when the last robot is home."""
        return max((self.cost(r) for r in self.parts), default=0.0)


def split_pots(between: np.ndarray, from_dock: Mapping[str, np.ndarray], aisles: Sequence[int] | None = None,
               up: Sequence[str] | None = None, keep_whole: float = KEEP_WHOLE, per_pot: float = PER_POT_M) -> Split:
    """Divide the pots between the robots ``up`` (default: every robot in ``from_dock``).
    ``between``: (N, N) path lengths between the pots; ``from_dock[robot]``: (N,) from its dock
    to each pot; ``aisles``: each pot's aisle (``NO_AISLE``: none), default none; ``per_pot``:
    a pot's stop in metres of driving. A robot not up gets nothing (and no entry)."""
    n = len(between)
    robots = sorted(up if up is not None else from_dock)
    if not robots:
        raise ValueError("no robot is up to take the pots")
    labels = np.full(n, NO_AISLE) if aisles is None else np.asarray(aisles)
    tours = _Tours(between, {r: np.asarray(from_dock[r], dtype=float) for r in robots}, per_pot)
    whole = _pieces(labels)
    starts = (tours.nearest_docks(whole), tours.farthest_first(whole))
    by_aisle = min((tours.improve(s, whole, swaps=True) for s in starts), key=lambda p: _ranked(
        tours.cost(r, o) for r, o in p.items()))
    by_pot = tours.improve({r: list(o) for r, o in by_aisle.items()}, [[k] for k in range(n)])
    waits = tours.lock_waits(by_pot, labels)
    best = by_pot if max(tours.cost(r, o) + waits[r] for r, o in by_pot.items()) < \
        (1.0 - keep_whole) * tours.makespan(by_aisle) else by_aisle
    return Split({r: [int(k) for k in best[r]] for r in robots}, {r: tours.length(r, best[r]) for r in robots}, per_pot)


def _pieces(labels: np.ndarray) -> list[list[int]]:
    """The pots grouped by aisle (each pot in no aisle alone), in the order they first appear."""
    groups: dict[object, list[int]] = {}
    for k, a in enumerate(labels.tolist()):
        groups.setdefault(("pot", k) if a == NO_AISLE else ("aisle", a), []).append(k)
    return list(groups.values())


class _Tours:
    """Tour lengths for each robot over ``[dock, pots...]`` (node 0 its dock, pot k node k + 1)."""

    def __init__(self, between: np.ndarray, from_dock: dict[str, np.ndarray], per_pot: float):
        self.between, self.per_pot = np.asarray(between, dtype=float), per_pot
        self.ext = {}
        for r, fd in from_dock.items():
            m = np.zeros((len(fd) + 1, len(fd) + 1))
            m[0, 1:] = m[1:, 0] = fd
            m[1:, 1:] = self.between
            self.ext[r] = m

    def length(self, robot: str, order: Sequence[int]) -> float:
        return tour_length(self.ext[robot], [0, *(k + 1 for k in order), 0]) if len(order) else 0.0

    def cost(self, robot: str, order: Sequence[int]) -> float:
        return self.length(robot, order) + self.per_pot * len(order)

    def makespan(self, parts: dict[str, list[int]]) -> float:
        return max(self.cost(r, o) for r, o in parts.items())

    def lock_waits(self, parts: dict[str, list[int]], labels: np.ndarray) -> dict[str, float]:
        """What each robot may wait at the aisle locks, m of driving: in every aisle it shares
        with others, their stops there and a pass along it (the module docstring)."""
        waits = {r: 0.0 for r in parts}
        for a in set(labels.tolist()) - {NO_AISLE}:
            inside = np.flatnonzero(labels == a)
            mine = {r: [k for k in o if labels[k] == a] for r, o in parts.items()}
            sharing = [r for r, ks in mine.items() if ks]
            if len(sharing) < 2:
                continue
            along = float(self.between[np.ix_(inside, inside)].max())
            for r in sharing:
                waits[r] += sum(self.per_pot * len(mine[q]) + along for q in sharing if q != r)
        return waits

    def tour(self, robot: str, pots: Sequence[int], order: Sequence[int] | None = None) -> list[int]:
        """A short order for ``pots`` from the robot's dock and back: ``nav.tour``'s, or ``order``
        (the one it has) when that is shorter."""
        pots = list(pots)
        if not pots:
            return []
        nodes = [0, *(k + 1 for k in pots), 0]
        sub = self.ext[robot][np.ix_(nodes, nodes)]
        found = [pots[i - 1] for i in shortest_tour(sub, 0, len(nodes) - 1)]
        if order is not None and self.length(robot, order) <= self.length(robot, found):
            return list(order)
        return found

    def nearest_docks(self, pieces: list[list[int]]) -> dict[str, list[int]]:
        """Each piece to the robot whose dock is nearest it."""
        got: dict[str, list[int]] = {r: [] for r in self.ext}
        for piece in pieces:
            got[min(self.ext, key=lambda r: (self.ext[r][0, np.asarray(piece) + 1].min(), r))] += piece
        return {r: self.tour(r, pots) for r, pots in got.items()}

    def farthest_first(self, pieces: list[list[int]]) -> dict[str, list[int]]:
        """The pieces farthest from every dock first, each to the robot whose tour it leaves
        shortest (a greedy start that fills the far end before the near one)."""
        got: dict[str, list[int]] = {r: [] for r in self.ext}
        far = sorted(range(len(pieces)), key=lambda i: -min(m[0, np.asarray(pieces[i]) + 1].min() for m in self.ext.values()))
        for i in far:
            path = self._piece_path(pieces[i])
            r, order = min(((r, self._inserted(r, got[r], path)) for r in got), key=lambda t: (t[1][0], t[0]))
            got[r] = order[1]
        return {r: self.tour(r, pots, pots) for r, pots in got.items()}

    def _inserted(self, robot: str, order: list[int], path: list[int]) -> tuple[float, list[int]]:
        """``path`` put whole into ``order`` at its cheapest place, either way round; the cost of
        the tour so made (its stops included)."""
        m = self.ext[robot]
        nodes = np.asarray([0, *(k + 1 for k in order), 0])
        inner = tour_length(m, [k + 1 for k in path])
        base = tour_length(m, nodes.tolist()) if len(order) else 0.0
        prev, nxt = nodes[:-1], nodes[1:]
        a, b = path[0] + 1, path[-1] + 1
        fwd = m[prev, a] + m[b, nxt] - m[prev, nxt]
        rev = m[prev, b] + m[a, nxt] - m[prev, nxt]
        i, j = int(np.argmin(fwd)), int(np.argmin(rev))
        piece = path if fwd[i] <= rev[j] else path[::-1]
        at = i if fwd[i] <= rev[j] else j
        cost = base + inner + min(fwd[i], rev[j]) + self.per_pot * (len(order) + len(path))
        return cost, order[:at] + list(piece) + order[at:]

    def _piece_path(self, piece: list[int]) -> list[int]:
        """The piece's pots in a short open order (an aisle end to end)."""
        if len(piece) == 1:
            return list(piece)
        sub = self.between[np.ix_(piece, piece)]
        first = int(np.argmax(sub.sum(axis=1)))  # an end of the aisle
        return [piece[first], *(piece[i] for i in shortest_tour(sub, first))]

    def improve(self, parts: dict[str, list[int]], pieces: list[list[int]], swaps: bool = False) -> dict[str, list[int]]:
        """Move pieces off the longest tour (or, with ``swaps``, trade one for another robot's)
        while that shortens the tours, longest first (compared as the lengths sorted longest
        first, so a tie for the longest still moves)."""
        paths = [self._piece_path(p) for p in pieces]
        for _ in range(4 * len(pieces) + 4):
            lengths = {r: self.cost(r, o) for r, o in parts.items()}
            worst = max(sorted(lengths), key=lambda r: lengths[r])
            best, move = _ranked(lengths.values()), None
            for path in (p for p in paths if set(parts[worst]).issuperset(p)):
                left = [k for k in parts[worst] if k not in set(path)]
                cut = self.cost(worst, left)
                for r in (q for q in parts if q != worst):
                    grown, order = self._inserted(r, parts[r], path)
                    score = _ranked({**lengths, worst: cut, r: grown}.values())
                    if score < best:
                        best, move = score, (r, left, order)
                    for other in (p for p in paths if swaps and set(parts[r]).issuperset(p)):
                        mine, mine_order = self._inserted(worst, left, other)
                        theirs, their_order = self._inserted(r, [k for k in parts[r] if k not in set(other)], path)
                        score = _ranked({**lengths, worst: mine, r: theirs}.values())
                        if score < best:
                            best, move = score, (r, mine_order, their_order)
            if move is None:
                break
            r, mine, theirs = move
            parts[worst] = self.tour(worst, mine, mine)
            parts[r] = self.tour(r, theirs, theirs)
        return parts


def _ranked(lengths) -> tuple[float, ...]:
    """Tour lengths longest first, rounded to a millimetre (a move must gain more than that)."""
    return tuple(sorted((round(v, 3) for v in lengths), reverse=True))
