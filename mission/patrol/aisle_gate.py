"""A patrol's gate at the aisles (spec/fleet.md "Aisles"): ask before entering, wait outside,
back out when told to yield, let go on leaving.

Before a leg the robot asks the arbiter (``mission.link.aisle_client``) for every aisle the
leg's path crosses, the one it stands in included, all at once (all or none: no robot holds one
aisle while it waits for the next). Refused, it waits *outside*: ``MOUTH`` short of the first aisle it does not hold and ``SIDE``
off its way in, beside the mouth rather than in front of it, so a robot coming out of that
aisle neither meets it in there nor drives into it on the way out (on its own path ``MOUTH``
short when the ground beside is not clear); it asks again every ``RETRY`` s.
Told to yield (its wait would close a cycle: it stands in an aisle another robot wants while it
wants theirs), it backs out of its aisle by the nearer end (by the planner's path lengths) to
beside its mouth, lets go of everything and asks again from there. On the way, the aisles it has left behind are let go
(``progress``), once its body is clear of them (``CLEAR``), not its centre: a robot standing at
a pot on an aisle's edge, its centre a few cm either side of the outline, holds that aisle.
While it drives, the planner is kept out of every aisle it does not hold (``keep_out``, the
navigator's filter of the global costmap): a replan around a robot or a person in the way
never takes it into another's aisle, the failure Open-RMF's users meet as a robot entering a
locked lane (measured here: two robots crossing at their docks swapped aisles that way). With no arbiter in the fleet (no dispatcher, a robot alone) there is no gate at
all: the patrol tree is built without one.

One request is in flight at a time (``ask``): each asks to hold exactly its aisles, so what the
robot believes it holds (``held``, set as each is sent or granted) is what the arbiter holds only
while no request overtakes an answer. With two at once, a let-go of the aisles behind (``progress``,
from what was held) sent while a leg's request was out came after its grant and freed the leg's
aisles while the robot drove into them: two robots in one aisle, in 1 run of 6 of
``tests/fleet/test_fleet_aisles.py`` with the machine loaded (stop 64).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from mission.link.aisle_client import AisleLockClient, Answer, Pending
from mission.patrol.aisle_outlines import NO_AISLE, AisleOutlines
from nav.costmap.grid import LETHAL, CostGrid

MOUTH = 0.6
"""How far short of an aisle a refused robot waits, m of its path: its 0.22 m radius clear of
the aisle's outline (``fleet.aisles.ROW_END`` already puts the outline 0.4 m past the end pots),
with room for one leaving to turn out past it."""
SIDE = 0.6
"""How far to the side of the way in a refused robot waits, m: a robot's width (0.44 m) and a
margin from the line a robot leaving the aisle drives along."""
CLEAR = 0.3
"""How far the robot's centre must be from an aisle's outline to be out of it, m: its 0.22 m
radius, and a margin for its belief of where it is against where it is."""
RETRY = 1.0
"""Seconds between a waiting robot's requests (``fleet.aisle_locks.STALE_WAIT`` counts on it)."""


@dataclass(frozen=True)
class Verdict:
    """What the leg may do now: ``go``; or drive to ``to`` (x, y) and ask again (``back_out``:
    let go of everything on getting there)."""

    go: bool
    to: np.ndarray | None = None
    back_out: bool = False
    held_by: dict[int, str] | None = None


class AisleGate:
    def __init__(self, client: AisleLockClient, outlines: AisleOutlines):
        self.client, self.outlines = client, outlines
        self.held: list[int] = []
        """The aisles the arbiter last granted this robot (and not let go since)."""
        self._masks: dict[tuple, np.ndarray] = {}
        self._asking: Pending | None = None
        """The request in flight, if any (module docstring)."""
        self.wait_s, self.waits, self.yields = 0.0, 0, 0
        """Seconds this patrol waited for aisles, the waits, and how many of them began with a yield."""

    def waited(self, seconds: float, yielded: bool) -> None:
        """A wait for aisles ended (granted, or the drive given up) after ``seconds``."""
        self.wait_s += seconds
        self.waits += 1
        self.yields += int(yielded)

    # the report's observer (``mission.patrol.report``): its ``aisles`` section
    def recorded(self, pot, entry: dict, kinds: list[str]) -> None:
        pass

    def sections(self) -> dict:
        return {"aisles": {"wait_s": round(self.wait_s, 1), "waits": self.waits, "yields": self.yields}}

    def finished(self, doc: dict) -> None:
        pass

    def want(self, path: np.ndarray) -> list[int]:
        """Every aisle ``path`` (K, 2) crosses, and the ones the robot's body is in at its start:
        one request."""
        return list(dict.fromkeys(self.outlines.near(path[:1], CLEAR) + self.outlines.along(path)))

    def keep_out(self, grid: CostGrid, here: tuple[float, float]) -> CostGrid:
        """``grid`` with every aisle the robot does not hold lethal, save any it is in at
        ``here`` (it must be able to leave): what the navigator plans a drive on."""
        closed = tuple(a for a in sorted(self.outlines.polygons)
                       if a not in self.held and a not in self.outlines.near([here], CLEAR))
        if not closed:
            return grid
        key = (grid.data.shape, grid.resolution, grid.origin_x, grid.origin_y, closed)
        if key not in self._masks:
            if len(self._masks) > 16:  # the costmap grew, or the held aisles changed many times
                self._masks.clear()
            self._masks[key] = self.outlines.cells(grid.data.shape, grid.resolution, (grid.origin_x, grid.origin_y), closed)
        data = grid.data.copy()
        data[self._masks[key]] = LETHAL
        return CostGrid(data, grid.resolution, grid.origin_x, grid.origin_y)

    @property
    def asking(self) -> bool:
        """Is a request still in flight (answered or timed out: not)?"""
        return self._asking is not None and not self._asking.answered.is_set()

    def ask(self, aisles: list[int]) -> Pending | None:
        """Ask to hold exactly ``aisles``, without waiting for the answer; None, sending
        nothing, while another request is in flight (ask again on a later tick)."""
        if self.asking:
            return None
        self._asking = self.client.ask_later(aisles)
        return self._asking

    def verdict(self, path: np.ndarray, want: list[int], answer: Answer | None,
                lengths_from_here: Callable[[np.ndarray], np.ndarray]) -> Verdict:
        """What the robot at ``path[0]`` does on ``answer`` to its request for ``want`` (None:
        none came, as refused). ``lengths_from_here``: the planner's path lengths from the
        robot to points (inf: unreachable), to wait and back out by. With no answer the arbiter
        may have granted it or not: the robot counts on holding only what it held either way."""
        if answer is not None and answer.granted:
            self.held = want
            return Verdict(True)
        if answer is None:
            self.held = [a for a in self.held if a in want]
        if answer is not None and answer.yield_:
            return Verdict(False, self._open_ground(path[0], lengths_from_here), back_out=True, held_by=answer.held_by)
        return Verdict(False, self._outside(path, lengths_from_here), held_by=answer.held_by if answer is not None else None)

    def enter(self, path: np.ndarray, lengths_from_here: Callable[[np.ndarray], np.ndarray]) -> Verdict:
        """Ask for ``path``'s aisles and wait for the answer (a tool, a test; the patrol asks
        without waiting: ``behaviours.aisles``)."""
        want = self.want(path)
        if self._asking is not None:  # one at a time, this one too
            self._asking.answered.wait(self.client.timeout + 1.0)
        return self.verdict(path, want, self.client.ask(want), lengths_from_here)

    def backed_out(self) -> bool:
        """On open ground after yielding, or at the patrol's end: let go of every aisle. False
        while another request is in flight (nothing sent: call again on a later tick)."""
        if self.ask([]) is None:
            return False
        self.held = []
        return True

    def progress(self, ahead: np.ndarray) -> None:
        """Driving, ``ahead`` (K, 2) the path left from the robot: let go of the aisles behind,
        ``CLEAR`` of it (asking for fewer than it holds is always granted); while another
        request is in flight, on a later call."""
        near = self.outlines.near(ahead, CLEAR)
        keep = [a for a in self.held if a in near]
        if keep != self.held and self.ask(keep) is not None:
            self.held = keep

    def _outside(self, path: np.ndarray, lengths_from_here: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
        """Beside the mouth of the first aisle on ``path`` not held (module docstring)."""
        inside = self.outlines.at(path)
        entry = next((i for i, a in enumerate(inside) if a != NO_AISLE and a not in self.held), len(path))
        if entry == 0:
            return path[0]
        run = np.r_[0.0, np.cumsum(np.hypot(*np.diff(path[:entry + 1], axis=0).T))]
        before = np.flatnonzero(run <= run[-1] - MOUTH)
        on_path = path[before[-1]] if before.size else path[0]
        way_in = path[entry] - path[max(0, entry - 3)]
        d = way_in / max(float(np.hypot(*way_in)), 1e-9)
        mouth = path[entry] - MOUTH * d
        beside = np.array([mouth + side * SIDE * np.array([-d[1], d[0]]) for side in (1.0, -1.0)])
        beside = beside[self._clear(beside)]
        if len(beside):
            lengths = lengths_from_here(beside)
            if np.isfinite(lengths).any():
                return beside[int(np.argmin(lengths))]
        return on_path

    def _clear(self, points: np.ndarray) -> np.ndarray:
        """Points ``MOUTH`` clear of every aisle (checked round a ring that far out)."""
        ok = self.outlines.at(points) == NO_AISLE
        for angle in np.arange(8) * np.pi / 4:
            ok &= self.outlines.at(points + MOUTH * np.array([np.cos(angle), np.sin(angle)])) == NO_AISLE
        return ok

    def _open_ground(self, here: np.ndarray, lengths_from_here: Callable[[np.ndarray], np.ndarray]) -> np.ndarray:
        """Out of the aisle the robot is in by its nearer end (by the way there): ``MOUTH`` past
        the end along the aisle, ``SIDE`` to either side of its line, clear of every aisle; where
        it stands when it is in none."""
        here = np.asarray(here, float)
        k = int(self.outlines.at(here)[0])
        if k == NO_AISLE:
            return here
        polygon = self.outlines.polygons[k]
        centre = polygon.mean(axis=0)
        along = np.linalg.svd(polygon - centre, full_matrices=False)[2][0]  # the aisle's long axis
        across = np.array([-along[1], along[0]])
        t = (polygon - centre) @ along
        ends = [centre + (t.min() - MOUTH) * along, centre + (t.max() + MOUTH) * along]
        points = np.array([e + side * SIDE * across for e in ends for side in (1.0, -1.0)])
        points = points[self._clear(points)]
        if not len(points):
            return here
        lengths = lengths_from_here(points)
        best = int(np.argmin(lengths))
        return points[best] if np.isfinite(lengths[best]) else here
