"""The boot heal: bring the five controllers to active, then park the arm at ``home``.

Seed ("The boot controller-heal", lupin_hmi/auto_home.py): on a cold boot the vendor stack
raced three spawners against the YAML auto-load, and a controller could come up *missing*,
*unconfigured* or *inactive*. A boot one-shot walked each of the five to active (load,
configure, activate only what needs it) and then homed the arm, the measured minimum-gravity
pose, because the arm must never stay parked extended.

The result is a deliberate tri-state, and the third value is the load-bearing one:

- ``True``: all five reached active; the arm is homed. Exit 0.
- ``False``: the states were read, but not every controller ended active. Exit 1 (systemd
  retries).
- ``None``: the states could not be read within the poll budget, so what is loaded is
  unknown. *No* load or switch is issued: blind loads and switches against an unknown stack
  are exactly what caused the 2026-05-27 retry storm (every load "already loaded", every switch
  failed, Restart=on-failure spun). Exit 0 on purpose, with a loud message; the operator
  re-triggers the heal.

``LUPIN_AUTO_HOME=false`` skips all of it (exit 0). The state query is a callable that may
time out or return garbage (``list_states``); by default it is the manager's own ``states``.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Callable, Mapping

from arm.controller import ArmUnavailable
from arm.presets import preset
from hw.controller_manager import ControllerManager, ControllerState, ControllerTransitionError
from hw.interfaces import Clock, DeviceError

log = logging.getLogger("lupin.heal")

POLL_BUDGET = 10.0
"""Seconds to get a valid list_controllers answer before giving up (the seed's poll budget;
10 s is Lupin's number: a healthy stack answers in well under a second)."""
POLL_INTERVAL = 0.5
"""Seconds between state queries while the stack does not answer."""
HOME_TIMEOUT = 15.0
"""Seconds allowed for the park at ``home`` (a full-span move at 0.6 rad/s takes ~3 s)."""
AUTO_HOME_ENV = "LUPIN_AUTO_HOME"

ListStates = Callable[[], Mapping[str, ControllerState | str] | None]

#: What each state needs on the way to active (seed: load, configure, activate only what needs it).
ACTIONS: dict[ControllerState, tuple[str, ...]] = {
    ControllerState.MISSING: ("load", "configure", "activate"),
    ControllerState.UNCONFIGURED: ("configure", "activate"),
    ControllerState.INACTIVE: ("activate",),
    ControllerState.ACTIVE: (),
}


@dataclass
class HealReport:
    healed: bool | None
    """The seed's tri-state; None also when the heal was skipped (see ``skipped``)."""
    before: dict[str, ControllerState] = field(default_factory=dict)
    actions: list[tuple[str, str]] = field(default_factory=list)
    after: dict[str, ControllerState] = field(default_factory=dict)
    homed: bool = False
    skipped: bool = False
    message: str = ""

    @property
    def exit_code(self) -> int:
        """0 healed and homed, 1 a controller not active (or the park failed), 0 unreadable."""
        if self.skipped or self.healed is None:
            return 0
        return 0 if (self.healed and self.homed) else 1


def auto_home_enabled(env: Mapping[str, str]) -> bool:
    return env.get(AUTO_HOME_ENV, "true").strip().lower() not in ("false", "0", "no", "off")


def read_states(list_states: ListStates, names: tuple[str, ...], clock: Clock,
                budget: float = POLL_BUDGET, interval: float = POLL_INTERVAL) -> dict[str, ControllerState] | None:
    """Poll ``list_states`` until it answers with valid data or the budget runs out (None).
    A controller the answer does not list is missing (list_controllers only lists loaded ones)."""
    deadline = clock.now() + budget
    while True:
        try:
            raw = list_states()
            if isinstance(raw, Mapping):
                return {n: ControllerState(raw.get(n, ControllerState.MISSING)) for n in names}
            log.warning("controller states: no valid answer (%r)", raw)
        except (TimeoutError, DeviceError, ValueError, TypeError) as exc:
            log.warning("controller states unreadable: %s", exc)
        if clock.now() + interval > deadline:
            return None
        clock.wait_until(clock.now() + interval)


def heal_controllers(manager: ControllerManager, names: tuple[str, ...], clock: Clock,
                     list_states: ListStates | None = None, budget: float = POLL_BUDGET) -> HealReport:
    """Walk each controller to active; the tri-state says how it went."""
    list_states = list_states or manager.states
    before = read_states(list_states, names, clock, budget)
    if before is None:
        return HealReport(None, message=(
            f"CONTROLLER STATES UNREADABLE within {budget:g} s: issued NO load or switch (an unknown stack "
            "is how the retry storm started); re-run `lupin heal` once the controller manager answers"))
    report = HealReport(False, before=before)
    for name in names:
        for action in ACTIONS[before[name]]:
            try:
                getattr(manager, action)(name)
                report.actions.append((name, action))
            except (ControllerTransitionError, KeyError) as exc:
                log.error("heal %s: %s failed: %s", name, action, exc)
                break
    after = read_states(list_states, names, clock, budget)
    if after is None:
        report.healed, report.message = None, "controller states unreadable after the heal: state unknown"
        return report
    report.after = after
    report.healed = all(s is ControllerState.ACTIVE for s in after.values())
    if not report.healed:
        report.message = "not active: " + ", ".join(f"{n} {s.value}" for n, s in after.items() if s is not ControllerState.ACTIVE)
    return report


def park_home(robot, timeout: float = HOME_TIMEOUT) -> bool:
    """Run the robot until the arm has a joint state, send it ``home`` and wait for it there."""
    arm, scheduler = robot.arm, robot.scheduler
    t_end = scheduler.clock.now() + timeout
    while not arm.interface.pinned and scheduler.clock.now() < t_end:
        scheduler.run_for(0.1)
    try:
        arm.preset("home")
    except ArmUnavailable as exc:
        log.error("arm not parked: %s", exc)
        return False
    scheduler.run_for(0.2)
    while scheduler.clock.now() < t_end and arm.available:
        if not arm.moving and arm.at(preset("home")):
            return True
        scheduler.run_for(0.1)
    return False


def boot_heal(robot, env: Mapping[str, str], list_states: ListStates | None = None,
              budget: float = POLL_BUDGET) -> HealReport:
    """The whole one-shot on an assembled robot (controllers, arm, scheduler on its clock)."""
    if not auto_home_enabled(env):
        return HealReport(None, skipped=True, message=f"{AUTO_HOME_ENV}=false: heal and home skipped")
    names = tuple(robot.config.hw.controllers)
    report = heal_controllers(robot.controllers, names, robot.scheduler.clock, list_states, budget)
    if report.healed:
        report.homed = park_home(robot)
        report.message = "all controllers active; arm parked at home" if report.homed else \
            f"all controllers active, but the arm did not reach home ({robot.arm.fault or 'timed out'})"
    return report
