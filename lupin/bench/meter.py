"""What a simulated patrol costs the robot: the runtime's CPU apart from the simulator's, SLAM's
work per scan over the patrol, and memory.

- **Runtime CPU** is the process's CPU time less the simulator's own (physics, renders, lidar
  rays: ``sim.engine.Engine.cpu_s``), plus the SLAM worker's CPU (it reports its own in every
  reply), per second of robot time: the share of a core the stack needs on the robot, whatever
  the simulator costs here. ``runtime_cpu_per_robot_s`` 0.3 means 30 % of one core.
- **SLAM per scan** is the worker's busy time for every scan it mapped, in order, so the first
  and the last tenth of a patrol can be compared (and their scans taken on the move alone: a
  scan costs more while the robot drives than while it stands at a pot, and the tenths need not
  hold the same share of each); solves are the scans that optimised the pose
  graph (each timed whole: the solve and the first share of the re-render of what it moved;
  an accepted loop closure that moves the estimate less than a centimetre is kept as an edge
  without a solve, so ``loop_closures`` can exceed ``solves``); ``kept_mb`` is what it holds to
  re-render. ``slam_longest_gap_s`` is the longest time between two consecutive scan updates
  the robot would see: its free-running worker takes a new scan at the first 10 Hz tick after
  it answers, so a scan that keeps it busy ``b`` seconds holds the next update back to
  ``ceil(b / period)`` periods (one period at the least; the sim's lock-step exchange waits
  instead, so the sim's clock cannot show the gap itself). The first scan (the worker starting
  up) is not a gap between two updates, and the map handed over whole at the patrol's end (a
  loop closure's re-render finished in that exchange, ``nav.slam.rerender``) is given apart as
  ``slam_whole_map_ms``. The busy time is wall time: on a machine shared with other work it
  counts the time the worker waited for a core. ``slam_longest_gap_cpu_s`` is the same gap from
  the worker's CPU seconds per scan (the difference of its CPU clock between two replies), what
  the robot's worker, with the second core to itself, would take.
- **Peak memory** is the high-water resident set of the runtime process during the patrol (the
  mark is reset at the start where Linux allows it) and of the SLAM worker.
"""
from __future__ import annotations

import math
import time
from pathlib import Path

import numpy as np

from mission.jobs.patrol import PatrolRun
from nav.slam.supervisor import SlamSupervisor


def _hwm_mb(pid: int | str = "self") -> float:
    """VmHWM (peak resident set) of a process, MB; 0 when unreadable."""
    try:
        for line in Path(f"/proc/{pid}/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return 0.0


def _reset_hwm() -> None:
    try:
        Path("/proc/self/clear_refs").write_text("5")
    except OSError:
        pass


class PatrolMeter:
    def __init__(self, run: PatrolRun):
        self.run = run
        self.engine = run.sim.sim.engine
        self.t0 = run.robot.scheduler.clock.now()
        _reset_hwm()
        self.cpu0, self.sim_cpu0 = time.process_time(), self.engine.cpu_s
        self.busy: list[float] = []
        self.settle: list[float] = []
        self.scan_cpu: list[float] = []
        """Per scan: the worker's CPU seconds on it (nan for a worker's first)."""
        self.moving: list[bool] = []
        """Per scan: had the robot moved since the scan before (1 cm or 0.01 rad)?"""
        self._last_pose = None
        self.solves: list[float] = []
        self.kept_bytes = 0
        self.keyframes = 0
        self.loop_closures = 0
        self._worker_cpu: dict[int, float] = {}
        self.worker_hwm_mb = 0.0
        self.slam: SlamSupervisor = run.nav.localisation  # metered patrols map as they go
        self.slam.listeners.append(self._reply)

    def _reply(self, reply) -> None:
        self.busy.append(reply.busy_s)
        self.settle.append(reply.settle_s)
        was, self._last_pose = self._last_pose, reply.pose
        self.moving.append(was is not None and (math.hypot(reply.pose.x - was.x, reply.pose.y - was.y) >= 0.01
                                                or abs(math.remainder(reply.pose.yaw - was.yaw, 2 * math.pi)) >= 0.01))
        if reply.solve_s:
            self.solves.append(reply.solve_s)
        self.kept_bytes, self.keyframes, self.loop_closures = reply.kept_bytes, reply.keyframes, reply.loop_closures
        pid = self.slam.pid
        self.scan_cpu.append(reply.cpu_s - self._worker_cpu[pid] if pid in self._worker_cpu else math.nan)
        self._worker_cpu[pid] = reply.cpu_s
        if len(self.busy) % 100 == 0:
            self.worker_hwm_mb = max(self.worker_hwm_mb, _hwm_mb(pid))

    def figures(self) -> dict:
        """Read before the run is closed (the worker must still be there to be read)."""
        robot_s = self.run.robot.scheduler.clock.now() - self.t0
        main = (time.process_time() - self.cpu0) - (self.engine.cpu_s - self.sim_cpu0)
        worker = sum(self._worker_cpu.values())
        if self.slam.pid is not None:
            self.worker_hwm_mb = max(self.worker_hwm_mb, _hwm_mb(self.slam.pid))
        busy = np.asarray(self.busy) * 1000.0
        period = self.slam.cfg.transform_publish_period
        settle = np.asarray(self.settle) * 1000.0
        between = (busy - settle)[1:] / 1000.0
        cpu = np.asarray(self.scan_cpu)[1:][(settle[1:] == 0) & np.isfinite(self.scan_cpu[1:])]
        tenth = max(1, len(busy) // 10)
        first, last = busy[:tenth], busy[-tenth:]
        moving = np.asarray(self.moving, dtype=bool)
        return {
            "robot_s": round(robot_s, 1),
            "runtime_cpu_s": round(main + worker, 2), "slam_worker_cpu_s": round(worker, 2),
            "sim_cpu_s": round(self.engine.cpu_s - self.sim_cpu0, 2),
            "runtime_cpu_per_robot_s": round((main + worker) / robot_s, 4) if robot_s else None,
            "peak_rss_mb": round(_hwm_mb(), 1), "slam_worker_peak_rss_mb": round(self.worker_hwm_mb, 1),
            "slam_scans": len(busy), "slam_keyframes": self.keyframes, "slam_kept_mb": round(self.kept_bytes / 1e6, 2),
            "slam_ms": _stats(busy), "slam_first_tenth_ms": _stats(first), "slam_last_tenth_ms": _stats(last),
            "slam_longest_gap_s": round(period * max(1, math.ceil(between.max(initial=0.0) / period - 1e-9)), 3),
            "slam_longest_busy_ms": round(float(between.max(initial=0.0)) * 1000.0, 1),
            "slam_whole_map_ms": round(float(settle.max(initial=0.0)), 1),
            "slam_longest_gap_cpu_s": round(period * max(1, math.ceil(cpu.max(initial=0.0) / period - 1e-9)), 3),
            "slam_longest_scan_cpu_ms": round(float(cpu.max(initial=0.0)) * 1000.0, 1),
            "slam_cpu_ms": _stats(cpu * 1000.0),
            "slam_last_over_first_median": round(float(np.median(last) / np.median(first)), 3) if len(busy) else None,
            "slam_moving_share": {"first_tenth": round(float(moving[:tenth].mean()), 3) if len(busy) else None,
                                  "last_tenth": round(float(moving[-tenth:].mean()), 3) if len(busy) else None},
            "slam_first_tenth_moving_ms": _stats(first[moving[:tenth]]),
            "slam_last_tenth_moving_ms": _stats(last[moving[-tenth:]]),
            "slam_loop_closures": self.loop_closures, "slam_solves": len(self.solves),
            "slam_solve_ms": _stats(np.asarray(self.solves) * 1000.0),
        }


def _stats(ms: np.ndarray) -> dict | None:
    if not len(ms):
        return None
    return {"median": round(float(np.median(ms)), 3), "p95": round(float(np.percentile(ms, 95)), 3),
            "max": round(float(ms.max()), 3)}
