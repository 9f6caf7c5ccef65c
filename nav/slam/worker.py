"""The SLAM worker process: the mapper behind a pipe.

SLAM runs in its own process, as slam_toolbox did in the original, so a wedged or crashed SLAM
can never stall the control loop, and so it uses the robot's second core. The runtime side is
``nav.slam.supervisor``. The protocol is one message each way per scan:

* request ``Scan``: a revolution, the wheel odometry pose it was taken at, the map pose to start
  from (used by a fresh worker's first scan only), and whether the map is wanted back (and
  whole: a map to keep has a loop closure's pending re-render drawn first, ``nav.slam.rerender``);
* reply ``Reply``: the robot's map pose and ``map -> odom`` after that scan, the graph's size,
  the time the worker spent, the occupancy map when asked for, and what the scan added to the
  mapper's state (``checkpoint.Delta``), which the supervisor keeps.

Two more requests: ``Restore`` (first, to a worker that replaces a lost one: the checkpoint to go
on from) and ``Stall``, the test hook that makes a worker wedge for real (a busy loop, a call that
never returns) or work a while without answering, so the supervisor's judgement is tried on a
real process mid-patrol (``tests/nav/test_slam_respawn.py``, ``lupin bench slam.wedge``).

The pipe carries plain dataclasses of numpy arrays (a scan is ~4 KB, the map ~0.2 MB once a
second). A closed pipe ends the worker; nothing else does.

It is started as ``python -c 'nav.slam.worker.main' FD CONFIG_JSON`` (``LAUNCH``) with one end of a socket pair
inherited as FD: a fresh interpreter (~0.5 s to import), never a fork of the runtime (whose
MuJoCo, EGL and numba threads do not survive a fork) and independent of the caller's
``__main__`` (multiprocessing's spawn would re-run a user's script in the worker).
"""
from __future__ import annotations

import faulthandler
import json
import signal
import time
from dataclasses import dataclass
from multiprocessing.connection import Connection
from typing import Optional

import numpy as np

from hw.odometry import Pose2D
from nav.occupancy import OccupancyMap
from nav.slam.checkpoint import Checkpoint, Delta
from nav.slam.config import SlamConfig
from nav.slam.mapper import Mapper
from nav.slam.planar_icp import VoxelMap
from nav.slam.relocate import Window, relocate


@dataclass(frozen=True)
class Scan:
    stamp: float
    angles: np.ndarray
    ranges: np.ndarray
    odom: Pose2D
    start: Pose2D
    want_map: bool
    whole: bool = False
    """A map to keep (a patrol's end, a map save): any pending re-render is drawn first."""
    people: np.ndarray | None = None
    """Which returns fall on people (``nav.slam.people_mask``): neither registered nor drawn."""


@dataclass(frozen=True)
class Restore:
    """Go on from this checkpoint: the first scan then starts the mapper from it."""

    checkpoint: Checkpoint


@dataclass(frozen=True)
class Stall:
    """Test hook: ``spin`` (a busy loop forever), ``block`` (a call that never returns) or
    ``work`` (``seconds`` of CPU spent before the next scan is taken, then on as before)."""

    kind: str
    seconds: float = 0.0


@dataclass(frozen=True)
class Reply:
    stamp: float
    pose: Pose2D
    map_to_odom: Pose2D
    keyframes: int
    loop_closures: int
    busy_s: float
    """Wall seconds the worker spent on this scan (the round trip minus this is the overhead)."""
    occupancy: Optional[OccupancyMap] = None
    solve_s: float = 0.0
    """``busy_s`` of a scan that optimised the pose graph (0 for the others): the solve's cost."""
    cpu_s: float = 0.0
    """The worker process's CPU seconds so far (the robot runtime's share of the second core)."""
    kept_bytes: int = 0
    """Memory held for re-rendering: the kept scans and the keyframes' points."""
    delta: Optional[Delta] = None
    """What this scan added to the mapper's state: the supervisor's checkpoint is their sum."""
    restore_s: float = 0.0
    """Wall seconds this scan spent rebuilding the mapper from a checkpoint (a respawn's first)."""
    settle_s: float = 0.0
    """Of ``busy_s``, wall seconds spent drawing a pending re-render whole for ``Scan.whole``."""


STACK_AFTER = 0.8
"""A message still being worked on after this share of the supervisor's limit for it
(``reply_timeout``; ``startup_timeout`` until the mapper exists) has every thread's Python stack
written to stderr (the runtime's, its journal) by ``faulthandler``'s own thread, which answers
mid-computation, in numpy or numba too: a worker the supervisor then kills as wedged has said
where it was stuck, not only that it was, and one only slow on a starved machine has said why.
The worker writes it itself, before the limit: the supervisor never waits to kill."""


def warm_up(cfg: SlamConfig) -> None:
    """Compile (or load from numba's cache) the kernels a patrol reaches only now and then, the
    local map's table growing and the relocation search, before the first scan, within the
    supervisor's ``startup_timeout``; the every-scan ones compile on the first scan anyway.
    Compiled mid-patrol, one took over ``reply_timeout`` (5 CPU s) on a busy machine and the
    worker was killed as spinning, its map handed to a new one from the checkpoint
    (safety.people seed 115 at stop 63, its stack at the kill: ``planar_icp._rebuild``
    compiling, the first time the table grew)."""
    xy = np.column_stack([np.linspace(0.5, 2.0, 16), np.linspace(-1.0, 1.0, 16)])
    local = VoxelMap(cfg.voxel_size, cfg.local_map_range, cfg.max_points_per_voxel, slots=4)
    local.update(xy, Pose2D())  # sixteen voxels in four slots: the table grows
    relocate(xy, local, Pose2D(0.05, 0.0, 0.0), 0.3, 0.1, Window(np.zeros((1, 2)), np.zeros(1)))


def serve(conn: Connection, config: dict, mount: tuple[float, float, float]) -> None:
    """The process body: map every scan that arrives until the pipe closes."""
    cfg = SlamConfig(**config)
    warm_up(cfg)
    mapper: Mapper | None = None
    checkpoint: Checkpoint | None = None
    while True:
        faulthandler.cancel_dump_traceback_later()  # waiting for a message is no wedge
        try:
            msg = conn.recv()
        except (EOFError, OSError):
            return
        limit = cfg.startup_timeout if mapper is None else cfg.reply_timeout
        faulthandler.dump_traceback_later(STACK_AFTER * limit)
        if isinstance(msg, Restore):
            checkpoint = msg.checkpoint
            continue
        if isinstance(msg, Stall):
            stall(msg)
            continue
        t0 = time.perf_counter()
        restore = 0.0
        if mapper is None:
            if checkpoint is None:
                mapper = Mapper(cfg, Pose2D(*mount), msg.start)
            else:
                mapper, checkpoint = Mapper.restored(cfg, Pose2D(*mount), checkpoint, msg.start), None
                restore = time.perf_counter() - t0
        solves = mapper.solves
        pose = mapper.process(msg.angles, msg.ranges, msg.odom, msg.people)
        settle = 0.0
        if msg.whole:
            t1 = time.perf_counter()
            mapper.settle()
            settle = time.perf_counter() - t1
        occ = mapper.occupancy() if msg.want_map else None
        busy = time.perf_counter() - t0
        reply = Reply(msg.stamp, pose, mapper.map_to_odom, mapper.keyframes, mapper.loop_closures,
                      busy, occ, busy if mapper.solves > solves else 0.0, time.process_time(), mapper.kept_bytes,
                      mapper.delta(), restore, settle)
        try:
            conn.send(reply)
        except (BrokenPipeError, OSError):
            return


def stall(msg: Stall) -> None:
    """The test hook's wedges, for real: a busy loop, a call that never returns, or bounded work."""
    if msg.kind == "spin":
        while True:
            pass
    if msg.kind == "block":
        signal.pause()  # no signal comes (SIGINT is ignored): blocked until killed
    end = time.process_time() + msg.seconds
    while time.process_time() < end:
        pass


#: The worker's command line after the interpreter (its classes then pickle as ``nav.slam.worker.*``,
#: which ``-m nav.slam.worker`` would not give: there they would live in ``__main__``).
LAUNCH = ["-c", "import sys; from nav.slam.worker import main; main(sys.argv[1:])"]


def main(argv: list[str]) -> None:
    # Ctrl-C in a terminal reaches the whole process group: the runtime decides when SLAM stops
    # (it kills this worker on close or on a map reset), so the worker must not die mid-run.
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    fd, config = int(argv[0]), json.loads(argv[1])
    mount = tuple(config.pop("lidar_mount"))
    serve(Connection(fd), config, mount)

