"""A mission kept true to what the robot saw: ``lupin mission update MISSION --report R``.

From a patrol's report: every pot reported ``moved`` goes to its measured pose (the anomaly's
``x``, ``y``, ``facing``); every tag discovered en route that no pot of the mission carries
becomes a new pot at the pose its tag reads put it (the discovered tag's ``pot``), id ``T017``
for tag 17 (unless taken), flagged in the file with a comment for the operator to check before
it is patrolled: a plate seen in passing may be on a pot the mission leaves out on purpose.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from hw.errors import InputError
from mission.patrol.mission_file import Mission, MissionPot, dump_mission

REVIEW = "# NEW: a tag the patrol discovered; check this pot before patrolling it"


@dataclass(frozen=True)
class Update:
    mission: Mission
    moved: list[str]
    added: list[str]

    def text(self) -> str:
        """The mission file, each new pot's line flagged for review."""
        lines = dump_mission(self.mission).splitlines()
        flagged = [f"{line}  {REVIEW}" if any(line.startswith(f"- {{id: {pid},") for pid in self.added) else line
                   for line in lines]
        return "\n".join(flagged) + "\n"


def read_report(path: Path) -> dict:
    """A patrol report (spec/report.md), checked enough to update a mission from."""
    try:
        doc = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise InputError(f"{path}: report not found") from None
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise InputError(f"{path}: not a patrol report (JSON): {exc}") from None
    if not isinstance(doc, dict) or not isinstance(doc.get("anomalies"), list) or not isinstance(doc.get("pots"), list):
        raise InputError(f"{path}: not a patrol report: it needs 'pots' and 'anomalies' lists (spec/report.md)")
    return doc


def update_mission(mission: Mission, report: dict, source: str) -> Update:
    """The mission with the report's moved pots where they were measured and its discovered
    tags added as new pots."""
    pots = {p.id: p for p in mission.pots}
    moved = []
    for i, a in enumerate(report["anomalies"]):
        if not isinstance(a, dict) or a.get("kind") != "moved":
            continue
        where = f"{source}: anomalies[{i}] (moved {a.get('pot')!r})"
        if a.get("pot") not in pots:
            raise InputError(f"{where}: the mission has no such pot (was this report from another mission?)")
        try:
            x, y, facing = float(a["x"]), float(a["y"]), float(a.get("facing", pots[a["pot"]].facing))
        except (KeyError, TypeError, ValueError):
            raise InputError(f"{where}: needs numbers 'x' and 'y' (the measured position)") from None
        pots[a["pot"]] = pots[a["pot"]].model_copy(update={"x": round(x, 4), "y": round(y, 4), "facing": round(facing, 4)})
        moved.append(a["pot"])
    tags = {p.tag for p in pots.values() if p.tag is not None}
    added = []
    for d in report.get("discovered_tags", []):
        pot = d.get("pot") if isinstance(d, dict) else None
        if not isinstance(pot, dict) or d.get("id") in tags:
            continue  # an older report places the tag but not its pot: nothing to add from it
        pid = f"T{int(d['id']):03d}"
        while pid in pots:
            pid += "+"
        pots[pid] = MissionPot(id=pid, x=round(float(pot["x"]), 4), y=round(float(pot["y"]), 4),
                               facing=round(float(pot["facing"]), 4), tag=int(d["id"]))
        tags.add(int(d["id"]))
        added.append(pid)
    return Update(mission.model_copy(update={"pots": list(pots.values())}), moved, added)
