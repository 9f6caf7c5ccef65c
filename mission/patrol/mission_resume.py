"""Resume a patrol that ended early (issue 31 item 4): ``lupin mission resume REPORT`` and
``lupin patrol --resume REPORT``.

The mission a patrol ran is written beside its report (``mission.yaml``, as ``config.yaml``
is), so a report is enough: the resumed mission is that mission's pots the report left undone,
``skipped`` (the patrol ended before them: switched off, stopped, out of charge) or not there at
all (a report read after a kill holds only the pots finished before it), in the shortest order
from the dock. Pots inspected or tried and failed are done: a failed pot's report says why.
"""
from __future__ import annotations

from pathlib import Path

from hw.errors import InputError
from mission.patrol.mission_file import Mission, load_mission
from mission.patrol.mission_update import read_report

MISSION_FILE = "mission.yaml"
"""The mission a patrol ran, beside its report."""


def undone(mission: Mission, doc: dict) -> list[str]:
    """The ids of ``mission``'s pots that the report ``doc`` did not finish."""
    status = {p["id"]: p.get("status") for p in doc.get("pots", [])}
    return [p.id for p in mission.pots if status.get(p.id, "skipped") == "skipped"]


def resume_mission(report: Path) -> Mission:
    """The mission of the pots ``report`` left undone; ``InputError`` naming the file when the
    report or the mission beside it cannot be read, or nothing is left to do."""
    report = Path(report)
    doc = read_report(report)
    beside = report.parent / MISSION_FILE
    if not beside.exists():
        raise InputError(f"{report}: no {MISSION_FILE} beside it: the mission the patrol ran is needed to resume it "
                         f"(lupin patrol writes it there)")
    mission = load_mission(beside)
    left = set(undone(mission, doc))
    if not left:
        raise InputError(f"{report}: every pot of mission {mission.name!r} was done: nothing to resume")
    return mission.model_copy(update={"pots": [p for p in mission.pots if p.id in left], "order": "shortest"})
