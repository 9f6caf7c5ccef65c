"""The fleet scenario's judge: what the robots did to each other, on ground truth, from outside.

``FleetWatch`` reads the shared sim scene only (``sim.scene``: each robot's true pose, the
robots' chassis contacts), never a runtime, and the robots never read it back:

* robot contacts: the pairs of robots whose bodies touch, looked at before every physics chunk
  (``sim.engine``: a few ms of sim time, so no touch is too short to see); a pair that touches
  counts once per touch (its onset);
* aisles: at ``RATE`` each robot's true centre is placed in an aisle of the fleet's aisle map
  (``fleet.aisles`` on the world's plan, as the dispatcher finds them; outlines in the world
  frame). Two robots in one aisle at once is a *meeting*; it is *head-on* when they close on
  each other: the gap between them shrinks faster than ``CLOSING`` m/s while neither drives away
  from the other (a robot driving at one standing in the aisle is head-on; one following
  another that drives off is not). Each meeting counts once, however long it lasts;
* every robot's true path, to measure how far the others drove while one was held stopped.

``fleet_checks`` turns those and the fleet's summary (``fleet.json``) into the ``expect.fleet``
checks (``mission.scenario.fleet_file``); ``robot_checks`` judges the expectations of one robot's
patrol on every robot (``outcome``) or on the robots whose events they are about (``estop``,
``effects``: each robot's presses and events on its own motion log, times from its own start),
each check named after its robot (``r2: estop.still_until_resume``).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import combinations

import numpy as np

from fleet.aisles import find_aisles, outlines
from fleet.fleet_map import plan_of_world
from mission.patrol.aisle_outlines import NO_AISLE, AisleOutlines
from mission.scenario.checks import Check, effects, estop, events_fired
from mission.scenario.effects import KINDS
from mission.scenario.judge import path_length
from mission.scenario.scenario_file import Expect, FleetExpect
from sim.scene import SimScene
from sim.world import World

RATE = 20.0
"""Aisle samples per second of sim time: a robot drives at most ~2 cm between two."""
CLOSING = 0.05
"""m/s the gap between two robots in one aisle must shrink by to count as closing (not noise)."""
AWAY = 0.02
"""m/s a robot's speed away from the other must stay under for the pair to count as head-on."""


def world_aisles(world: World) -> AisleOutlines:
    """The fleet's aisles in the world frame: found on the world's plan as the dispatcher does."""
    pots = np.array([(p.x, p.y, p.facing) for p in world.pots])
    return AisleOutlines(outlines(find_aisles(plan_of_world(world, (0.0, 0.0, 0.0)), pots)))


@dataclass
class Meeting:
    """Two robots in one aisle at once, from ``start`` to ``end`` (sim time)."""

    robots: tuple[str, str]
    aisle: int
    start: float
    end: float
    nearest_m: float
    head_on: bool = False

    def as_json(self, t0: float) -> dict:
        return {"robots": list(self.robots), "aisle": self.aisle, "from_s": round(self.start - t0, 2),
                "to_s": round(self.end - t0, 2), "nearest_m": round(self.nearest_m, 3), "head_on": self.head_on}


@dataclass
class FleetWatch:
    scene: SimScene
    aisles: AisleOutlines
    t: list[float] = field(default_factory=list)
    xy: list[np.ndarray] = field(default_factory=list)
    """Each sample's true (x, y) per robot, (R, 2) in the scene's robot order, world frame."""
    contacts: list[tuple[float, str, str]] = field(default_factory=list)
    """Each touch's onset: (sim time, robot, robot)."""
    meetings: list[Meeting] = field(default_factory=list)
    _touching: set = field(default_factory=set)
    _open: dict = field(default_factory=dict)

    @property
    def names(self) -> list[str]:
        return list(self.scene.robots)

    def attach(self, scheduler) -> "FleetWatch":
        """Contacts before every physics chunk; aisles at ``RATE`` on ``scheduler`` (a robot's:
        in lock-step the engine is at the time each of its tasks runs for)."""
        self.scene.engine.attach(self)
        scheduler.every("judge.fleet", RATE, self.sample)
        return self

    def pre_chunk(self, t: float) -> None:
        now = set(self.scene.robot_contacts())
        self.contacts += [(t, a, b) for a, b in sorted(now - self._touching)]
        self._touching = now

    def sample(self, now: float) -> None:
        truths = self.scene.truths()
        xy = np.array([(truths[n].x, truths[n].y) for n in self.names], float)
        inside = self.aisles.at(xy)
        before = (self.t[-1], self.xy[-1]) if self.t else None
        self.t.append(now)
        self.xy.append(xy)
        together = set()
        for i, j in combinations(range(len(xy)), 2):
            if inside[i] == NO_AISLE or inside[i] != inside[j]:
                continue
            pair, gap = (self.names[i], self.names[j]), float(np.hypot(*(xy[j] - xy[i])))
            together.add(pair)
            m = self._open.get(pair)
            if m is None or m.aisle != inside[i]:
                m = self._open[pair] = Meeting(pair, int(inside[i]), now, now, gap)
                self.meetings.append(m)
            m.end, m.nearest_m = now, min(m.nearest_m, gap)
            if before is not None and not m.head_on:
                m.head_on = _closing(before[1][[i, j]], xy[[i, j]], now - before[0])
        for pair in set(self._open) - together:
            del self._open[pair]

    def driven(self, robot: str, start: float, end: float) -> float:
        """How far ``robot`` truly drove from ``start`` to ``end`` (sim time), m."""
        t = np.asarray(self.t)
        s = slice(max(int(np.searchsorted(t, start, side="right")) - 1, 0), int(np.searchsorted(t, end, side="right")))
        return path_length(np.asarray(self.xy, float)[s, self.names.index(robot)])


def _closing(before: np.ndarray, after: np.ndarray, dt: float) -> bool:
    """Two robots (rows) closing on each other over ``dt``: the gap shrinking faster than
    ``CLOSING`` and neither driving away from the other faster than ``AWAY``."""
    if dt <= 0:
        return False
    gap0, gap1 = np.hypot(*(before[1] - before[0])), np.hypot(*(after[1] - after[0]))
    if gap0 <= 0 or (gap0 - gap1) / dt < CLOSING:
        return False
    toward = (before[1] - before[0]) / gap0  # from the first robot to the second
    v = (after - before) / dt
    return bool(v[0] @ toward > -AWAY and v[1] @ -toward > -AWAY)


def fleet_checks(x: FleetExpect, watch: FleetWatch, summary: dict, stops: dict[str, list[tuple[float, float]]],
                 t0: float) -> list[Check]:
    """``expect.fleet`` against the watch and the fleet's summary; ``stops``: each robot's e-stop
    holds (press, release) in sim time, ``t0`` the zero of the times shown."""
    out = []
    if x.robot_contacts is not None:
        shown = ", ".join(f"{a}-{b} at {t - t0:.1f} s" for t, a, b in watch.contacts[:5]) or "none"
        out.append(Check("fleet.robot_contacts", len(watch.contacts) <= x.robot_contacts,
                         f"<= {x.robot_contacts} contact(s) between robots", f"{len(watch.contacts)} ({shown})"))
    if x.head_on_in_aisle is not None:
        head_on = [m for m in watch.meetings if m.head_on]
        shown = ", ".join(f"{'-'.join(m.robots)} in aisle {m.aisle} at {m.start - t0:.1f} s ({m.nearest_m:.2f} m)"
                          for m in head_on[:5]) or "none"
        out.append(Check("fleet.head_on_in_aisle", len(head_on) <= x.head_on_in_aisle,
                         f"<= {x.head_on_in_aisle} head-on meeting(s) in an aisle",
                         f"{len(head_on)} ({shown}); {len(watch.meetings)} time(s) two robots shared an aisle"))
    if x.pots is not None:
        out.append(_pots(x.pots, summary))
    if x.others_drive_while_stopped is not None:
        out.append(_others(x.others_drive_while_stopped, watch, stops, t0))
    return out


def _pots(want, summary: dict) -> Check:
    pots, missing = summary["pots"], set(summary["pots"]["not_inspected"])
    by = ", ".join(f"{r} {len(v['done'])}" for r, v in summary["robots"].items())
    actual = f"{pots['inspected']} of {pots['total']} inspected ({by})" + (
        f"; not inspected: {', '.join(sorted(missing))}" if missing else "")
    if want == "all":
        return Check("fleet.pots", not missing, f"all {pots['total']} pots inspected by some robot", actual)
    if isinstance(want, int):
        return Check("fleet.pots", pots["inspected"] == want, f"{want} pots inspected by some robot", actual)
    done = {p for v in summary["robots"].values() for p in v["done"]}
    return Check("fleet.pots", set(want) <= done, f"{', '.join(want)} inspected by some robot", actual)


def _others(least: float, watch: FleetWatch, stops: dict[str, list[tuple[float, float]]], t0: float) -> Check:
    expected = f"every other robot to drive >= {least:g} m while a robot was held by its e-stop"
    held = [(r, a, b) for r, spans in stops.items() for a, b in spans]
    if not held:
        return Check("fleet.others_drive_while_stopped", False, expected, "no robot was held by an e-stop")
    figures = [(r, a, o, watch.driven(o, a, b)) for r, a, b in held for o in watch.names if o != r]
    shown = ", ".join(f"{o} {d:.2f} m while {r} was held from {a - t0:.1f} s" for r, a, o, d in figures)
    return Check("fleet.others_drive_while_stopped", all(d >= least for *_, d in figures), expected, shown or "no other robot")


def robot_checks(x: Expect, robots: dict[str, dict], at_limit: bool) -> list[Check]:
    """``robots``: per robot its ``summary`` (``fleet.json``'s row), ``t0`` (its first patrol's
    start), ``presses`` and ``events`` (judged on its own log); ``at_limit``: patrols were still
    running at ``max_sim_time``."""
    out = []
    if x.outcome is not None:
        for name, r in robots.items():
            got = r["summary"].get("outcome") or "no patrol"
            out.append(Check(f"{name}: outcome", got == x.outcome, x.outcome, got))
    out.append(Check("max_sim_time", not at_limit or x.outcome == "aborted",
                     f"every patrol to end within {x.max_sim_time:g} s of the first start",
                     "still running at the limit" if at_limit else "every patrol ended"))
    out += [_robot(n, events_fired(r["events"], r["t0"])) for n, r in robots.items() if r["events"]]
    if x.estop is not None:
        pressed = {n: r for n, r in robots.items() if r["presses"]}
        if not pressed:
            out.append(Check("estop", False, "an e-stop press in some robot's events", "no press fired"))
        out += [_robot(n, c) for n, r in pressed.items() for c in estop(x.estop, r["presses"], r["t0"])]
    if x.effects is not None:
        has = {n: {k for k, cls in KINDS.items() if any(isinstance(v.event, cls) for v in r["events"])}
               for n, r in robots.items()}
        for kind in KINDS:
            if getattr(x.effects, kind) is not None and not any(kind in h for h in has.values()):
                out.append(Check(f"effects.{kind}", False, f"a {kind} event", f"no {kind} in any robot's events"))
        for n, r in robots.items():
            mine = x.effects.model_copy(update={k: None for k in KINDS if k not in has[n]})
            out += [_robot(n, c) for c in effects(mine, r["events"], r["t0"])]
    return out


def _robot(name: str, c: Check) -> Check:
    return Check(f"{name}: {c.name}", c.passed, c.expected, c.actual)
