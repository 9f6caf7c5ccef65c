"""What needs a person after a patrol (spec/web.md ``/alerts``): the grower's short list.

===========  ==========================================================================
kind         when
===========  ==========================================================================
pest_new     a pest now where the patrol before saw none (``changes``' ``pest_new``)
spreading    that new pest is within ``radius`` of a pot that had a pest the patrol before:
             integrated pest management reads a find beside a find as the pest moving
failed       the pot failed in both of the last two patrols (once is a person in the aisle;
             twice in a row, something a person must look at)
moved        the pot was found moved (its ``moved`` anomaly): the mission needs updating
===========  ==========================================================================

Pure functions on two patrols' rows (the latest and the one before it, of one mission in one
greenhouse), shared by the dashboard's page and its JSON; the pest rule is ``changes``' own.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Sequence

import numpy as np

from mission.history.changes import pot_changes
from mission.history.records import Observation

KINDS = ("pest_new", "spreading", "failed", "moved")
SPREAD_RADIUS_M = 1.0
"""A new pest this near (centre to centre) to last patrol's pest is spreading: the re-scouting
mission's default radius (``lupin mission rescout --radius``), the neighbours IPM checks."""


@dataclass(frozen=True)
class Alert:
    pot: str
    kind: str
    detail: str

    def as_json(self) -> dict:
        return asdict(self)


def alerts(latest: Sequence[Observation], before: Sequence[Observation],
           radius: float = SPREAD_RADIUS_M) -> list[Alert]:
    """The alerts of patrol ``latest`` against ``before`` (empty: no patrol before), in the
    latest patrol's order, a spreading pest listed once (as spreading, not also as new)."""
    prior = {o.pot_id: o for o in before}
    sources = [o for o in before if o.bug is True and o.x is not None and o.y is not None]
    out: list[Alert] = []
    for o in latest:
        was = prior.get(o.pot_id)
        if was is not None and any(c.kind == "pest_new" for c in pot_changes(was, o)):
            near = _nearest(o, sources)
            if near is not None and near[1] <= radius + 1e-9:
                out.append(Alert(o.pot_id, "spreading", f"new pest {near[1]:.1f} m from {near[0]}, "
                                                        f"which had one the patrol before"))
            else:
                out.append(Alert(o.pot_id, "pest_new", "new pest (none the patrol before)"))
        if o.status == "failed" and was is not None and was.status == "failed":
            why = ", ".join(o.anomalies) or "failed"
            out.append(Alert(o.pot_id, "failed", f"failed twice in a row ({why})"))
        if "moved" in o.anomalies:
            where = f" (now at {o.x:.2f}, {o.y:.2f})" if o.x is not None and o.y is not None else ""
            out.append(Alert(o.pot_id, "moved", f"found moved{where}: update the mission"))
    return out


def _nearest(pot: Observation, sources: Sequence[Observation]) -> tuple[str, float] | None:
    """The nearest other pot of ``sources`` and its distance, m; None when there is none."""
    others = [s for s in sources if s.pot_id != pot.pot_id]
    if pot.x is None or pot.y is None or not others:
        return None
    d = np.hypot([s.x - pot.x for s in others], [s.y - pot.y for s in others])
    k = int(np.argmin(d))
    return others[k].pot_id, float(d[k])
