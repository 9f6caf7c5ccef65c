"""A scenario's expectations checked against what its run did: one :class:`Check` each, with what
was expected and what happened, so a failure reads like ``estop.zero_duty_within_ticks: expected
<= 1 tick(s) after every press, got ticks to zero duty: 2 at 40.0 s``.

Times in messages are seconds from the mission's start, as in the scenario file.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from mission.scenario.effects import KINDS, EventEffect
from mission.scenario.judge import Press
from mission.jobs.people_log import PeopleLog
from mission.scenario.scenario_file import EffectsExpect, EStopExpect, Expect, PeopleExpect, PotsExpect


@dataclass
class Check:
    name: str
    passed: bool
    expected: str
    actual: str

    def line(self) -> str:
        mark = "pass" if self.passed else "FAIL"
        return f"  {mark}  {self.name}: " + (self.actual if self.passed else f"expected {self.expected}, got {self.actual}")


@dataclass
class Ending:
    """What the judge reads at the end of a run, beside the report."""

    doc: dict
    stopped_at_limit: bool
    home_error: float
    arm_preset: str
    presses: list[Press]
    events: list[EventEffect]
    t0: float
    """The mission's start, runtime time: the zero of the scenario's times."""
    directory: Path
    people: PeopleLog | None = None
    """Clearance and contacts with the walkers, ground truth (worlds with walkers)."""


def expectations(x: Expect, e: Ending) -> list[Check]:
    doc, checks = e.doc, []
    if x.outcome is not None:
        actual = doc["outcome"] + (f" ({doc['reason']})" if doc.get("reason") else "")
        checks.append(Check("outcome", doc["outcome"] == x.outcome, x.outcome, actual))
    ended = "still running at the limit" if e.stopped_at_limit else f"ended at {doc['sim_time_s']:.1f} s"
    checks.append(Check("max_sim_time", not e.stopped_at_limit or x.outcome == "aborted",
                        f"the run to end within {x.max_sim_time:g} s", ended))
    if e.events:
        checks.append(events_fired(e.events, e.t0))
    if x.pots is not None:
        checks += _pots(x.pots, doc)
    kinds = [(a["kind"], a["pot"]) for a in doc["anomalies"]]
    for want in x.anomalies:
        found = any(k == want.kind and (want.pot is None or p == want.pot) for k, p in kinds)
        where = f" at {want.pot}" if want.pot else ""
        checks.append(Check(f"anomalies: {want.kind}{where}", found, f"a {want.kind} anomaly{where}",
                            "found" if found else f"anomalies {_anomalies(kinds)}"))
    for kind in x.no_anomalies:
        at = [p for k, p in kinds if k == kind]
        checks.append(Check(f"no_anomalies: {kind}", not at, f"no {kind} anomaly", f"{kind} at {', '.join(at)}" if at else "none"))
    if x.home is not None:
        checks.append(Check("home", e.home_error <= x.home.within, f"within {x.home.within:g} m of home",
                            f"{e.home_error:.3f} m from home"))
    if x.arm is not None:
        checks.append(Check("arm", e.arm_preset == x.arm, f"the arm at {x.arm}", f"the arm at {e.arm_preset}"))
    if x.estop is not None:
        checks += estop(x.estop, e.presses, e.t0)
    if x.effects is not None:
        checks += effects(x.effects, e.events, e.t0)
    if x.people is not None:
        checks += people(x.people, e.people, e.t0)
    for name in x.report_files:
        present = (e.directory / name).is_file()
        checks.append(Check(f"report_files: {name}", present, f"{name} beside the report", "present" if present else "missing"))
    return checks


def events_fired(events: list[EventEffect], t0: float) -> Check:
    """Every scripted event fired: one that never did (its ``when_moving`` never came true, or
    the run ended before its time) tested nothing."""
    missed = [_named(v) for v in events if v.fired is None]
    if missed:
        return Check("events fired", False, "every event to fire", "not fired: " + "; ".join(missed))
    moving = [f"{v.event.do} at {v.fired - t0:.1f} s ({v.speed:.2f} m/s)" for v in events if v.event.when_moving]
    return Check("events fired", True, "every event to fire",
                 f"all {len(events)}" + (f"; when moving: {', '.join(moving)}" if moving else ""))


def _named(v: EventEffect) -> str:
    e = v.event
    when = f", when_moving {e.when_moving:g} m/s" if e.when_moving else ""
    return f"events[{v.index}] (do {e.do}, at {e.at:g} s{when})"


def _anomalies(kinds: list[tuple[str, str]]) -> str:
    return "[" + ", ".join(f"{k} at {p}" for k, p in kinds) + "]" if kinds else "none"


def _pots(x: PotsExpect, doc: dict) -> list[Check]:
    status = {p["id"]: p["status"] for p in doc["pots"]}
    out = []
    for want in ("inspected", "failed", "skipped"):
        spec = getattr(x, want)
        if spec is None:
            continue
        have = [i for i, s in status.items() if s == want]
        if spec == "all":
            ok, expected = len(have) == len(status), f"all {len(status)} pots {want}"
        elif isinstance(spec, int):
            ok, expected = len(have) == spec, f"{spec} pots {want}"
        else:
            ok, expected = all(status.get(i) == want for i in spec), f"{', '.join(spec)} {want}"
        others = {s: [i for i, v in status.items() if v == s] for s in sorted(set(status.values()))}
        actual = "; ".join(f"{s}: {', '.join(ids)}" for s, ids in others.items())
        out.append(Check(f"pots.{want}", ok, expected, actual))
    return out


def people(x: PeopleExpect, log: PeopleLog, t0: float) -> list[Check]:
    out = []
    if x.min_clearance is not None:
        if math.isinf(log.clearance):
            out.append(Check("people.min_clearance", True, f">= {x.min_clearance:g} m to every walker while moving",
                             "no walker measured while the robot moved"))
        else:
            worst = min(log.min_clearance, key=log.min_clearance.get)
            t, rx, ry = log.close_at[worst]
            out.append(Check("people.min_clearance", log.clearance >= x.min_clearance,
                             f">= {x.min_clearance:g} m to every walker while moving",
                             f"{log.clearance:.3f} m (walker {worst}, at {t - t0:.1f} s, robot at ({rx:.2f}, {ry:.2f}))"))
    if x.contacts is not None:
        onsets = log.moving_contacts
        shown = ", ".join(f"{name} at {t - t0:.1f} s" for t, name in onsets[:5]) or "none"
        out.append(Check("people.contacts", len(onsets) <= x.contacts, f"<= {x.contacts} contact(s) while moving",
                         f"{len(onsets)} ({shown})"))
    if x.encounters is not None:
        met = log.encounters
        shown = ", ".join(f"{e['walker']} at {e['t'] - t0:.1f} s ({e['nearest_m']:.2f} m)" for e in met[:6]) or "none"
        out.append(Check("people.encounters", len(met) >= x.encounters,
                         f">= {x.encounters} time(s) a walker came within 1.0 m", f"{len(met)} ({shown})"))
    return out


def estop(x: EStopExpect, presses: list[Press], t0: float) -> list[Check]:
    out = []
    if not presses:
        return [Check("estop", False, "an e-stop press in the events", "no press fired")]
    if x.zero_duty_within_ticks is not None:
        worst = [p for p in presses if p.ticks_to_zero is None or p.ticks_to_zero > x.zero_duty_within_ticks]
        shown = ", ".join(f"{p.ticks_to_zero} at {p.at - t0:.1f} s" for p in presses)
        out.append(Check("estop.zero_duty_within_ticks", not worst,
                         f"<= {x.zero_duty_within_ticks} tick(s) after every press", f"ticks to zero duty: {shown}"))
    if x.still_until_resume is not None:
        still = x.still_until_resume
        released = [p for p in presses if p.released is not None]
        moved = [p for p in released if not p.still_after_release]
        shown = ", ".join(f"{p.moved_after_release * 1000:.1f} mm after the release at {p.released - t0:.1f} s" for p in released)
        ok = (not moved) == still and (bool(released) or not still)
        out.append(Check("estop.still_until_resume", ok,
                         "no wheel duty or motion between each release and its resume" if still else "motion after a release",
                         shown or "never released"))
    if x.max_distance_after_press is not None:
        far = [p for p in presses if p.distance_after > x.max_distance_after_press]
        shown = ", ".join(f"{p.distance_after * 1000:.0f} mm after the press at {p.at - t0:.1f} s" for p in presses)
        out.append(Check("estop.max_distance_after_press", not far,
                         f"<= {x.max_distance_after_press * 1000:g} mm of true motion from each press to its release",
                         shown))
    if x.min_speed_at_press is not None:
        slow = [p for p in presses if p.speed < x.min_speed_at_press]
        shown = ", ".join(f"{p.speed:.2f} m/s at {p.at - t0:.1f} s" for p in presses)
        out.append(Check("estop.min_speed_at_press", not slow,
                         f"every press to find the base driving at >= {x.min_speed_at_press:g} m/s (true speed)",
                         f"speed at press: {shown}" + (" (a press at rest tests nothing)" if slow else "")))
    return out


def effects(x: EffectsExpect, events: list[EventEffect], t0: float) -> list[Check]:
    out = []
    for kind, cls in KINDS.items():
        want = getattr(x, kind)
        if want is None:
            continue
        mine = [v for v in events if isinstance(v.event, cls)]
        if not mine:
            out.append(Check(f"effects.{kind}", False, f"a {kind} event", f"no {kind} in the events"))
        for v in mine:
            name = f"effects.{kind} (events[{v.index}])"
            if v.fired is None:
                out.append(Check(name, False, f"the {kind} to fire and show its effect", "it never fired"))
                continue
            out.append(Check(name, *_JUDGES[kind](want, v.figures, v.fired - t0)))
    return out


def _pause(x, f: dict, at: float) -> tuple[bool, str, str]:
    until = at + f["resumed_after_s"]
    expected = (f"no duty past the motors' dead zone from {x.still_within:g} s after the pause at {at:.1f} s until its "
                f"resume ({until:.1f} s), the base moving < {x.max_motion * 1000:g} mm")
    moved = f"moved {f['moved_m'] * 1000:.1f} mm from {at + x.still_within:.1f} s to {until:.1f} s"
    if f["held_after_s"] is None:
        driven = at + f["last_driven_after_s"]
        return False, expected, f"the wheels were driven until {driven:.1f} s (the pause held nothing), {moved}"
    ok = f["held_after_s"] <= x.still_within and f["moved_m"] < x.max_motion
    held = f"held from {f['held_after_s']:.1f} s after the pause (|duty| <= {f['max_duty_while_held']:.3f})"
    return ok, expected, f"{held}, {moved}"


def _dropout(x, f: dict, at: float) -> tuple[bool, str, str]:
    expected = (f"zero twist to the base from <= {x.zero_twist_within:g} s after the lidar went dark at {at:.1f} s "
                f"until it came back ({at + f['blind_s']:.1f} s), autonomy driving <= {x.drives_again_within:g} s after")
    zero = ("the base was driven until the scans came back" if f["zero_twist_after_s"] is None else
            f"zero twist from {f['zero_twist_after_s']:.1f} s after (moved {f['moved_while_zero_m'] * 1000:.0f} mm while held)")
    again = ("autonomy never drove again" if f["drives_again_after_s"] is None else
             f"driving again {f['drives_again_after_s']:.1f} s after the scans returned")
    ok = (f["zero_twist_after_s"] is not None and f["zero_twist_after_s"] <= x.zero_twist_within
          and f["drives_again_after_s"] is not None and f["drives_again_after_s"] <= x.drives_again_within)
    return ok, expected, f"{zero}; {again}"


def _blind(x, f: dict, at: float) -> tuple[bool, str, str]:
    expected = (f"zero linear twist to the base from <= {x.zero_linear_within:g} s after the lidar went blind at "
                f"{at:.1f} s until it saw again ({at + f['blind_s']:.1f} s), autonomy driving <= "
                f"{x.drives_again_within:g} s after")
    zero = ("the base was driven until the lidar saw again" if f["zero_linear_after_s"] is None else
            f"zero linear twist from {f['zero_linear_after_s']:.2f} s after (moved {f['moved_while_zero_m'] * 1000:.0f} mm "
            "while held)")
    again = ("autonomy never drove again" if f["drives_again_after_s"] is None else
             f"driving again {f['drives_again_after_s']:.1f} s after the lidar saw again")
    ok = (f["zero_linear_after_s"] is not None and f["zero_linear_after_s"] <= x.zero_linear_within
          and f["drives_again_after_s"] is not None and f["drives_again_after_s"] <= x.drives_again_within)
    return ok, expected, f"{zero}; {again}"


def _clear_map(x, f: dict, at: float) -> tuple[bool, str, str]:
    expected = (f"SLAM's map erased and its worker respawned at the reset ({at:.1f} s), the map back to "
                f">= {x.map_back:.0%} of its {f['known_before']} known cells within {x.within:g} s")
    back = (f"back to {x.map_back:.0%} after {f['back_after_s']:.1f} s" if f["back_after_s"] is not None else
            f"{f['known_after']} cells known {x.within:g} s after")
    ok = bool(f["known_before"]) and f["erased"] and f["respawned"] and f["back_after_s"] is not None
    return ok, expected, (f"{'erased' if f['erased'] else 'never erased'}, "
                          f"{'respawned' if f['respawned'] else 'no new worker'}, {back}")


def _teleop(x, f: dict, at: float) -> tuple[bool, str, str]:
    asked = ", ".join(f"{v:g}" for v in f["asked"])
    true = ", ".join(f"{v:.2f}" for v in f["true_twist"])
    expected = (f"the base following the stick pressed at {at:.1f} s on every control tick of its hold, and its true "
                f"twist (vx, vy, wz) within {x.tolerance:g} of ({asked}) from {x.settle:g} s in")
    follows = all(abs(a - b) <= x.tolerance for a, b in zip(f["true_twist"], f["asked"]))
    owned = f["ticks_owned"] == f["ticks"] > 0
    lost = "" if owned or f["lost_after_s"] is None else f", first not at {at + f['lost_after_s']:.1f} s ({f['lost_to']})"
    return owned and follows, expected, f"{f['ticks_owned']} of {f['ticks']} ticks followed the stick{lost}; true twist ({true})"


def _restart(x, f: dict, at: float) -> tuple[bool, str, str]:
    expected = (f"the runtime restarted after the crash at {at:.1f} s with its soft stop "
                f"{'engaged on every control tick' if x.engaged else 'released'}, the base moving "
                f"< {x.max_motion * 1000:g} mm from {x.still_within:g} s after")
    held = f["ticks_estop"] == f["ticks"] > 0 if x.engaged else f["ticks_estop"] == 0
    return (held and f["moved_m"] < x.max_motion, expected,
            f"e-stop on {f['ticks_estop']} of {f['ticks']} ticks after the restart, moved {f['moved_m'] * 1000:.1f} mm")


_JUDGES = {"pause": _pause, "lidar_dropout": _dropout, "lidar_blind": _blind, "clear_map": _clear_map, "teleop": _teleop,
           "runtime_crash": _restart}
