"""The running robot served live to Foxglove: the same channels as a recording
(``mission.record.channels``) on the foxglove-sdk WebSocket server.

The server advertises the ``Time`` capability and broadcasts the runtime clock at the
channels' 10 Hz, so the app's clock is the robot's (sim time in the sim) and matches every
message's timestamp. Channels only build messages while a sink listens, so an idle server
(nobody subscribed) costs the control loop almost nothing: the MCAP file, when there is one,
is the only other sink. Connect the app to ``ws://HOST:PORT``.
"""
from __future__ import annotations

import foxglove
from foxglove import Capability

from mission.record.channels import RATE, Parts, PatrolChannels, ns

DEFAULT_PORT = 8765
"""The Foxglove app's default connection (ws://localhost:8765)."""


class LiveServer:
    """A started WebSocket server fed by ``channels``; ``stop()`` ends both (idempotent)."""

    def __init__(self, parts: Parts, port: int = DEFAULT_PORT, host: str = "127.0.0.1",
                 channels: PatrolChannels | None = None, name: str | None = None):
        self.channels = channels or PatrolChannels.of(parts)
        self._own = channels is None
        """Shared channels (a recording's) are their owner's to stop; ours end with the server."""
        name = name or f"lupin {parts.robot.config.link.robot}"  # Foxglove names the robot it shows
        self.server = foxglove.start_server(name=name, host=host, port=port, capabilities=[Capability.Time],
                                            context=self.channels.context)
        self.scheduler = parts.robot.scheduler
        self._task = f"{self.channels.task}.time"
        self.channels.start()
        self.scheduler.every(self._task, RATE, self._time)
        self._running = True

    @property
    def port(self) -> int:
        return self.server.port

    def _time(self, now: float) -> None:
        self.server.broadcast_time(ns(now))

    def stop(self) -> None:
        if not self._running:
            return
        self._running = False
        self.scheduler.cancel(self._task)
        if self._own:
            self.channels.close()
        self.server.stop()


def serve_foxglove(parts: Parts, port: int = DEFAULT_PORT, host: str = "127.0.0.1",
                   channels: PatrolChannels | None = None) -> LiveServer:
    """Serve ``parts`` (robot, nav, optionally tree) live on ``host:port`` (0: any free port,
    read it back from ``.port``). ``channels``: share ones a recording already started."""
    return LiveServer(parts, port, host, channels)
