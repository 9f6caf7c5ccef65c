"""The scenario judge's event effects: did each event do what it is for (spec/scenario.md)?

An event that did nothing must not pass, so each kind is judged by what it must change, measured
on the motion log (``mission.scenario.motion_log``: the duties at the motors, the true pose,
the twist the base controller was handed, SLAM's map), from the instant the event really fired:

* ``pause``: how long after the pause the wheels were last driven (a duty past the motors' dead
  zone) before the resume (or the end of the run), and how far the true base moved from a
  settling time after the pause until then. (Not "every duty zero": when the twist drops to
  zero the wheel PID keeps a residue of its integral, up to ~0.06 duty, on the motors, inside
  their 10 % dead zone, so it turns nothing; an e-stop resets the PID and writes exact zeros.)
* ``lidar_dropout``: while the lidar is blind the twist handed to the base is zero from some
  instant on (how long after the scans stopped), and autonomy drives again after they return;
* ``lidar_blind``: while every return is invalid the *linear* twist handed to the base is zero
  from some instant on (the collision monitor: blind is not clear; a turn may pass), and
  autonomy drives again after the lidar sees;
* ``clear_map``: SLAM's map is erased, a fresh worker is spawned, and the map's known cells
  come back to a fraction of what it knew before (and when);
* ``runtime_crash``: on every control tick after the restart the base is held by the e-stop
  (the latch came back engaged) and the true base stands still;
* ``teleop``: through the hold, every control tick the base follows the event's source and
  twist, and the true base twist (mean over the hold after ``settle``) is the stick's.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from mission.patrol import events_file as ev
from mission.scenario.judge import max_displacement, path_length
from mission.scenario.motion_log import MotionLog
from mission.scenario.scenario_file import (ClearMapEffect, DropoutEffect, EffectsExpect, PauseEffect, RestartEffect,
                                           TeleopEffect)

KINDS = {"pause": ev.Pause, "lidar_dropout": ev.LidarDropout, "lidar_blind": ev.LidarBlind, "clear_map": ev.ClearMap, "teleop": ev.Teleop,
         "runtime_crash": ev.RuntimeCrash}
"""The event kinds whose effect is judged, by their ``effects:`` key."""


@dataclass
class EventEffect:
    index: int
    event: object
    fired: float | None
    """Runtime time it fired (None: its ``when_moving`` never came true)."""
    speed: float = 0.0
    """True base speed over the control tick up to the event, m/s."""
    figures: dict = field(default_factory=dict)
    """What it changed (per kind, see the module doc); empty for a kind not judged here."""

    def as_json(self, t0: float) -> dict:
        e = self.event
        return {"index": self.index, "do": e.do, "at": e.at, **({"when_moving": e.when_moving} if e.when_moving else {}),
                "fired": None if self.fired is None else round(self.fired - t0, 3), "speed_mps": round(self.speed, 3),
                "effect": self.figures}


def event_effects(log: MotionLog, events: list, fired: dict[int, float], end: float,
                  expect: EffectsExpect | None) -> list[EventEffect]:
    """Every event as it played, with its effect measured (with the expectation's parameters
    where the scenario gives them, else their defaults)."""
    expect = expect or EffectsExpect()
    out = []
    for i, e in enumerate(events):
        t = fired.get(i)
        effect = EventEffect(i, e, t)
        out.append(effect)
        if t is None:
            continue
        effect.speed = log.speed_at(t)
        match e:
            case ev.Pause():
                resumes = [fired[j] for j, r in enumerate(events) if isinstance(r, ev.Resume) and fired.get(j, -1) > t]
                effect.figures = pause(log, t, min(resumes, default=end), expect.pause or PauseEffect())
            case ev.LidarDropout():
                effect.figures = lidar_dropout(log, t, e.duration, end)
            case ev.LidarBlind():
                effect.figures = lidar_blind(log, t, e.duration, end)
            case ev.ClearMap():
                effect.figures = clear_map(log, t, expect.clear_map or ClearMapEffect(), end)
            case ev.Teleop():
                effect.figures = teleop(log, t, e, expect.teleop or TeleopEffect())
            case ev.RuntimeCrash():
                effect.figures = runtime_crash(log, t, end, expect.runtime_crash or RestartEffect())
    return out


def runtime_crash(log: MotionLog, at: float, end: float, x: RestartEffect) -> dict:
    """What the runtime came back as: the control ticks after the crash on which the e-stop held
    the base, and how far the true base moved once it had ``still_within`` to stop."""
    after = log.after(at, end)
    ticks = range(after.start + 1, after.stop)  # the crash's own tick ran before the restart
    still = log.since(at + x.still_within, end)
    return {"ticks": len(ticks), "ticks_estop": sum(log.source[k] == "estop" for k in ticks),
            "moved_m": round(max_displacement(log.xy[still]), 4)}


def pause(log: MotionLog, at: float, until: float, x: PauseEffect) -> dict:
    """``until``: the resume (or the run's end). Times in the figures are seconds after the pause;
    the motion is the true base's from ``x.still_within`` after the pause until ``until``."""
    s = log.after(at, until)
    driven = np.flatnonzero(log.driven(s))
    start = s.start + (int(driven[-1]) + 1 if len(driven) else 0)
    held = start < s.stop
    duty = np.abs(np.asarray(log.duties[start:s.stop], dtype=float).reshape(-1, 4))
    still = log.since(at + x.still_within, until)
    return {"resumed_after_s": round(until - at, 3), "held_after_s": round(log.t[start] - at, 3) if held else None,
            "max_duty_while_held": round(float(duty.max()), 3) if held else None,
            "last_driven_after_s": round(log.t[s.start + int(driven[-1])] - at, 3) if len(driven) else None,
            "moved_m": round(max_displacement(log.xy[still]), 4)}


def lidar_dropout(log: MotionLog, at: float, duration: float, end: float) -> dict:
    back = at + duration
    s = log.after(at, back)
    command = np.asarray(log.command, dtype=float).reshape(-1, 3)
    driven = np.flatnonzero(np.any(command[s] != 0.0, axis=1))
    start = s.start + (int(driven[-1]) + 1 if len(driven) else 0)
    held = start < s.stop
    later = log.after(back, end)
    again = [k for k in range(later.start, later.stop) if log.source[k] == "auto" and np.any(command[k] != 0.0)]
    return {"blind_s": duration, "zero_twist_after_s": round(log.t[start] - at, 3) if held else None,
            "moved_while_zero_m": round(path_length(log.xy[start:s.stop]), 4) if held else None,
            "drives_again_after_s": round(log.t[again[0]] - back, 3) if again else None}


def lidar_blind(log: MotionLog, at: float, duration: float, end: float) -> dict:
    back = at + duration
    s = log.after(at, back - 1e-6)  # the tick at ``back`` takes the first scan that sees again
    command = np.asarray(log.command, dtype=float).reshape(-1, 3)
    driven = np.flatnonzero(np.any(command[s, :2] != 0.0, axis=1))
    start = s.start + (int(driven[-1]) + 1 if len(driven) else 0)
    held = start < s.stop
    later = log.after(back, end)
    again = [k for k in range(later.start, later.stop) if log.source[k] == "auto" and np.any(command[k, :2] != 0.0)]
    return {"blind_s": duration, "zero_linear_after_s": round(log.t[start] - at, 3) if held else None,
            "moved_while_zero_m": round(path_length(log.xy[start:s.stop]), 4) if held else None,
            "drives_again_after_s": round(log.t[again[0]] - back, 3) if again else None}


def clear_map(log: MotionLog, at: float, x: ClearMapEffect, end: float) -> dict:
    i = log.since(at, at).start
    before, workers = log.known[i], log.workers[i]
    s = log.after(at, min(at + x.within, end))
    known = np.asarray(log.known[s], dtype=int)
    back = np.flatnonzero(known >= x.map_back * before) if before else np.array([], dtype=int)
    return {"known_before": before, "erased": bool(len(known) and known.min() == 0),
            "respawned": bool(len(known) and max(log.workers[s]) > workers),
            "known_after": int(known[-1]) if len(known) else 0, "fraction": x.map_back,
            "back_after_s": round(log.t[s.start + int(back[0])] - at, 3) if len(back) else None}


def teleop(log: MotionLog, at: float, e: ev.Teleop, x: TeleopEffect) -> dict:
    held = log.after(at, at + e.duration)
    stick = np.array([e.vx, e.vy, e.wz])
    command = np.asarray(log.command, dtype=float).reshape(-1, 3)[held]
    source = np.array(log.source[held], dtype=object)
    owned = (source == e.source) & np.all(np.abs(command - stick) < 1e-9, axis=1)
    lost = held.start + int(np.flatnonzero(~owned)[0]) if not owned.all() else None
    return {"ticks": int(len(owned)), "ticks_owned": int(np.sum(owned)),
            "lost_after_s": None if lost is None else round(log.t[lost] - at, 3),
            "lost_to": None if lost is None else log.source[lost],
            "true_twist": [round(v, 3) for v in body_twist(log, at + x.settle, at + e.duration)], "asked": stick.tolist()}


def body_twist(log: MotionLog, start: float, end: float) -> tuple[float, float, float]:
    """Mean true body twist (vx, vy, wz) over ``start``..``end``: each tick's true displacement
    in the body frame at its mid-heading, over the stretch's time."""
    s = log.since(start, end)
    pose = np.asarray(log.pose, dtype=float).reshape(-1, 3)[s]
    if len(pose) < 2:
        return 0.0, 0.0, 0.0
    yaw = np.unwrap(pose[:, 2])
    d, mid = np.diff(pose[:, :2], axis=0), (yaw[1:] + yaw[:-1]) / 2
    c, sn = np.cos(mid), np.sin(mid)
    span = log.t[s.stop - 1] - log.t[s.start]
    vx, vy = np.sum(c * d[:, 0] + sn * d[:, 1]) / span, np.sum(-sn * d[:, 0] + c * d[:, 1]) / span
    return float(vx), float(vy), float((yaw[-1] - yaw[0]) / span)
