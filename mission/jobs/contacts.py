"""Every contact of the chassis with the world, as it happens: what a bump count must count.

``NavigateRun.bumps`` keeps the first time each body was touched (enough to say *whether* and
*what* was hit); a trial that counts bumps from it misses a second touch of the same pot, or a
graze that comes and goes between two 10 Hz trace samples. ``ContactLog`` is sampled by the
simulator before every physics chunk (10 ms) and records each *onset*: a body touching the
chassis that was not touching it at the previous sample. A contact held for a while is one
contact; touching, letting go and touching again are two. Judging only: nothing steers by it.
``robot_contact_log`` counts a fleet's robots touching each other the same way (``sim.scene``).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable

if TYPE_CHECKING:
    from sim.scene import SimScene


class ContactLog:
    def __init__(self, touching: Callable[[], list[str]]):
        self._touching = touching
        self._now: set[str] = set()
        self.onsets: list[tuple[float, str]] = []
        """(sim time s, geom name) of every contact that began, oldest first."""

    def pre_chunk(self, t: float) -> None:
        """The simulator's hook (``sim.engine.Engine.attach``), called every physics chunk."""
        self.sample(t)

    def sample(self, t: float) -> None:
        now = set(self._touching())
        for name in sorted(now - self._now):
            self.onsets.append((t, name))
        self._now = now

    def since(self, t: float) -> list[tuple[float, str]]:
        """The contacts that began at or after ``t``."""
        return [c for c in self.onsets if c[0] >= t]


def robot_contact_log(scene: "SimScene") -> ContactLog:
    """Every contact between two robots of ``scene`` as it begins, named ``r1-r2`` (names sorted),
    sampled from now on before every physics chunk."""
    log = ContactLog(lambda: [f"{a}-{b}" for a, b in scene.robot_contacts()])
    scene.engine.attach(log)
    return log
