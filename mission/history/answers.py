"""The history's questions answered as plain JSON-ready data: what ``lupin serve`` sends a
console over the link (the ``history`` command) and what an in-process console reads. The same
shapes as ``lupin history ... --json``.

==========  ==========================================================================
query       answer
==========  ==========================================================================
patrols     ``{"patrols": [...]}``, newest first, at most ``limit``
pot         ``{"pot": ID, "timeline": [...]}``, oldest first (``pot`` required)
changes     ``{"after": patrol, "before": patrol | null, "changes": [...]}``
pests       ``{"mission", "patrols": [ids], "pots": [{pot_id, pests, observed, streak,
            pressure, x, y, ...}]}`` over the last ``last`` patrols
==========  ==========================================================================

Comparisons (``pot``, ``changes``, ``pests``) stay in one greenhouse, that of the latest patrol
they start from (spec/history.md), unless ``every`` is true.
"""
from __future__ import annotations

from typing import Literal

from mission.history.store import History

Query = Literal["patrols", "pot", "changes", "pests"]
QUERIES: tuple[str, ...] = ("patrols", "pot", "changes", "pests")


class BadQuery(ValueError):
    """A question the history cannot answer as asked (the reason, one line)."""


def answer(history: History, query: str, pot: str | None = None, mission: str | None = None, last: int = 10,
           limit: int = 20, every: bool = False) -> dict:
    """The answer to one question; BadQuery when it is malformed."""
    if query == "patrols":
        return {"patrols": [p.as_json() for p in history.patrols(mission, None, limit)]}
    if query == "pot":
        if not pot:
            raise BadQuery("history pot: name the pot (pot: ID)")
        return {"pot": pot, "timeline": [e.as_json() for e in history.pot_timeline(pot, mission, every)]}
    if query == "changes":
        return history.changes(mission, every).as_json()
    if query == "pests":
        return {"last": last, **history.pest_map(last, mission, every).as_json()}
    raise BadQuery(f"history: unknown query {query[:40]!r} (known: {', '.join(QUERIES)})")
