"""Commands over the link: each is a JSON object checked here before the runtime sees it.

A command is a query on ``lupin/<robot>/cmd/<name>`` whose payload is a JSON object: its
arguments plus ``token``. Anything malformed (not JSON, not an object, an unknown command or
argument, a wrong type, a non-finite number) is refused with a one-line reason; so is a command
without the operator token, except engaging the soft e-stop: anyone who sees the robot misbehave
may stop it (releasing it needs the token). A robot in a fleet with certificates has no token
(``token`` None): the router's access control already lets only consoles reach its commands.
"""
from __future__ import annotations

import hmac
import json
from typing import Annotated, Any, Literal, Optional

from pydantic import BaseModel, ConfigDict, Field, ValidationError


class CommandRefused(Exception):
    """The reason a command was not carried out (sent back to the client)."""


class _Args(BaseModel):
    model_config = ConfigDict(extra="forbid", strict=True, allow_inf_nan=False)
    token: str = ""


class EStopArgs(_Args):
    engaged: bool


class NoArgs(_Args):
    pass


AisleId = Annotated[str, Field(pattern=r"^[0-9]+$")]
Vertex = Annotated[list[float], Field(min_length=2, max_length=2)]
"""x, y, m."""


class MissionStartArgs(_Args):
    mission: Optional[dict[str, Any]] = None
    """A mission as spec/mission.md's mapping; none: every pot of the world."""
    aisles: Optional[dict[AisleId, list[Vertex]]] = None
    """A fleet's aisles, an outline each in the mission's frame (``fleet.aisles.outlines``; the
    id a JSON key), from the dispatcher: the patrol asks for them before it drives
    (``mission.patrol.aisle_gate``); none: no aisle is asked for, as a robot alone."""
    others: Optional[list[Vertex]] = None
    """The fleet mission's other pots, x, y in the mission's frame, from the dispatcher: pots
    other robots inspect are pots all the same, and the person tracker knows them as such
    (``mission.runtime.people``); none: the mission's own pots are all it knows."""


class TeleopArgs(_Args):
    vx: float = Field(0.0, ge=-1.0, le=1.0)
    vy: float = Field(0.0, ge=-1.0, le=1.0)
    wz: float = Field(0.0, ge=-3.0, le=3.0)
    source: Literal["manual", "joy"] = "manual"
    """The mux source: ``manual`` (the console's keys) or ``joy`` (its gamepad, the seed's
    dead-man source: priority 100, 0.3 s)."""


class ArmPresetArgs(_Args):
    name: str = Field(min_length=1, max_length=40)


class GripperArgs(_Args):
    action: Literal["open", "close", "angle"]
    deg: Optional[float] = Field(None, ge=-30.0, le=30.0)


class SnapshotArgs(_Args):
    camera: Literal["front", "wrist"] = "front"


class ArmCalibrateArgs(_Args):
    action: Literal["start", "commit", "cancel", "status"]


class HistoryArgs(_Args):
    query: Literal["patrols", "pot", "changes", "pests"]
    pot: Optional[str] = Field(None, min_length=1, max_length=64)
    mission: Optional[str] = Field(None, min_length=1, max_length=200)
    last: int = Field(10, ge=1, le=1000)
    limit: int = Field(20, ge=1, le=1000)


SCHEMAS: dict[str, type[_Args]] = {
    "estop": EStopArgs, "resume": NoArgs, "pause": NoArgs, "mission_start": MissionStartArgs,
    "mission_abort": NoArgs, "teleop": TeleopArgs, "arm_preset": ArmPresetArgs, "gripper": GripperArgs,
    "clear_map": NoArgs, "heal": NoArgs, "snapshot": SnapshotArgs, "history": HistoryArgs,
    "arm_calibrate": ArmCalibrateArgs, "report": NoArgs,
}
MAX_PAYLOAD = 64 * 1024
"""Bytes: a mission of a few hundred pots fits; anything bigger is not a command."""


def parse_command(name: str, payload: bytes, token: str | None) -> _Args:
    """The checked arguments of command ``name``; ``CommandRefused`` says what is wrong."""
    schema = SCHEMAS.get(name)
    if schema is None:
        raise CommandRefused(f"unknown command {name[:40]!r} (known: {', '.join(SCHEMAS)})")
    if len(payload) > MAX_PAYLOAD:
        raise CommandRefused(f"{name}: payload of {len(payload)} bytes is over {MAX_PAYLOAD}")
    try:
        data = json.loads(payload.decode("utf-8")) if payload else {}
    except (UnicodeDecodeError, json.JSONDecodeError, RecursionError):
        raise CommandRefused(f"{name}: payload is not a JSON object") from None
    if not isinstance(data, dict):
        raise CommandRefused(f"{name}: payload must be a JSON object, got {type(data).__name__}")
    try:
        args = schema.model_validate(data)
    except ValidationError as exc:
        e = exc.errors()[0]
        # a key is whatever the client sent: escaped and cut short, so the reply stays one line
        where = ".".join(str(p) for p in e["loc"]).encode("unicode_escape").decode()[:40] or "payload"
        raise CommandRefused(f"{name}: {where}: {e['msg']}") from None
    open_to_all = (name == "estop" and args.engaged) or token is None
    if not open_to_all and not token:
        raise CommandRefused(f"{name}: refused: the runtime has no operator token set")
    if not open_to_all and not hmac.compare_digest(args.token.encode(), token.encode()):
        raise CommandRefused(f"{name}: refused: missing or wrong operator token")
    return args
