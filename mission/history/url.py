"""What a ``--history`` value names (spec/history.md "Where it lives").

- ``none`` (any case): no history at all;
- ``postgresql://user@host/db`` (also ``postgres://`` and ``postgresql+psycopg://``): a server,
  reached with psycopg 3;
- ``sqlite:///PATH``: a SQLite file; ``sqlite://`` alone (in memory) is refused, a history
  that vanishes with the process is no history;
- anything else without ``://``: a file path, SQLite.

A password in a URL is never printed (:attr:`HistoryTarget.shown`).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from sqlalchemy.engine import URL, make_url
from sqlalchemy.exc import ArgumentError

from hw.errors import InputError

NONE = "none"
POSTGRES_SCHEMES = ("postgresql", "postgres", "postgresql+psycopg")


@dataclass(frozen=True)
class HistoryTarget:
    url: URL
    """The SQLAlchemy URL the engine is made from."""
    shown: str
    """How messages name it: the path, or the URL with its password hidden."""
    path: Path | None = None
    """The SQLite file; None for a server."""

    @property
    def is_sqlite(self) -> bool:
        return self.path is not None


def parse_history_url(text: str, option: str = "--history") -> HistoryTarget | None:
    """The database ``text`` names, or None for ``none``; InputError naming ``option`` else."""
    text = text.strip()
    if text.lower() == NONE:
        return None
    if not text:
        raise InputError(f"{option}: empty (give a file path, sqlite:///PATH, postgresql://user@host/db or none)")
    if "://" not in text:
        return _sqlite(Path(text).expanduser())
    scheme = text.split("://", 1)[0].lower()
    try:
        url = make_url(text)
    except (ArgumentError, ValueError):  # ValueError: a port that is not a number
        raise InputError(f"{option} {text}: not a database URL") from None
    if scheme == "sqlite":
        if not url.database:
            raise InputError(f"{option} {text}: give a file (sqlite:///PATH); an in-memory history is lost at exit")
        return _sqlite(Path(url.database).expanduser())
    if scheme in POSTGRES_SCHEMES:
        if not url.database:
            raise InputError(f"{option} {url.render_as_string(hide_password=True)}: name the database "
                             f"(postgresql://user@host/DB)")
        url = url.set(drivername="postgresql+psycopg")
        shown = url.render_as_string(hide_password=True).replace("postgresql+psycopg", "postgresql", 1)
        return HistoryTarget(url, shown)
    raise InputError(f"{option} {scheme}://...: not a history database (give a file path, sqlite:///PATH, "
                     f"postgresql://user@host/db or none)")


def _sqlite(path: Path) -> HistoryTarget:
    return HistoryTarget(URL.create("sqlite", database=str(path)), str(path), path)
