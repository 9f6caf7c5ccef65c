"""Link settings: who the robot is on the link, where it listens, who may command it.

The seed's compute split is the lesson behind the rates: over the robot's access point little
should cross (compressed images on request, map deltas), and the robot never waits on it.
"""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class LinkConfig(BaseModel):
    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)

    robot: str = Field("mirte", pattern=r"^[A-Za-z0-9_-]+$")
    """The robot's name: every key is under ``lupin/<robot>/`` so several robots can share one
    Zenoh router."""
    listen: str = "tcp/127.0.0.1:7447"
    """The endpoint ``lupin serve`` listens on (explicit: no multicast scouting). Loopback by
    default; ``tcp/0.0.0.0:7447`` to accept consoles from the network."""
    token: str = ""
    """The operator token every command but 'engage the soft e-stop' must carry. Empty: ``lupin
    serve`` makes a random one at start-up and prints it (give it to the console with
    ``--token`` or ``LUPIN_LINK__TOKEN``)."""
    fast_rate: float = Field(10.0, gt=0)
    """Pose, velocity, mux source, e-stop, battery, Hz: the controllers' beat."""
    slow_rate: float = Field(2.0, gt=0)
    """Navigation status and plan, mission state and tree, pots, controllers, scan, Hz."""
    map_rate: float = Field(1.0, gt=0)
    """Map and costmap deltas, Hz (SLAM hands its map back once a second)."""
    queue: int = Field(256, ge=8)
    """Outgoing messages held for the sender thread; when full the oldest is dropped, so the
    control loop never waits on the link."""
    command_timeout: float = Field(2.0, gt=0)
    """Seconds a command waits for the runtime's answer before the client is told it timed out."""
