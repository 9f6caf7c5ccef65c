"""Signing in to the dashboard (spec/web.md): it is on the farm network, so it asks for a
password unless started with ``--open`` on 127.0.0.1.

The password is kept as a salted scrypt hash (``hashlib.scrypt``, n=2**14, r=8, p=1: RFC 7914's
interactive figures, ~50 ms and 16 MiB a try, so a stolen file is slow to guess from) in
``web-password`` in the runtime's state directory (``runtime.state_dir``; else the robot's
default, ``$XDG_STATE_HOME/lupin``), written by ``lupin web --set-password``, readable by its
owner only. A sign-in makes a random session token kept in the server's memory (a restart signs
everyone out) and sent as an HttpOnly, SameSite=Strict cookie.
"""
from __future__ import annotations

import hashlib
import hmac
import os
import secrets
import time
from pathlib import Path
from typing import Callable

from hw.errors import InputError

FILE = "web-password"
N, R, P, SALT_BYTES = 2 ** 14, 8, 1, 16
MIN_LENGTH = 8
"""Characters: NIST SP 800-63B's minimum for a password a person chooses."""
SESSION_S = 12 * 3600.0
"""A sign-in lasts a working day."""
COOKIE = "lupin_web"


def hash_password(password: str, salt: bytes | None = None) -> str:
    """``scrypt$n$r$p$salt$hash`` (hex) of ``password``."""
    salt = salt or os.urandom(SALT_BYTES)
    digest = hashlib.scrypt(password.encode(), salt=salt, n=N, r=R, p=P, dklen=32)
    return f"scrypt${N}${R}${P}${salt.hex()}${digest.hex()}"


def verify(password: str, stored: str) -> bool:
    try:
        kind, n, r, p, salt, digest = stored.strip().split("$")
        if kind != "scrypt":
            return False
        got = hashlib.scrypt(password.encode(), salt=bytes.fromhex(salt), n=int(n), r=int(r), p=int(p),
                             dklen=len(bytes.fromhex(digest)))
    except (ValueError, MemoryError):
        return False
    return hmac.compare_digest(got.hex(), digest)


def set_password(path: Path, password: str) -> None:
    """Store ``password``'s hash in ``path`` (owner-only, replaced atomically)."""
    if len(password) < MIN_LENGTH:
        raise InputError(f"--set-password: too short ({len(password)} characters; at least {MIN_LENGTH})")
    tmp = path.with_name(f".{path.name}.tmp")
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
        with os.fdopen(fd, "w") as f:
            f.write(hash_password(password) + "\n")
        os.replace(tmp, path)
    except OSError as exc:
        raise InputError(f"--set-password: cannot write {path}: {exc.strerror or exc}") from None


def stored_hash(path: Path) -> str | None:
    """The stored hash, or None when no password was set."""
    try:
        text = path.read_text().strip()
    except FileNotFoundError:
        return None
    except OSError as exc:
        raise InputError(f"{path}: cannot read the dashboard's password: {exc.strerror or exc}") from None
    return text or None


class Sessions:
    """Who is signed in: random tokens with their expiry, in memory."""

    def __init__(self, stored: str | None, clock: Callable[[], float] = time.monotonic):
        self.stored, self.clock = stored, clock
        self._tokens: dict[str, float] = {}

    @property
    def open(self) -> bool:
        """No password asked (``--open``)."""
        return self.stored is None

    def sign_in(self, password: str) -> str | None:
        """A new session's token, or None for a wrong password."""
        if self.stored is None or not verify(password, self.stored):
            return None
        token = secrets.token_urlsafe(32)
        self._tokens[token] = self.clock() + SESSION_S
        return token

    def signed_in(self, token: str | None) -> bool:
        if self.open:
            return True
        until = self._tokens.get(token or "")
        if until is None:
            return False
        if until < self.clock():
            del self._tokens[token]
            return False
        return True

    def sign_out(self, token: str | None) -> None:
        self._tokens.pop(token or "", None)
