"""The runtime's side of SLAM: the worker process, its pipe, its respawn, and ``map -> odom``.

This is what navigation holds as its ``Localisation`` in SLAM mode. ``tick`` runs at 10 Hz on
the runtime's scheduler (the seed's transform_publish_period 0.10: map -> odom at 10 Hz, down
from slam_toolbox's 50 Hz, one of the two bandwidth levers of the original). Each tick collects
the worker's reply to the previous scan and sends the newest scan, so the worker computes while
the runtime runs on (it uses the second core), and a scan's result is applied one tick later:

* **lock-step** (the sim): the tick waits for the reply it is due, so the reply is applied at
  the same sim time whatever the machine's load, and runs stay deterministic for a seed;
* **free-running** (the robot): the tick never waits; a scan that finds the worker busy is
  dropped and the latest reply stands. Either way a worker silent for ``reply_timeout`` counts
  as wedged and is killed.

**The map reset** (seed, "Resetting the map"): slam_toolbox had no wipe-map call, so the
original killed the process and let ``respawn_delay=1.0`` bring it back with an empty graph.
``reset`` does the same: it kills the worker and a fresh one starts ``respawn_delay`` later on
the runtime clock; a worker that dies on its own (or wedges) is replaced the same way. Through
the gap ``map -> odom`` holds its last value, so navigation runs on wheel odometry, and the new
worker starts its graph at the robot's current map pose: the map frame (the dock) survives the
reset, and so do goals and mission poses given in it. The caller clears the costmaps.

**A lost worker costs seconds, not the map** (issue 29): every reply carries what its scan added
to the mapper's state, which is folded into a ``Checkpoint`` held here (``nav.slam.checkpoint``
says why here and not on disk). A worker that wedges or crashes is replaced by one that is
handed the checkpoint before its first scan and goes on from it at the robot's current map pose:
same graph, same kept scans, the map as last handed back. Only the operator's map reset drops
the checkpoint, so the fresh worker starts an empty map as the seed's reset did. The checkpoint
travels to the new worker from a helper thread, since the new interpreter reads it only once it
has imported (seconds on a cold Pi) and the runtime's thread must not wait on it; lock-step
waits for it (its clock stands still meanwhile, so runs stay deterministic).
"""
from __future__ import annotations

import json
import logging
import subprocess
import sys
import threading
from multiprocessing.connection import Pipe
from typing import Callable, Optional

from hw.interfaces import LidarScan
from hw.odometry import Pose2D
from hw.people import PeopleSource, nobody
from nav.frames import compose
from nav.occupancy import OccupancyMap
from nav.slam import worker
from nav.slam.checkpoint import Checkpoint
from nav.slam.config import SlamConfig
from nav.slam.liveness import Liveness
from nav.slam.people_mask import on_people

log = logging.getLogger(__name__)

_SLICE = 0.25
"""Seconds a lock-step wait polls between looks at the worker's CPU time: a poll that comes back
empty has waited that long, so the wait is timed without reading a clock."""


class SlamSupervisor:
    def __init__(self, cfg: SlamConfig, lidar_mount: Pose2D, odom_pose: Callable[[], Pose2D],
                 scan: Callable[[], Optional[LidarScan]], on_map: Callable[[OccupancyMap], None] = lambda m: None,
                 deterministic_clock: bool = True, people: PeopleSource = nobody):
        self.cfg = cfg
        self.lockstep = deterministic_clock if cfg.lockstep is None else cfg.lockstep
        self.rate = 1.0 / cfg.transform_publish_period
        """Hz the runtime ticks this at: map -> odom's publish rate."""
        self.mount = lidar_mount
        self.odom_pose, self.scan, self.on_map = odom_pose, scan, on_map
        self.people = people
        """The people whose returns are neither registered nor mapped (odom): those pressing on
        the robot (``nav.slam.people_mask``)."""
        self._map_to_odom = Pose2D()
        self.occupancy: OccupancyMap | None = None
        """The latest map the worker handed back."""
        self.last_reply: worker.Reply | None = None
        self.listeners: list[Callable[[worker.Reply], None]] = []
        """Called with every reply as it is taken (a benchmark's meter, say)."""
        self.spawned = self.deaths = 0
        self.spared = 0
        """Replies that came later than the limit from a worker that kept using CPU: starved, not
        wedged, so waited for (``nav.slam.liveness``)."""
        self._proc = None
        self._conn = None
        self._pending: float | None = None
        """Runtime time the outstanding scan was sent at, None when none is."""
        self._watch: Liveness | None = None
        """Tells a wedged worker from a starved one once a reply is late (None until then)."""
        self._sent_stamp = -1.0
        self._respawn_at: float | None = 0.0
        self._answered = False
        """Has the current worker replied yet (before that, ``startup_timeout`` applies)?"""
        self._next_map = 0.0
        self._whole = False
        """Is the next map asked for one to keep (``request_map``)?"""
        self.checkpoint = Checkpoint()
        """What a replacement worker goes on from (emptied by the map reset)."""
        self.restored = 0
        """Workers started from the checkpoint rather than an empty map."""
        self._handing: threading.Thread | None = None
        """Sending the checkpoint to a new worker; no scan is sent until it is done."""

    # -- Localisation --------------------------------------------------------------------------

    def map_to_odom(self) -> Pose2D:
        return self._map_to_odom

    def has_map(self) -> bool:
        return self.occupancy is not None

    def ready(self) -> bool:
        """``map -> odom`` resolves once a worker has answered a scan; it then stays resolved
        (held through a reset's gap)."""
        return self.last_reply is not None

    # -- the beat ------------------------------------------------------------------------------

    def tick(self, now: float) -> None:
        if self._proc is None:
            if self._respawn_at is not None and now >= self._respawn_at - 1e-9:
                self._spawn()
            else:
                return
        if self._handing is not None:
            if self.lockstep:
                self._handing.join()
            if self._handing.is_alive():
                return
            self._handing = None
        if self._pending is not None and not self._collect(now):
            return
        scan = self.scan()
        if scan is None or scan.stamp <= self._sent_stamp:
            return
        want_map = now >= self._next_map - 1e-9
        odom = self.odom_pose()
        start = compose(self._map_to_odom, odom)
        try:
            self._conn.send(worker.Scan(scan.stamp, scan.angles, scan.ranges, odom, start, want_map, self._whole,
                                        on_people(scan.angles, scan.ranges, compose(odom, self.mount), self.people())))
        except (BrokenPipeError, OSError):
            self._lost(now, "its pipe broke")
            return
        if want_map:
            self._next_map = now + self.cfg.map_update_interval
            self._whole = False
        self._pending, self._sent_stamp = now, scan.stamp
        self._watch = None

    def request_map(self) -> None:
        """Have the next exchange bring the map back, whatever the update interval, and whole
        (a map save, a patrol's end): a loop closure's re-render still being drawn is finished
        first, in that one exchange (``nav.slam.rerender``)."""
        self._next_map = float("-inf")
        self._whole = True

    def stall(self, kind: str, seconds: float = 0.0) -> None:
        """Test hook: have the worker wedge for real (``spin``, ``block``) or work ``seconds``
        of CPU silently (``work``) once it has answered the scan it holds (``worker.Stall``)."""
        self._conn.send(worker.Stall(kind, seconds))

    def reset(self, now: float) -> int:
        """The map reset: kill the worker; a fresh one starts ``respawn_delay`` later, from an
        empty map. Returns how many workers were killed (0 when none was running, e.g. inside
        a reset's gap)."""
        killed = self._kill()
        self.occupancy = None  # erased: nothing may save or show the old map from now on
        self.checkpoint = Checkpoint()
        self._respawn_at = now + self.cfg.respawn_delay
        log.info("map reset: killed %d SLAM worker(s); respawning in %.1f s", killed, self.cfg.respawn_delay)
        return killed

    def close(self) -> None:
        self._kill()
        self._respawn_at = None

    @property
    def pid(self) -> int | None:
        return self._proc.pid if self._proc is not None else None

    # -- internals -----------------------------------------------------------------------------

    def _spawn(self) -> None:
        parent, child = Pipe()
        mx = self.mount
        config = json.dumps({**self.cfg.model_dump(mode="json"), "lidar_mount": [mx.x, mx.y, mx.yaw]})
        self._proc = subprocess.Popen([sys.executable, *worker.LAUNCH, str(child.fileno()), config],
                                      pass_fds=(child.fileno(),), stdin=subprocess.DEVNULL)
        child.close()
        self._conn = parent
        if not self.checkpoint.empty:
            self._handing = threading.Thread(target=self._hand_over, args=(parent, self.checkpoint),
                                             name="slam-checkpoint", daemon=True)
            self._handing.start()
            self.restored += 1
        self._pending, self._respawn_at = None, None
        self._answered = False
        self._next_map = 0.0
        self.spawned += 1

    @staticmethod
    def _hand_over(conn, checkpoint: Checkpoint) -> None:
        try:
            conn.send(worker.Restore(checkpoint))
        except (BrokenPipeError, OSError):
            pass  # the worker died before reading it: the next exchange finds that out

    def _collect(self, now: float) -> bool:
        """Take the reply to the outstanding scan; False if there is none (yet).

        Lock-step waits, slice by slice, for as long as the worker is working, however slowly
        (the wait's clock is the slices waited); free-running looks once and judges the silence
        on the runtime clock from when the scan was sent. Only a late reply costs a look at the
        worker's CPU time."""
        limit = self.cfg.reply_timeout if self._answered else self.cfg.startup_timeout
        waited = 0.0
        try:
            while not self._conn.poll(min(_SLICE, limit) if self.lockstep else 0.0):
                if self._watch is None:
                    self._watch = Liveness(self._proc.pid, 0.0 if self.lockstep else self._pending)
                waited += min(_SLICE, limit)
                why = self._watch.wedged(waited if self.lockstep else now, limit)
                if why is not None:
                    self._lost(now, why + ", wedged")
                    return False
                if not self.lockstep:
                    return False
            reply: worker.Reply = self._conn.recv()
        except (EOFError, OSError):
            self._lost(now, "it exited")
            return False
        if (waited if self.lockstep else now - self._pending) >= limit:
            self.spared += 1
        self._pending = None
        self.last_reply = reply
        for listener in self.listeners:
            listener(reply)
        self._answered = True
        self._map_to_odom = reply.map_to_odom
        if reply.delta is not None:
            self.checkpoint.apply(reply.delta)
        if reply.occupancy is not None:
            self.checkpoint.map(reply.occupancy)
            self.occupancy = reply.occupancy
            self.on_map(reply.occupancy)
        return True

    def _lost(self, now: float, why: str) -> None:
        log.warning("SLAM worker lost (%s); respawning in %.1f s from the checkpoint", why, self.cfg.respawn_delay)
        self.deaths += 1
        if not self._answered and not self.checkpoint.empty:
            # lost before its first reply: the checkpoint itself may be what it cannot get past,
            # so the next worker starts an empty map rather than dying the same way for ever
            log.warning("SLAM worker lost before starting from the checkpoint; the next starts an empty map")
            self.checkpoint = Checkpoint()
        self._kill()
        self._respawn_at = now + self.cfg.respawn_delay

    def _kill(self) -> int:
        if self._proc is None:
            return 0
        proc, conn = self._proc, self._conn
        self._proc = self._conn = None
        self._pending = None
        alive = proc.poll() is None
        proc.kill()
        proc.wait(timeout=5.0)
        if self._handing is not None:  # its send fails on the dead peer: then the pipe may close
            self._handing.join()
            self._handing = None
        conn.close()
        return int(alive)
