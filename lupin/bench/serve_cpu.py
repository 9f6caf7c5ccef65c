"""``runtime.cpu_serve``: the runtime's CPU on the robot's working day (issue 29 item 8).

``runtime.cpu`` meters a bare patrol as fast as the machine allows; the robot's real load is
``lupin serve`` with a console attached: telemetry on the link, camera frames captured and
JPEG-encoded on request, Zenoh. So this benchmark builds the service exactly as ``lupin serve``
does on the sim (``start_sim_service``, a ``LinkServer`` on a free loopback endpoint,
``run_service`` on a thread of its own), **paced in real time** as the service runs on the
robot: the console's load is per wall second (telemetry at the link's rates, snapshots at the
operator's), so ``--fast`` would thin it out per robot-second and flatter the figure. The
console is the real console app, headless, in a process of its own (``lupin.bench.operator``):
it starts the default patrol with its ``m`` key and presses ``f`` at the front camera's
producer cap throughout. The benchmark waits for the patrol to end (``WALL_LIMIT_S`` at most),
then stops the console and the service.

The service runs in this process so the runtime's CPU is metered as ``runtime.cpu`` meters it
(``lupin.bench.meter``): the process's CPU time less the simulator's own (physics, renders,
lidar rays: ``sim.engine.Engine.cpu_s``), plus the SLAM worker's (read from ``/proc``), per
second of robot time, sampled on the runtime's own thread at ``SAMPLE_HZ`` from the patrol's
start to its end. The harness thread only waits. The whole patrol's figure is the goal check
(<= ``GOAL`` core); the ``WINDOW_S`` windows give its median and p95 (``median_ms`` and
``p95_ms`` are CPU ms per robot-second in a window: 120 is 0.12 core). The patrol is judged on
ground truth (the world's tags, flowers and pests against the report). Beside it, the same
patrol bare (``runtime.cpu``'s default patrol, shared within one ``lupin bench`` process: no
link, as fast as the machine allows), so the line says what serving with a console adds.
"""
from __future__ import annotations

import json
import signal
import subprocess
import sys
import tempfile
import threading
import time
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from lupin.bench import Sample, benchmark
from lupin.bench.patrol import cached, correct_pots, metered_patrol
from mission.jobs.serve import Service, run_service
from mission.jobs.sim_serve import start_sim_service
from mission.link.server import LinkServer, free_endpoint
from mission.runtime.config import LupinConfig, with_overrides
from nav.slam.liveness import cpu_seconds
from sim.world import load_default_world

GOAL = 0.12
"""Cores per robot-second the runtime may take on this machine (issue 29 item 8)."""
SAMPLE_HZ = 1.0
"""Meter readings per robot-second: one ``/proc`` read and two clock reads each, nothing the
runtime notices."""
WINDOW_S = 10.0
"""Robot seconds per window of the median and p95: long enough to hold a pot's approach and
inspection, short enough for a 125 s patrol to give a dozen."""
WALL_LIMIT_S = 900.0
"""Wall seconds the default patrol (~125 s of robot time, a couple of minutes in real time) may
take on a busy machine before the service is stopped and the patrol reported aborted."""
TOKEN = "bench"


def cpu_windows(t: np.ndarray, cpu: np.ndarray, window_s: float) -> np.ndarray:
    """CPU seconds per robot-second in consecutive windows of ``window_s`` robot seconds, from
    cumulative CPU readings ``cpu`` at robot times ``t`` (ascending). Each window runs from the
    first reading at or after its start to the first at or after the next window's start; a
    trailing part window is left out (it would be a noisy short one)."""
    t, cpu = np.asarray(t, dtype=float), np.asarray(cpu, dtype=float)
    if t.size < 2:
        return np.empty(0)
    edges = t[0] + window_s * np.arange(int((t[-1] - t[0]) // window_s + 1e-9) + 1)
    idx = np.searchsorted(t, edges - 1e-9)
    return np.diff(cpu[idx]) / np.diff(t[idx])


@dataclass(frozen=True)
class Reading:
    robot_s: float
    wall_s: float
    main_cpu_s: float
    """The service process's CPU less the simulator's, since the process began."""
    sim_cpu_s: float
    worker_cpu_s: float
    """The SLAM workers' CPU since the patrol began."""
    link_bytes: int


class ServeMeter:
    """Readings of a service's cost from its patrol's start to its end, on the runtime's thread
    (a scheduled task and the service's ``on_run``: registered before the service runs)."""

    def __init__(self, service: Service, link_bytes: Callable[[], int]):
        self.service, self.link_bytes = service, link_bytes
        self.engine = service.robot.hal.wheels.engine  # the sim's drive holds the engine
        self.readings: list[Reading] = []
        self.report: Path | None = None
        self.done = threading.Event()
        self._worker0: dict[int, float] = {}
        self._worker: dict[int, float] = {}
        self._running = False
        service.on_run.append(self._on_run)
        service.robot.scheduler.every("bench.cpu_meter", SAMPLE_HZ, self._tick)

    def _on_run(self, run) -> None:
        if run is not None:
            self._running, self.report = True, run.report.path
            self._read()
        elif self._running:
            self._read()
            self._running = False
            self.done.set()

    def _tick(self, now: float) -> None:
        if self._running:
            self._read()

    def _worker_cpu(self) -> float:
        pid = getattr(self.service.nav.localisation, "pid", None)
        cpu = cpu_seconds(pid) if pid is not None else None
        if cpu is not None:  # a worker started during the patrol counts from zero
            self._worker0.setdefault(pid, cpu if not self.readings else 0.0)
            self._worker[pid] = cpu
        return sum(self._worker[p] - self._worker0[p] for p in self._worker)

    def _read(self) -> None:
        cpu, sim = time.process_time(), self.engine.cpu_s
        self.readings.append(Reading(self.service.now, time.perf_counter(), cpu - sim, sim,
                                     self._worker_cpu(), self.link_bytes()))

    def figures(self) -> tuple[np.ndarray, dict]:
        """(per-window cores, the patrol's figures); call once the service has stopped."""
        r = self.readings
        if len(r) < 2:
            return np.empty(0), {"readings": len(r)}
        first, last = r[0], r[-1]
        robot_s = last.robot_s - first.robot_s
        worker = last.worker_cpu_s
        runtime = last.main_cpu_s - first.main_cpu_s + worker
        cumulative = np.array([x.main_cpu_s - first.main_cpu_s + x.worker_cpu_s for x in r])
        windows = cpu_windows(np.array([x.robot_s for x in r]), cumulative, WINDOW_S)
        per = runtime / robot_s
        return windows, {
            "robot_s": round(robot_s, 1), "wall_s": round(last.wall_s - first.wall_s, 1),
            "rtf": round(robot_s / (last.wall_s - first.wall_s), 3),
            "runtime_cpu_per_robot_s": round(per, 4), "goal_per_robot_s": GOAL, "meets_goal": bool(per <= GOAL),
            "window_s": WINDOW_S, "windows": int(windows.size),
            "window_cores": {"median": round(float(np.median(windows)), 4),
                             "p95": round(float(np.percentile(windows, 95)), 4),
                             "max": round(float(windows.max()), 4)} if windows.size else None,
            "runtime_cpu_s": round(runtime, 2), "slam_worker_cpu_s": round(worker, 2),
            "slam_worker_share": round(worker / runtime, 3) if runtime > 0 else None,
            "sim_cpu_per_robot_s": round((last.sim_cpu_s - first.sim_cpu_s) / robot_s, 4),
            "link_bytes_per_robot_s": round((last.link_bytes - first.link_bytes) / robot_s),
        }


def _console_figures(out: Path, wall_s: float) -> dict:
    """What the operator process said (its last stdout line), or why it said nothing."""
    lines = out.read_text().strip().splitlines()
    try:
        said = json.loads(lines[-1])
    except (IndexError, ValueError):
        return {"error": f"the console printed no tally (last line: {lines[-1][:200] if lines else 'none'})"}
    sizes, cpu = said.pop("jpeg_bytes"), said.pop("cpu_s")
    return {**said, "failed": said["asked"] - said["answered"],
            "jpeg_kb_median": round(float(np.median(sizes)) / 1000.0, 1) if sizes else None,
            "cpu_per_wall_s": round(cpu / wall_s, 3)}


def _wait_for_patrol(meter: ServeMeter, service: threading.Thread, console: subprocess.Popen) -> bool:
    """Whether the patrol ended within ``WALL_LIMIT_S``; gives up early when the service's
    thread died or the console exited before starting any patrol (nothing would end it)."""
    end = time.perf_counter() + WALL_LIMIT_S
    while time.perf_counter() < end:
        if meter.done.wait(1.0):
            return True
        if not service.is_alive() or (meter.report is None and console.poll() is not None):
            return False
    return False


@benchmark("runtime.cpu_serve")
def runtime_cpu_serve(config: LupinConfig) -> Sample:
    """The runtime's CPU per robot-second on `lupin serve` (sim, real time) with the console
    attached over Zenoh on loopback, asking front-camera snapshots, through one default patrol."""
    live = with_overrides(config, {"sim": {"realtime": True}})
    world = load_default_world()
    hz = live.perception.rates.front
    with tempfile.TemporaryDirectory() as tmp:
        service = start_sim_service(world, live, Path(tmp) / "runs", time.perf_counter)
        endpoint = free_endpoint()
        server = LinkServer(service, live.link, TOKEN, endpoint)
        meter = ServeMeter(service, lambda: sum(server.outbox.bytes.values()))
        stop = threading.Event()
        thread = threading.Thread(target=run_service, args=(service, stop, server.close), daemon=True)
        out, err = Path(tmp) / "console.out", Path(tmp) / "console.err"
        thread.start()
        t0 = time.perf_counter()
        with out.open("w") as so, err.open("w") as se:  # files, never a pipe nobody drains
            console = subprocess.Popen([sys.executable, "-m", "lupin.bench.operator", endpoint, live.link.robot,
                                        TOKEN, str(hz)], stdout=so, stderr=se)
        try:
            finished = _wait_for_patrol(meter, thread, console)
        finally:
            console.send_signal(signal.SIGTERM)
            try:
                console.wait(30)
            except subprocess.TimeoutExpired:
                console.kill()
                console.wait()
            stop.set()
            thread.join(60)
        windows, figures = meter.figures()
        doc = json.loads(meter.report.read_text()) if meter.report is not None and meter.report.exists() else None
        console_figures = _console_figures(out, time.perf_counter() - t0)
        if "error" in console_figures:
            print(f"runtime.cpu_serve: {console_figures['error']}; its stderr ends: "
                  f"{err.read_text()[-500:]}", file=sys.stderr, flush=True)
    judged = {"outcome": doc["outcome"] if doc else "not started", "finished_in_wall_limit": finished,
              "pots": len(world.pots),
              "inspected": sum(p["status"] == "inspected" for p in doc["pots"]) if doc else 0,
              "correct": correct_pots(world, doc) if doc else 0}
    bare = cached(("default",), lambda: metered_patrol(load_default_world(), config))[2]["runtime_cpu_per_robot_s"]
    served = figures.get("runtime_cpu_per_robot_s")
    return Sample(list(windows * 1000.0), {"pacing": "real time", **judged, **figures,
                                           "bare_patrol_cpu_per_robot_s": bare,
                                           "serving_adds_per_robot_s": round(served - bare, 4) if served else None,
                                           "console": {"snapshot_hz": hz, **console_figures}})
