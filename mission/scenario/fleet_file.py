"""A scenario file's fleet part (issue 34, "Judging"): ``robots: N``, events addressed to a
robot, ``expect.fleet``.

A scenario with ``robots: N`` is run by the real fleet (``fleet.scenario_runner``): N
robots at the world's first N ``spawns`` (``r1``..``rN``), a router, and the dispatcher splitting
the mission. Each event may say which robot it happens to (``robot: r2``; ``r1`` when left out)
and is played on that robot's runtime, ``at`` counted from that robot's patrol start, as for one
robot. What this module checks, before anything runs, each problem one line naming the file, the
entry and the field (exit 2)::

    two.yaml: field 'robots': 3 robots but the world 'generated-3x4-seed1' has 2 spawns (spawns: in the world file)
    two.yaml: events[1] (do estop): field 'robot': no robot 'r3' in this fleet (r1, r2)
    two.yaml: expect: field 'pots': a fleet scenario judges the pots in expect.fleet.pots

Expectations of one robot's patrol that a fleet has no single answer to (its pots, anomalies,
home, arm, report files, people) are refused in a fleet scenario rather than judged on one robot
only; ``outcome``, ``estop`` and ``effects`` are judged on every robot (each press and event on
the robot it was addressed to). ``runtime_crash`` and ``history_down`` are refused too: a fleet
robot's service is not restarted by the scenario, and its runs record no history, so neither
event could show its effect.
"""
from __future__ import annotations

from typing import Any

from hw.errors import InputError

NOT_IN_A_FLEET = ("runtime_crash", "history_down")
"""Event actions a fleet scenario cannot show the effect of (see the module doc)."""
ONE_ROBOT_ONLY = {"pots": "judges the pots in expect.fleet.pots", "anomalies": "does not judge anomalies yet",
                  "no_anomalies": "does not judge anomalies yet", "home": "does not judge home yet",
                  "arm": "does not judge the arm yet", "report_files": "does not judge report files yet",
                  "people": "does not judge walkers yet"}
"""Expectations refused in a fleet scenario, and why."""


def robot_names(robots: int) -> list[str]:
    """A fleet scenario's robots, as ``lupin fleet sim`` names them."""
    return [f"r{k + 1}" for k in range(robots)]


def check_fleet_file(data: dict, spec, spawns: int, world_name: str, source: str) -> None:
    """``spec`` (the validated scenario) against its fleet rules; InputError naming what and where."""
    problems = []
    if spec.robots is None:
        if spec.expect.fleet is not None:
            problems.append("expect: field 'fleet': only in a fleet scenario (give robots: N)")
    else:
        if spec.robots > spawns:
            problems.append(f"field 'robots': {spec.robots} robots but the world {world_name!r} has {spawns} "
                            f"spawn{'s' if spawns != 1 else ''} (spawns: in the world file)")
        given = data.get("expect") or {}
        problems += [f"expect: field '{k}': a fleet scenario {why}" for k, why in ONE_ROBOT_ONLY.items() if k in given]
    if problems:
        raise InputError("\n".join(f"{source}: {p}" for p in problems))


def addressed(events: Any, robots: int | None, source: str) -> tuple[Any, list[str]]:
    """The events without their ``robot`` keys, and the robot each is addressed to (``r1``
    when left out). A single-robot scenario's events are left as they are (a ``robot`` key is
    then the events file's unknown field)."""
    if robots is None or not isinstance(events, list):
        return events, []
    names, plain, to, problems = robot_names(robots), [], [], []
    for i, e in enumerate(events):
        if not isinstance(e, dict):
            plain.append(e)
            to.append("r1")
            continue
        e = dict(e)
        who = e.pop("robot", "r1")
        entry = f"events[{i}]" + (f" (do {e['do']})" if isinstance(e.get("do"), str) else "")
        if who not in names:
            problems.append(f"{entry}: field 'robot': no robot {who!r} in this fleet ({', '.join(names)})")
        if e.get("do") in NOT_IN_A_FLEET:
            problems.append(f"{entry}: field 'do': {e['do']} cannot show its effect in a fleet scenario")
        plain.append(e)
        to.append(who)
    if problems:
        raise InputError("\n".join(f"{source}: {p}" for p in problems))
    return plain, to


def by_robot(events: list, to: list[str], robots: int, parse) -> dict[str, list]:
    """Each robot's events, checked and sorted by ``parse`` (the events file's) like one robot's."""
    return {r: parse([e for e, w in zip(events, to) if w == r]) for r in robot_names(robots)}
