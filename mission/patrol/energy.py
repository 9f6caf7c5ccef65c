"""The patrol's energy budget (issue 31): how much charge is left, what the robot's work costs,
and whether it can do the next pot and still reach the dock with the reserve.

**Charge.** Coulomb counting on the power monitor's current, from the pack's charge at the
first reading: its open-circuit voltage (the terminal voltage plus I*R) placed linearly between
the pack's empty and full voltages, as the sim's pack model has it and a LiPo's middle range
nearly does. Current out of the pack reads positive, current into it (the dock's charger)
negative, as the INA226 is wired; so charging on the dock is seen, not assumed.

**Costs.** Each sample of the monitor is put to what the robot did since the last one (from
odometry): driving (Ah per metre), turning on the spot (Ah per radian) or standing (A). Each
rate starts from the sim's battery model (its idle current, and its motors at ``PRIOR_LOAD``
at ``PRIOR_SPEED`` of the top speed), worth ``PRIOR_WEIGHT`` of measurement, and follows what
the robot measures from then on. A pot costs the time the robot stands at it (the mean of
the pots done, ``patrol.energy.pot_seconds`` before any) and half a turn. The planner's path
lengths are not the metres driven (they run long where a path skirts inflated cost, between
rows of pots; short where the robot weaves round people), so the ratio of metres driven to a
pot to the planned length there is measured too (``detour``) and the ways are scaled by it.

**Checks.** Before each pot: charge now - margin x (the way there + the pot + the way from it
to the dock) must stay above the reserve, or the robot heads home now. Every
``check_every`` s on the way: charge now - margin x (the way to the dock) likewise, so a pack
falling faster than the model said (a stuck wheel, a short) sends it home at once. The ways
are the planner's path lengths over the map (``nav.path_lengths``), one wavefront from the
dock.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from hw.interfaces import PowerReading
from hw.odometry import Pose2D
from mission.patrol.config import EnergyConfig
from sim.config import BatteryConfig

Lengths = Callable[[tuple[float, float], np.ndarray], np.ndarray]
"""(origin x, y), (N, 2) points -> (N,) the planner's path lengths, m."""

PRIOR_LOAD = 1.0
"""Wheel duties summed (0..4) while driving, before anything is measured (untuned: cruising
takes a fraction of each motor's duty; the measurement replaces it within a few metres)."""
PRIOR_SPEED = 0.6
"""Mean driving speed as a share of MPPI's top speed, before anything is measured (the robot
slows for turns, pots and people)."""
PRIOR_WEIGHT = (20.0, 20.0, 60.0)
"""What the prior rates count as: metres driven, radians turned, seconds stood."""
DETOUR_WEIGHT = 10.0
"""The prior detour, 1 (the planned length is the driven one), counts as this many metres."""
MOVING_M = 0.02
"""More than this between two samples (0.5 s apart) is driving, m; else a turn of more than
``TURNING_RAD`` is turning; else the robot stands."""
TURNING_RAD = 0.05
POT_TURN = math.pi
"""Radians turned at a pot (facing it from the aisle, then back along it)."""
RECHECK_M = 2.0
"""The way back to the dock is measured again (a wavefront over the map, ~10-25 ms on a 60 m
greenhouse) once the robot is this far from where it was last measured, m; in between it is
that length plus the straight distance since, never less than the way is."""


@dataclass
class Rate:
    """Charge per unit of work (Ah per metre, per radian, per second), prior plus measured."""
    ah: float
    units: float

    @property
    def per_unit(self) -> float:
        return self.ah / self.units

    def add(self, ah: float, units: float) -> None:
        self.ah += ah
        self.units += units


class EnergyBudget:
    """The charge, the learned costs and the checks; ``sample`` at the power watch's rate."""

    def __init__(self, config: EnergyConfig, pack: BatteryConfig, top_speed: float,
                 dock: tuple[float, float], lengths: Lengths):
        self.config, self.pack, self.dock, self.lengths = config, pack, dock, lengths
        m, rad, s = PRIOR_WEIGHT
        driving = pack.idle_current + pack.stall_current * PRIOR_LOAD
        self.drive = Rate(driving / (PRIOR_SPEED * top_speed) / 3600.0 * m, m)
        self.turn = Rate(driving / 1.0 / 3600.0 * rad, rad)  # about 1 rad/s on the spot
        self.stand = Rate(pack.idle_current / 3600.0 * s, s)
        self.detour = Rate(DETOUR_WEIGHT, DETOUR_WEIGHT)
        self.driven = 0.0
        """Metres driven (odometry) since the start."""
        self._planned: tuple[float, float] | None = None
        self._back: tuple[float, float, float] | None = None
        """The last measured way back to the dock: (x, y, metres)."""
        self.charge: float | None = None
        """The pack's charge, 0..1; None before the first reading."""
        self.lowest: float | None = None
        self.current = 0.0
        self.projected: float | None = None
        """Charge expected at the dock after the pot being checked (the status line shows it)."""
        self.why_home = ""
        """Why the robot is heading home ('' while it is not)."""
        self._last: tuple[float, Pose2D] | None = None
        self._pot_standing: list[float] = []
        self._standing_since_pot = 0.0

    # --- measuring -------------------------------------------------------------------------
    def _initial_charge(self, reading: PowerReading) -> float:
        p = self.pack
        ocv = reading.voltage + p.internal_resistance * reading.current
        return float(min(1.0, max(0.0, (ocv - p.empty_voltage) / (p.full_voltage - p.empty_voltage))))

    def sample(self, reading: PowerReading | None, pose: Pose2D) -> None:
        """The monitor's latest reading with the robot's odometry pose: the charge, and the cost
        of what the robot did since the last reading (one already taken is skipped)."""
        if reading is None or not (math.isfinite(reading.voltage) and math.isfinite(reading.current)):
            return
        now = reading.stamp
        if self._last is not None and now <= self._last[0]:
            return
        if self.charge is None:
            self.charge = self._initial_charge(reading)
        if self._last is not None:
            t, before = self._last
            dt = now - t
            ah = reading.current * dt / 3600.0
            self.charge = float(min(1.0, max(0.0, self.charge - ah / self.pack.capacity_ah)))
            if reading.current > 0:  # the dock's charger is not the robot's work
                self._learn(ah, dt, before, pose)
        self.current = reading.current
        self._last = (now, pose)
        self.lowest = self.charge if self.lowest is None else min(self.lowest, self.charge)

    def _learn(self, ah: float, dt: float, before: Pose2D, after: Pose2D) -> None:
        moved = math.hypot(after.x - before.x, after.y - before.y)
        turned = abs(math.remainder(after.yaw - before.yaw, 2 * math.pi))
        if moved > MOVING_M:
            self.drive.add(ah, moved)
            self.driven += moved
        elif turned > TURNING_RAD:
            self.turn.add(ah, turned)
        else:
            self.stand.add(ah, dt)
            self._standing_since_pot += dt

    def pot_done(self) -> None:
        """A pot was recorded: the time stood since the last one is what a pot takes."""
        self._pot_standing.append(self._standing_since_pot)
        self._standing_since_pot = 0.0
        if self._planned is not None:
            planned, driven0 = self._planned
            if planned > 0.5:
                self.detour.add(self.driven - driven0, planned)
            self._planned = None

    @property
    def charging(self) -> bool:
        """Current flows into the pack."""
        return self.current < 0

    # --- costs -----------------------------------------------------------------------------
    @property
    def pot_seconds(self) -> float:
        done = self._pot_standing[-20:]
        return float(np.mean(done)) if done else self.config.pot_seconds

    def way(self, metres: float) -> float:
        """Charge (share of the pack) to drive ``metres`` of the planner's path."""
        return self.drive.per_unit * self.detour.per_unit * metres / self.pack.capacity_ah

    def pot(self) -> float:
        """Charge (share of the pack) one pot takes where the robot stands at it."""
        ah = self.stand.per_unit * self.pot_seconds + self.turn.per_unit * POT_TURN
        return ah / self.pack.capacity_ah

    # --- checks ----------------------------------------------------------------------------
    def check_pot(self, here: tuple[float, float], pot: tuple[float, float]) -> str:
        """'' when the pot at approach pose ``pot`` can be done from ``here`` with the way back to
        the dock and the reserve left; else why the robot must head home now."""
        if self.charge is None:
            return ""
        to_pot, back = (float(m) for m in self.lengths(pot, np.array([here, self.dock])))  # one wavefront
        self._planned = (to_pot, self.driven)
        need = self.config.margin * (self.way(to_pot + float(back)) + self.pot())
        self.projected = self.charge - need
        if not math.isfinite(need) or self.projected >= self.config.reserve:
            return ""
        return (f"charge {self.charge:.0%}: the next pot and the way back ({to_pot + back:.0f} m) would "
                f"leave {max(self.projected, 0.0):.0%} at the dock, below the {self.config.reserve:.0%} reserve")

    def way_back(self, here: tuple[float, float]) -> float:
        """Metres of the planner's path from ``here`` to the dock (at most ``RECHECK_M`` stale)."""
        if self._back is not None:
            x, y, metres = self._back
            moved = math.hypot(here[0] - x, here[1] - y)
            if moved <= RECHECK_M:
                return metres + moved
        metres = float(self.lengths(self.dock, np.array([here]))[0])
        self._back = (here[0], here[1], metres)
        return metres

    def check_home(self, here: tuple[float, float]) -> str:
        """'' while the robot can still reach the dock from ``here`` above the reserve; else why
        it must head home now (the pack fell faster than the model said)."""
        if self.charge is None:
            return ""
        back = self.way_back(here)
        at_dock = self.charge - self.config.margin * self.way(back)
        if not math.isfinite(at_dock) or at_dock >= self.config.reserve:
            return ""
        return (f"charge {self.charge:.0%} is falling faster than planned: the way back ({back:.0f} m) would "
                f"leave {max(at_dock, 0.0):.0%} at the dock, below the {self.config.reserve:.0%} reserve")

    def reachable(self, here: tuple[float, float]) -> bool:
        """The dock is within what the pack holds from ``here``, as the model expects (no margin,
        no reserve): else the robot stops clear of the aisles instead (``mission.patrol.parking``)."""
        if self.charge is None:
            return True
        return bool(self.charge - self.way(self.way_back(here)) > 0.0)

    def figures(self) -> dict:
        """The report's ``energy``: the charge, its lowest, and what the work was found to cost."""
        cap = self.pack.capacity_ah
        return {"charge": _share(self.charge), "lowest_charge": _share(self.lowest), "reserve": self.config.reserve,
                "drive_per_m": round(self.drive.per_unit / cap, 6), "turn_per_rad": round(self.turn.per_unit / cap, 6),
                "stand_a": round(self.stand.per_unit * 3600.0, 3), "pot_s": round(self.pot_seconds, 1),
                "detour": round(self.detour.per_unit, 3)}


def _share(value: float | None) -> float | None:
    return None if value is None else round(value, 4)
