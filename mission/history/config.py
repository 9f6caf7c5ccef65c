"""History settings: where the patrol history lives (spec/history.md)."""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field


class HistoryConfig(BaseModel):
    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)

    url: str = Field("lupin-history.db", min_length=1)
    """Where every patrol is recorded: a file path (SQLite, embedded, nothing to install; the
    default ``lupin-history.db`` is in the directory the command runs in), ``sqlite:///PATH``,
    a PostgreSQL URL (``postgresql://user@host/db``: a farm server several robots and people
    share), or ``none`` to record nothing. ``--history`` overrides it."""
    connect_timeout: float = Field(5.0, gt=0)
    """Seconds to reach a PostgreSQL server before it counts as unreachable: an unreachable
    database is an error before the robot moves, and should not take long to say so."""
