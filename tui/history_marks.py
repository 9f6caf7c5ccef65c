"""What the pot table shows of the patrol history: per pot, what changed since the last patrol
and its pest streak, made from the robot's ``changes`` and ``pests`` answers
(:mod:`mission.history.answers`, read over the link).

The history compares a mission's last two patrols, and the latest is the one running: while a
patrol goes, the "since last" cells fill in as its pots are recorded, and after it they say what
it found different from the one before. A pest streak counts the latest patrols in a row that
saw a pest at the pot, so the running patrol, which has not judged the pots ahead of it yet,
would read 0 for all of them; a pot not visited yet in the running patrol keeps the streak the
console knew for it (the grower's "this pot had a pest the last three times" is what matters
before the robot gets there).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Mapping

ORDER = ("pest_new", "failed", "pest_cleared", "color", "blooms")
"""Which change a pot's cell names when it has several (the rest are counted, ``+1``): the pot
table sits in a 62-column panel, and a new pest matters most."""
PEST_PATROLS = 20
"""How many of the latest patrols the streak is counted over (``pests``' ``last``): a longer
streak shows as ``x20+``."""


@dataclass(frozen=True)
class PotMarks:
    """One pot's history cells: ``since`` (blank: nothing changed), ``streak`` (0: none)."""
    since: str = ""
    streak: int = 0
    capped: bool = False
    """The streak reached ``PEST_PATROLS``: there may be more."""

    @property
    def streak_text(self) -> str:
        """``x3``: the latest three patrols saw a pest (the column is headed ``pests``)."""
        return f"x{self.streak}{'+' if self.capped else ''}" if self.streak else ""


def change_text(change: Mapping) -> str:
    """One change (``mission.history.changes``' kinds) in a few characters."""
    kind, before, after = change.get("kind"), change.get("before"), change.get("after")
    if kind == "pest_new":
        return "pest new"
    if kind == "pest_cleared":
        return "pest gone"
    if kind == "color":
        return f"{before}→{after}"
    if kind == "blooms":
        return f"bloom {before}→{after}"
    if kind == "failed":
        return "failed now"
    return str(kind or "?")


def _rank(change: Mapping) -> int:
    kind = change.get("kind")
    return ORDER.index(kind) if kind in ORDER else len(ORDER)


def since_texts(changes: Mapping | None) -> dict[str, str]:
    """Pot -> its most telling change, ``+N`` more (the ``changes`` answer; None or malformed:
    nothing)."""
    out: dict[str, list[Mapping]] = {}
    for c in (changes or {}).get("changes") or ():
        if isinstance(c, Mapping) and c.get("pot"):
            out.setdefault(str(c["pot"]), []).append(c)
    texts = {}
    for pot, found in out.items():
        first = min(found, key=_rank)
        texts[pot] = change_text(first) + (f" +{len(found) - 1}" if len(found) > 1 else "")
    return texts


def streaks(pests: Mapping | None) -> dict[str, int]:
    """Pot -> pest streak (the ``pests`` answer; pots without one left out)."""
    out = {}
    for p in (pests or {}).get("pots") or ():
        if isinstance(p, Mapping) and p.get("pot_id") and isinstance(p.get("streak"), int) and p["streak"] > 0:
            out[str(p["pot_id"])] = p["streak"]
    return out


def pot_marks(changes: Mapping | None, pests: Mapping | None, known: Mapping[str, PotMarks] | None = None,
              not_yet: Iterable[str] = ()) -> dict[str, PotMarks]:
    """Each pot's marks from the two answers; the pots in ``not_yet`` (the running patrol has
    not judged them) keep the streak ``known`` gave them when the answer has none."""
    since, streak = since_texts(changes), streaks(pests)
    last = (pests or {}).get("last", PEST_PATROLS)
    cap = last if isinstance(last, int) and last > 0 else PEST_PATROLS
    for pot in not_yet:
        old = (known or {}).get(pot)
        if pot not in streak and old is not None and old.streak:
            streak[pot] = old.streak
    return {pot: PotMarks(since.get(pot, ""), streak.get(pot, 0), streak.get(pot, 0) >= cap)
            for pot in since.keys() | streak.keys()}
