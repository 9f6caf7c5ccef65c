"""Folding py_trees' own rendering (a small patrol-shaped tree ticked for real): the running
branch open, its siblings one line each, a selector's ``[o]`` marker and bracketed feedback read
right, ANSI colours ignored, and under a hold the branch that ran last kept open."""
from __future__ import annotations

import py_trees
from py_trees.behaviours import Failure, Running, Success
from py_trees.common import OneShotPolicy, ParallelPolicy
from py_trees.composites import Parallel, Selector, Sequence
from py_trees.decorators import OneShot

from behaviours.guard import Hold
from tui.widgets.mission_tree import TreeFolder


def pot(i: int, running: bool) -> OneShot:
    pid = f"P{i:02d}"
    step = Running if running else Success
    inspect = Sequence(f"inspect {pid}", memory=True, children=[Success(f"approach {pid}"), step(f"front camera {pid}"),
                                                                Success(f"record {pid}")])
    return OneShot(pid, Selector(f"visit {pid}", memory=True, children=[inspect, Success(f"{pid} failed")]),
                   OneShotPolicy.ON_COMPLETION)


def patrol(paused: list):
    pots = Sequence("pots", memory=True, children=[pot(i, i == 3) for i in range(1, 6)])
    body = Sequence("patrol", memory=True, children=[
        Parallel("pots and tags", ParallelPolicy.SuccessOnSelected([pots]), children=[pots, Running("watch tags")]),
        Success("finish")])
    battery = Sequence("battery low", memory=True, children=[Failure("battery low?"), Success("go home")])
    mission = Selector("mission", memory=False, children=[battery, body])
    return Hold("Lupin patrol", Hold("operator pause", mission, lambda: paused[0]), lambda: None)


def render(root, colour: bool = False) -> str:
    text = py_trees.display.unicode_tree(root, show_status=True)
    return text.replace("[*]", "[\x1b[34m*\x1b[0m]") if colour else text


def test_the_running_branch_is_open_and_the_rest_one_line_each():
    paused = [None]
    root = patrol(paused)
    for _ in range(3):
        root.tick_once()
    whole = render(root)
    assert "[o] mission [*]" in whole and "--> battery low? [✕]" in whole
    lines, focus = TreeFolder().lines(whole)
    text = "\n".join(lines)
    assert "front camera P03 [*]" in lines[focus]
    assert "[o] mission [*]" in text and "{-} battery low [✕]" in text and "battery low?" not in text
    for i in (1, 2, 4, 5):
        assert f"-^- P{i:02d} [" in text and f"visit P{i:02d}" not in text
    assert "visit P03 [*]" in text and "record P03 [-]" in text  # the steps of the pot in progress, all
    assert len(lines) < len(whole.splitlines())


def test_colour_codes_are_read_and_kept_for_the_panel():
    paused = [None]
    root = patrol(paused)
    root.tick_once()
    lines, focus = TreeFolder().lines(render(root, colour=True))
    assert "front camera P03 [\x1b[34m*\x1b[0m]" in lines[focus]
    assert not any("battery low?" in line for line in lines)


def test_a_hold_keeps_the_branch_that_ran_last_open():
    paused = [None]
    root = patrol(paused)
    folder = TreeFolder()
    root.tick_once()
    folder.lines(render(root))
    paused[0] = "paused by the operator"
    root.tick_once()
    held = render(root)
    assert "front camera P03 [-]" in held and "[*]" not in held.split("operator pause", 1)[1].split("\n", 1)[1]
    lines, focus = folder.lines(held)
    text = "\n".join(lines)
    assert "front camera P03 [-]" in lines[focus] and "visit P02" not in text and "battery low?" not in text
    fresh, _ = TreeFolder().lines(held)  # a console that never saw it run: the whole tree
    assert fresh == held.splitlines()
