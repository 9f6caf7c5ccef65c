"""The patrol history (spec/history.md): every patrol recorded in a database, and the grower's
questions asked of it.

One interface for everyone who reads or writes it -- the patrol, ``lupin serve``, the
``lupin history`` command, the console: :class:`~mission.history.store.History`, opened with
:func:`~mission.history.store.open_history` from a ``--history`` value or ``history.url``.

- ``url``: what a ``--history`` value names (a SQLite file by default, a PostgreSQL server, none);
- ``schema`` and ``migrations``: the tables, and the numbered steps that build and upgrade them;
- ``store``: open, write a patrol, ask; ``queries``: the questions as SQL;
- ``recorder``: a patrol written as it goes, off the robot's thread;
- ``changes``: what changed at a pot between two patrols;
- ``rescout``: the directed re-scouting mission; ``pest_map``: the pest-pressure picture;
  ``export``: CSV files for spreadsheets.
"""
