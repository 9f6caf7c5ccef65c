"""Playing an events file (spec/events.md) into a simulated run, on the runtime clock.

Each event is a one-shot task on the robot's scheduler at ``t0 + at`` (``t0``: the mission's
start), registered before the mission's own tick, so at a shared instant the robot's services
(base, e-stop publish) run first, then the events in file order, then the mission tree: a press
at 40.0 is seen by the tree at 40.0 and by the wheels on the next control tick.

Every action goes through the path the real thing takes: the button through the sim's pin and
the e-stop bridge, the soft stop and ``resume`` / ``pause`` through the operator's commands,
teleop through the twist_mux source it names (published at ``TELEOP_RATE`` for ``duration``; the
mux times it out after), faults through ``sim.faults``, ``clear_map`` through the runtime's map
reset, ``history_down`` through the history store's outage hook, ``runtime_crash`` through the
patrol job's restart (``PatrolRun.crash``). Nothing here touches the mission tree.

An event with ``when_moving: V`` is instead a task at the control rate from the first control
beat at or after ``at`` (the sim patrol starts on a beat): it fires on the first beat at which
the base's wheel odometry, measured by that beat's base tick, says the base drives at V m/s or
faster. It keeps its place in the file order (registered with the others, before the mission's
tick). One whose condition never comes true is never fired: absent from ``fired``.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field
from typing import Callable

from hw.interfaces import Twist
from mission.patrol import events_file as ev
from mission.patrol.holds import MissionHolds
from mission.runtime.navigation import clear_map
from mission.runtime.robot import Robot
from nav.navigator import Navigator
from sim.faults import SimFaults

log = logging.getLogger("lupin.events")

TELEOP_RATE = 20.0
"""A joystick / console publishes its twist at 20 Hz (well inside the mux's 0.3 s joy timeout)."""

_NS = 1_000_000_000


@dataclass
class EventPlayer:
    robot: Robot
    nav: Navigator
    holds: MissionHolds
    faults: SimFaults
    applied: list[dict] = field(default_factory=list)
    """``{"t", "do"}`` of every event applied, t from the mission's start (the report's
    ``events``); a refused ``resume`` also says why."""
    fired: dict[int, float] = field(default_factory=dict)
    """Runtime time each event was applied at, by its index in the events list (a judge's
    record: an event whose ``when_moving`` never came true is absent)."""
    crash: Callable[[float], None] = lambda now: None
    """What ``runtime_crash`` does: the patrol job's (the runtime dies and starts again)."""
    history_down: Callable[[float], None] = lambda until: None
    """What ``history_down`` does: the history's database unreachable until then (runtime time)."""

    def schedule(self, events: list, t0: float) -> None:
        sched = self.robot.scheduler
        for i, event in enumerate(events):
            name, apply = f"event.{i}.{event.do}", lambda now, e=event, i=i: self._apply(i, e, now, t0)
            if event.when_moving is None:
                sched.at(name, t0 + event.at, apply)
            else:
                rate = self.robot.config.hw.base.control_rate
                sched.every(name, rate, self._when_moving(name, event.when_moving, apply),
                            offset=t0 + _first_beat(event.at, rate) - sched.clock.now())

    def _when_moving(self, name: str, speed: float, apply):
        odometry = self.robot.base.odometry

        def check(now: float) -> None:
            if math.hypot(odometry.twist.vx, odometry.twist.vy) >= speed:
                self.robot.scheduler.cancel(name)
                apply(now)

        return check

    def _apply(self, i: int, e, now: float, t0: float) -> None:
        log.info("event at t=%.2f: %s", now, e.model_dump(exclude={"at", "when_moving"}))  # the log's clock
        entry = {"t": round(now - t0, 3), "do": e.do}
        self.applied.append(entry)
        self.fired[i] = now
        f, robot = self.faults, self.robot
        match e:
            case ev.EStop():
                f.estop(e.engaged)
            case ev.SoftEStop():
                robot.estop.set_soft(e.engaged)
            case ev.Resume():
                refused = self.holds.resume()
                if refused:
                    entry["refused"] = refused
            case ev.Pause():
                self.holds.pause()
            case ev.LidarDropout():
                f.lidar_dropout(e.duration)
            case ev.LidarBlind():
                f.lidar_blind(e.duration)
            case ev.ServoStall():
                f.servo_stall(e.joint, e.mode)
            case ev.Battery():
                f.battery(e.voltage)
            case ev.BatteryDrain():
                f.battery_drain(e.load, e.duration)
            case ev.ClearMap():
                clear_map(self.nav, now)
            case ev.Teleop():
                self._teleop(i, e, now)
            case ev.PlaceBox():
                f.place_box(e.x, e.y, e.sx, e.sy, e.yaw)
            case ev.ControllerRace():
                f.controller_race(e.controllers, e.state)
            case ev.CameraDropout():
                f.camera_dropout(e.camera, e.duration)
            case ev.MovePot():
                f.move_pot(e.pot, e.dx, e.dy, e.dyaw)
            case ev.WalkerEvent():
                f.walker(e.walker, e.moving)
            case ev.RuntimeCrash():
                self.crash(now)
            case ev.HistoryDown():
                self.history_down(now + e.duration)

    def _teleop(self, i: int, e: ev.Teleop, now: float) -> None:
        name, twist, mux = f"event.{i}.teleop.publish", Twist(e.vx, e.vy, e.wz), self.robot.mux
        end = now + e.duration
        sched = self.robot.scheduler

        def publish(t: float) -> None:
            if t >= end:  # the stick is let go: the source falls silent, the mux times it out
                sched.cancel(name)
                return
            mux.publish(e.source, twist, t)

        sched.every(name, TELEOP_RATE, publish)


def _first_beat(at: float, rate: float) -> float:
    """The first control beat at or after ``at`` s from the start (a beat every ``1 / rate``),
    in whole nanoseconds as the scheduler keeps them."""
    period = round(_NS / rate)
    return -(-round(at * _NS) // period) * period / _NS
