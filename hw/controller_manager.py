"""Lifecycle of the five ros2_control-style controllers, and the boot race that breaks it.

Seed ("the boot controller-heal"): on a cold boot the vendor stack raced three spawners against
the YAML auto-load, and a controller could end up *missing* (its spawner died, never loaded),
*unconfigured* (loaded, configure never ran) or *inactive* (configured, never switched on).
The base only drives when its controllers are active, so a broken boot looked like a dead robot.
Lupin healed it with a boot one-shot that walks each of the five controllers to *active*.

Here the same state machine is explicit:

    missing --load--> unconfigured --configure--> inactive --activate--> active
                                                  inactive <--deactivate-- active

Illegal transitions raise ``ControllerTransitionError`` naming the controller, its state and the
move attempted, which is what a heal log needs. ``force`` sets a state directly: the sim uses it
to bring a controller up broken (the events file's ``controller_race``), not the heal.
"""
from __future__ import annotations

from enum import Enum
from typing import Callable, Iterable, Mapping


class ControllerState(str, Enum):
    MISSING = "missing"
    UNCONFIGURED = "unconfigured"
    INACTIVE = "inactive"
    ACTIVE = "active"


class ControllerTransitionError(RuntimeError):
    """A lifecycle call that is not legal from the controller's current state."""


#: action -> (required state, resulting state)
_TRANSITIONS: dict[str, tuple[ControllerState, ControllerState]] = {
    "load": (ControllerState.MISSING, ControllerState.UNCONFIGURED),
    "configure": (ControllerState.UNCONFIGURED, ControllerState.INACTIVE),
    "activate": (ControllerState.INACTIVE, ControllerState.ACTIVE),
    "deactivate": (ControllerState.ACTIVE, ControllerState.INACTIVE),
}

#: The legal path to active from each state (what a heal does, in order).
_PATH_TO_ACTIVE: dict[ControllerState, tuple[str, ...]] = {
    ControllerState.MISSING: ("load", "configure", "activate"),
    ControllerState.UNCONFIGURED: ("configure", "activate"),
    ControllerState.INACTIVE: ("activate",),
    ControllerState.ACTIVE: (),
}

ChangeCallback = Callable[[str, ControllerState, ControllerState], None]


class ControllerManager:
    def __init__(
        self,
        names: Iterable[str],
        initial: ControllerState | str | Mapping[str, ControllerState | str] = ControllerState.ACTIVE,
    ):
        """All controllers start ``initial`` (active unless told otherwise); a mapping sets
        some controllers' start state and leaves the rest active."""
        names = tuple(names)
        if len(set(names)) != len(names):
            raise ValueError(f"duplicate controller names in {names}")
        if isinstance(initial, Mapping):
            unknown = set(initial) - set(names)
            if unknown:
                raise KeyError(f"initial state given for unknown controllers: {sorted(unknown)}")
            self._states = {n: ControllerState(initial.get(n, ControllerState.ACTIVE)) for n in names}
        else:
            self._states = {n: ControllerState(initial) for n in names}
        self._subscribers: list[ChangeCallback] = []

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self._states)

    def _check(self, name: str) -> ControllerState:
        try:
            return self._states[name]
        except KeyError:
            raise KeyError(f"unknown controller {name!r} (known: {', '.join(self._states)})") from None

    def state(self, name: str) -> ControllerState:
        return self._check(name)

    def states(self) -> dict[str, ControllerState]:
        return dict(self._states)

    def is_active(self, name: str) -> bool:
        return self._check(name) is ControllerState.ACTIVE

    def all_active(self) -> bool:
        return all(s is ControllerState.ACTIVE for s in self._states.values())

    def subscribe(self, callback: ChangeCallback) -> None:
        """``callback(name, old, new)`` on every state change."""
        self._subscribers.append(callback)

    def _set(self, name: str, new: ControllerState) -> None:
        old = self._states[name]
        if old is new:
            return
        self._states[name] = new
        for callback in self._subscribers:
            callback(name, old, new)

    def _transition(self, name: str, action: str) -> None:
        current = self._check(name)
        required, result = _TRANSITIONS[action]
        if current is not required:
            raise ControllerTransitionError(
                f"cannot {action} controller {name!r}: it is {current.value}, "
                f"{action} needs {required.value}"
            )
        self._set(name, result)

    def load(self, name: str) -> None:
        self._transition(name, "load")

    def configure(self, name: str) -> None:
        self._transition(name, "configure")

    def activate(self, name: str) -> None:
        self._transition(name, "activate")

    def deactivate(self, name: str) -> None:
        self._transition(name, "deactivate")

    def force(self, name: str, state: ControllerState | str) -> None:
        """Set a state directly, bypassing the lifecycle (sim fault injection only)."""
        self._check(name)
        self._set(name, ControllerState(state))

    def heal(self, name: str) -> list[str]:
        """Walk ``name`` along the legal path to active; returns the actions taken."""
        actions = list(_PATH_TO_ACTIVE[self._check(name)])
        for action in actions:
            self._transition(name, action)
        return actions
