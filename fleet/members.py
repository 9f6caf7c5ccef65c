"""Who is in the fleet: which certificate names are robots, which consoles, and the dispatcher.

Access control tells members apart by their certificate's common name only, so the router
needs the roles beside the names: ``lupin fleet certs`` writes them to ``DIR/fleet.yaml`` (public,
no keys) next to the certificates, and ``lupin router --certs DIR`` builds its rules from it.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import yaml

from hw.errors import InputError

MEMBERS_FILE = "fleet.yaml"
"""Beside the certificates: which names are robots and which consoles (public: no keys)."""


@dataclass(frozen=True)
class Members:
    robots: tuple[str, ...]
    consoles: tuple[str, ...]
    dispatcher: str | None = "dispatcher"


def read_members(certs: Path) -> Members:
    path = certs / MEMBERS_FILE
    try:
        data = yaml.safe_load(path.read_text()) or {}
    except OSError as exc:
        raise InputError(f"--certs {certs}: no {MEMBERS_FILE} there ({exc.strerror}); make the fleet with "
                         "`lupin fleet certs`") from None
    except yaml.YAMLError as exc:
        raise InputError(f"{path}: not YAML: {str(exc).splitlines()[0]}") from None
    if not isinstance(data, dict) or not all(isinstance(data.get(k, []), list) for k in ("robots", "consoles")):
        raise InputError(f"{path}: expected robots: [names] and consoles: [names]")
    return Members(tuple(map(str, data.get("robots", []))), tuple(map(str, data.get("consoles", []))),
                   data.get("dispatcher", "dispatcher"))


def write_members(certs: Path, members: Members) -> None:
    (certs / MEMBERS_FILE).write_text(yaml.safe_dump(
        {"robots": list(members.robots), "consoles": list(members.consoles), "dispatcher": members.dispatcher},
        sort_keys=False))
