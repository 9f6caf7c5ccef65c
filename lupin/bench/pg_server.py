"""A throwaway PostgreSQL server on loopback, for the history's benchmark and tests.

``initdb`` refuses to run as root, so as root (CI, this machine) the temporary directory is
given to the ``postgres`` user and the server runs as it (``runuser``); as anyone else it runs
as that user. It listens on 127.0.0.1 only, on a free port, with trust authentication for the
role ``lupin`` (a cluster that lives for one run and holds nothing), fsync off (its speed is
then the server's, not this disk's; :data:`DURABLE` turns fsync back on where a figure should
count it). :meth:`stop` stops it and deletes everything.
"""
from __future__ import annotations

import os
import shutil
import socket
import subprocess
import tempfile
import uuid
from pathlib import Path

PG_BIN = Path(os.environ.get("LUPIN_PG_BIN", "/usr/lib/postgresql/15/bin"))


class PostgresUnavailable(RuntimeError):
    """The server could not be started (the reason, with what to install)."""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class PostgresServer:
    def __init__(self, fsync: bool = False, bin_dir: Path = PG_BIN, port: int | None = None):
        """``port``: where to listen (default: a free one), e.g. where a history URL already points."""
        self.bin = Path(bin_dir)
        missing = [b for b in ("initdb", "pg_ctl", "postgres") if not (self.bin / b).is_file()]
        if missing:
            raise PostgresUnavailable(f"PostgreSQL 15 server binaries missing in {self.bin} ({', '.join(missing)}): "
                                      f"install the postgresql-15 package (or set LUPIN_PG_BIN to its bin directory)")
        self.root = Path(tempfile.mkdtemp(prefix="lupin-pg-"))
        self.data, self.port = self.root / "data", port or free_port()
        self.as_user: list[str] = []
        if os.geteuid() == 0:
            if shutil.which("runuser") is None:
                raise PostgresUnavailable("running as root and runuser is missing: initdb refuses to run as root")
            shutil.chown(self.root, "postgres", "postgres")
            os.chmod(self.root, 0o700)
            self.as_user = ["runuser", "-u", "postgres", "--"]
        try:
            self._run("initdb", "-D", str(self.data), "-U", "lupin", "--auth=trust", "-E", "UTF8", "--no-sync")
            options = f"-p {self.port} -k {self.root} -c listen_addresses=127.0.0.1 -c fsync={'on' if fsync else 'off'}"
            self._run("pg_ctl", "-D", str(self.data), "-l", str(self.root / "log"), "-w", "-t", "60", "-o", options,
                      "start")
        except BaseException:
            shutil.rmtree(self.root, ignore_errors=True)
            raise
        self.url = f"postgresql://lupin@127.0.0.1:{self.port}/postgres"

    def _run(self, binary: str, *args: str) -> None:
        done = subprocess.run([*self.as_user, str(self.bin / binary), *args], capture_output=True, text=True,
                              timeout=120, cwd=self.root)
        if done.returncode != 0:
            log = (self.root / "log").read_text()[-2000:] if (self.root / "log").exists() else ""
            raise PostgresUnavailable(f"{binary} failed ({done.returncode}): {done.stderr.strip()[-2000:]} {log}")

    def new_database(self) -> str:
        """A fresh, empty database on the server: its URL."""
        import psycopg

        name = f"t_{uuid.uuid4().hex[:12]}"
        with psycopg.connect(self.url, autocommit=True) as conn:
            conn.execute(f"CREATE DATABASE {name}")
        return self.url.rsplit("/", 1)[0] + "/" + name

    def stop(self) -> None:
        try:
            subprocess.run([*self.as_user, str(self.bin / "pg_ctl"), "-D", str(self.data), "-m", "immediate", "-w",
                            "stop"], capture_output=True, timeout=60, cwd=self.root)
        finally:
            shutil.rmtree(self.root, ignore_errors=True)
