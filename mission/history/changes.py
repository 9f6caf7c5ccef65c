"""What changed at a pot between two patrols: the grower's "what is new since this morning".

Only what changed is listed, one :class:`~mission.history.records.Change` per kind:

============  =====================================================================
kind          when
============  =====================================================================
pest_new      a pest now, none seen before (or the pot's flower was not judged before)
pest_cleared  a pest before, and now the flower was judged and has none
color         the bloom colour differs (``none`` is no bloom), both judged
blooms        the bloom count differs, both judged
failed        the pot failed now (never inspected) and did not before
============  =====================================================================

A pot not judged now (failed, skipped, arm unavailable) says nothing about its flower: it can
clear no pest and change no colour. Pure functions on records, shared by ``report.json``'s
``changes`` (computed as each pot is recorded) and ``lupin history changes``.
"""
from __future__ import annotations

from typing import Iterable, Mapping

from mission.history.records import Change, Observation

KINDS = ("pest_new", "pest_cleared", "color", "blooms", "failed")


def pot_changes(before: Observation, after: Observation) -> list[Change]:
    """The changes at one pot from ``before`` to ``after`` (the same pot, two patrols)."""
    pot, out = after.pot_id, []
    if after.bug is True and before.bug is not True:
        why = "not judged before" if before.bug is None else "none before"
        plant = "a plant with no bloom" if after.flower_color == "none" else f"a {after.flower_color or '?'} plant"
        out.append(Change(pot, "pest_new", before.bug, True, f"pest on {plant} ({why})"))
    if before.bug is True and after.bug is False:
        out.append(Change(pot, "pest_cleared", True, False, "no pest now"))
    if before.flower_color is not None and after.flower_color is not None and before.flower_color != after.flower_color:
        out.append(Change(pot, "color", before.flower_color, after.flower_color,
                          f"colour {before.flower_color} -> {after.flower_color}"))
    if before.blooms is not None and after.blooms is not None and before.blooms != after.blooms:
        out.append(Change(pot, "blooms", before.blooms, after.blooms, f"blooms {before.blooms} -> {after.blooms}"))
    if after.status == "failed" and before.status != "failed":
        why = ", ".join(k for k in after.anomalies if k) or "failed"
        out.append(Change(pot, "failed", before.status, "failed", f"failed now ({why}); {before.status} before"))
    return out


def patrol_changes(before: Mapping[str, Observation], after: Iterable[Observation]) -> list[Change]:
    """Every change over the pots of ``after`` (in its order) that ``before`` also saw."""
    out: list[Change] = []
    for obs in after:
        prior = before.get(obs.pot_id)
        if prior is not None:
            out += pot_changes(prior, obs)
    return out
