"""Formatting a drive run: wheel odometry against ground truth, per move and overall."""
from __future__ import annotations

import math

from hw.odometry import Pose2D
from mission.jobs.drive import DriveRun
from mission.jobs.route import relative


def _pct(err: float, ref: float) -> str:
    return f"{100 * abs(err) / abs(ref):5.2f} %" if abs(ref) > 1e-6 else "   -   "


def format_results(run: DriveRun) -> str:
    lines = [f"{'move':<20} {'odom fwd/left/yaw':>26} {'truth fwd/left/yaw':>26} {'error':>10}"]
    for r in run.results:
        o, t, e = r.odom, r.truth, r.error
        axis = ("x", "y", "yaw").index(r.move.axis)
        err = f"{math.degrees(abs(e[2])):6.2f} deg" if r.move.axis == "yaw" else _pct(e[axis], t[axis])
        lines.append(f"{r.move.name:<20} {o[0]:7.3f} {o[1]:7.3f} {math.degrees(o[2]):8.2f}d "
                     f"{t[0]:7.3f} {t[1]:7.3f} {math.degrees(t[2]):8.2f}d {err:>10}")
    odom, truth = run.robot.base.odometry.pose, run.sim.truth()
    spawn = run.sim.world.spawn
    moved = relative(Pose2D(spawn.x, spawn.y, spawn.yaw), truth)
    drift = math.hypot(odom.x - moved[0], odom.y - moved[1])
    lines.append(f"final: odom ({odom.x:.3f}, {odom.y:.3f}, {math.degrees(odom.yaw):.1f} deg), "
                 f"truth from spawn ({moved[0]:.3f}, {moved[1]:.3f}, {math.degrees(moved[2]):.1f} deg), "
                 f"drift {drift:.3f} m over {run.robot.base.odometry.distance:.2f} m driven, "
                 f"{run.sim_time:.1f} s sim time, {run.scans} lidar scans")
    for name, t in run.bumps.items():
        lines.append(f"bumped into {name} at {t:.1f} s: wheel odometry cannot tell (does the route fit this world?)")
    return "\n".join(lines)


def results_json(run: DriveRun) -> dict:
    return {
        "moves": [
            {"name": r.move.name, "axis": r.move.axis, "commanded": r.move.amount,
             "odom": list(r.odom), "truth": list(r.truth), "error": list(r.error)}
            for r in run.results
        ],
        "completed": run.driver.done,
        "held": run.held,
        "bumps": [{"geom": name, "t": t} for name, t in run.bumps.items()],
        "sim_time_s": run.sim_time,
        "distance_m": run.robot.base.odometry.distance,
    }
