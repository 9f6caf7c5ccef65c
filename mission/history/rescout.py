"""Directed re-scouting: a mission back to where pests were found.

Integrated pest management checks the plants around a find, not just the find: the pots with
a pest in any of the last N patrols of a mission, plus every pot within R metres of one of them
(centre to centre, where each was last seen), make a new mission. Its pots are listed in the
shortest straight-line tour from home and its order is ``shortest``, so the patrol orders them
again over the planner's path lengths on the map it has (``mission.patrol.visit_order``). It is
a mission like any other: ``lupin patrol --mission`` runs it.

Poses come from the history (``observations.x``, ``y``, ``facing``, ``tag_expected`` of each
pot's latest row), so the mission file the patrols ran is not needed.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from hw.errors import InputError
from mission.history.records import PestMap, PestPressure
from mission.patrol.mission_file import Mission, MissionPot
from mission.patrol.visit_order import visit_order


@dataclass(frozen=True)
class Rescout:
    mission: Mission
    pests: tuple[str, ...]
    """Pots with a pest in the patrols looked at."""
    neighbours: tuple[str, ...]
    """Pots added for being within the radius of one."""


def select_pots(pests: PestMap, radius: float) -> tuple[list[PestPressure], list[PestPressure]]:
    """(pots with a pest, their neighbours within ``radius`` m that had none), in ``pests``' order."""
    placed = [p for p in pests.pots if p.x is not None and p.y is not None]
    found = [p for p in placed if p.pests]
    if not found:
        return [], []
    xy = np.array([(p.x, p.y) for p in placed])
    centres = np.array([(p.x, p.y) for p in found])
    near = (np.hypot(*(xy[:, None, :] - centres[None, :, :]).transpose(2, 0, 1)) <= radius + 1e-9).any(axis=1)
    return found, [p for p, n in zip(placed, near) if n and not p.pests]


def rescout(pests: PestMap, radius: float, name: str | None = None) -> Rescout | None:
    """The re-scouting mission over ``pests`` (the last patrols of one mission), or None when no
    pot had a pest. InputError when a chosen pot has no recorded facing (rows written before
    schema version 2): its approach pose cannot be known."""
    found, around = select_pots(pests, radius)
    if not found:
        return None
    chosen = found + around
    blind = [p.pot_id for p in chosen if p.facing is None]
    if blind:
        raise InputError(f"history: pot(s) {', '.join(blind)} have no recorded facing (recorded before history "
                         f"schema 2), so they cannot be approached; patrol them once with this Lupin first")
    pots = [MissionPot(id=p.pot_id, x=p.x, y=p.y, facing=p.facing, tag=p.tag) for p in chosen]
    draft = Mission(name=name or f"{pests.mission}-rescout", pots=pots, order="shortest")
    ordered = visit_order(draft, (draft.home.x, draft.home.y))
    return Rescout(draft.model_copy(update={"pots": ordered}), tuple(p.pot_id for p in found),
                   tuple(p.pot_id for p in around))
