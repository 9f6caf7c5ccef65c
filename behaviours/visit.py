"""What the leaves of one pot's branch find out, gathered for the report.

One :class:`PotVisit` per pot of the mission, created with the tree and filled in as its leaves
run: navigation attempts and the pose the robot believed it reached, the wrist frame and what
the flower detector made of it, the front frame and the tags read in it, and every step that
failed with its reason. The report (``mission.patrol.report``) turns it into JSON; nothing here
decides what is an anomaly.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from hw.odometry import Pose2D
from perception.camera_pipeline import Frame
from perception.detections import FlowerFrame, TagRead


@dataclass
class PotVisit:
    id: str
    attempts: int = 0
    """Navigation attempts started for this pot."""
    arrived: Pose2D | None = None
    """The robot's map pose (its belief) where it stands for the pot: taken when the approach
    succeeded, and again when the wrist is aimed (a loop closure in between moves it)."""
    view: str | None = None
    """The arm pose the wrist frame is taken from: the patrol's inspect preset ('inspect_plant'), or
    'aim' (IK, off the ideal pose)."""
    wrist: Frame | None = None
    flower: FlowerFrame | None = None
    """The detector's reading of ``wrist``; None when no wrist frame was taken."""
    front: Frame | None = None
    tags: tuple[TagRead, ...] = ()
    """Every whitelisted tag read in ``front``, nearest first."""
    located: tuple[float, float, float] | None = None
    """Where the pot's own tag put the pot (x, y, facing in the map), when it was read."""
    own_tag: TagRead | None = None
    """The read of the pot's own tag that placed it (kept when a later frame misses it)."""
    moved: bool = False
    """``located`` is off the mission's pose beyond the map's drift there: the pot itself moved
    (and was driven to)."""
    drift: tuple[float, float] = (0.0, 0.0)
    """The map's drift from the mission's frame where the pot was located (``located`` less this
    is where the pot stands in the mission's frame): the offset the moved decision was made on."""
    drift_known: bool = False
    """The neighbours read nearest in time agreed on ``drift`` (else it is what all those near
    agree on, or zero, and ``moved`` is provisional, judged again at the patrol's end)."""
    failures: dict[str, str] = field(default_factory=dict)
    """Step -> why it failed ('approach', 'search', 'arm', 'wrist', 'front')."""
    done: bool = False
    """The pot's branch has finished (inspected or failed) and been recorded."""
    aside: str = ""
    """Why the robot stood beside the approach pose instead, and where (empty: it stood there or
    near): something else stood on it, and a look beside it read the pot's tag
    (``mission.patrol.aside``)."""
    deferred: str = ""
    """Why its first go could not get there (empty: it did, or has not been tried): the patrol
    comes back to it after the other pots instead of failing it at once."""
