"""The map renderer without a terminal: things are drawn where they are, thin walls survive
downsampling, the window fits what is known, and the strips are the panel's size."""
from __future__ import annotations

import math

import numpy as np

from mission.link.view import GridView, PotView, RobotView
from tests.tui.fakes import idle_view, patrolling_view
from tui.widgets.map_panel import (ANOMALY, FREE, GOAL, HEADING, OCCUPIED, PLAN, POT_COLOURS, ROBOT, UNKNOWN,
                                   map_pixels, render_map)


def tiny_view(yaw: float = 0.0) -> RobotView:
    """A 2 x 1 m walled room (0.05 m cells, origin 0, 0), the robot at its left, a plan to the
    right, a goal at the plan's end and two pots."""
    g = np.zeros((20, 40), np.int8)
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = 100
    return RobotView(pose=(0.4, 0.5, yaw), grid=GridView(g, 0.05, 0.0, 0.0),
                     plan=np.array([[0.4, 0.5], [1.0, 0.5], [1.6, 0.5]]), goal=(1.6, 0.5, 0.0),
                     pots=[PotView("A", 1.5, 0.2, "inspected"), PotView("B", 1.0, 0.8, "failed"),
                           PotView("C", 0.4, 0.85, "inspected", anomalies=["bug"])])


def colour(cv, x: float, y: float) -> tuple[int, int, int]:
    c, r = cv.to_pixel(x, y)
    return tuple(int(k) for k in cv.rgb[int(r), int(c)])


def test_robot_heading_plan_goal_and_pots_are_where_they_are():
    cv = map_pixels(tiny_view(), 60, 20)
    assert colour(cv, 0.4, 0.5) in (ROBOT, HEADING)
    assert colour(cv, 0.4 - 0.1, 0.5 + 0.1) == ROBOT  # the footprint around it
    assert colour(cv, 0.85, 0.5) == PLAN  # beyond the heading line (0.35 m), on the plan
    assert colour(cv, 1.0, 0.5) == PLAN
    assert colour(cv, 1.6, 0.5) == GOAL
    assert colour(cv, 1.5, 0.2) == POT_COLOURS["inspected"]
    assert colour(cv, 1.0, 0.8) == POT_COLOURS["failed"]
    assert colour(cv, 0.4, 0.85) == ANOMALY
    assert colour(cv, 1.2, 0.3) == FREE and colour(cv, 0.01, 0.5) == OCCUPIED


def test_the_heading_line_points_along_the_yaw():
    up = map_pixels(tiny_view(yaw=math.pi / 2), 60, 20)
    assert colour(up, 0.4, 0.5 + 0.25) == HEADING  # ahead of the robot, which faces +y
    assert colour(up, 0.4 + 0.25, 0.5) != HEADING
    east = map_pixels(tiny_view(), 60, 20)
    assert colour(east, 0.4 + 0.25, 0.5) == HEADING


def test_the_strips_carry_the_same_picture():
    v = tiny_view()
    cv, strips = map_pixels(v, 60, 20), render_map(v, 60, 20)
    assert len(strips) == 20 and all(s.cell_length == 60 for s in strips)
    c, r = cv.to_pixel(1.5, 0.2)  # pot A, in character (c, r // 2): top pixel fg, bottom pixel bg
    col = 0
    for seg in strips[int(r) // 2]:
        if col <= c < col + len(seg.text):
            style = seg.style
            break
        col += len(seg.text)
    drawn = (style.color if r % 2 == 0 else style.bgcolor).triplet
    assert tuple(drawn) == POT_COLOURS["inspected"]


def test_a_one_cell_wall_and_a_lone_box_survive_downsampling():
    """400 x 400 cells (20 m) into 40 x 20 pixels: 10 cells per pixel. Nearest-cell sampling
    would keep one cell in ten; the max-pool keeps every occupied cell visible."""
    g = np.zeros((400, 400), np.int8)
    g[201, :] = 100  # a wall one cell thick, across
    g[57, 333] = 100  # one occupied cell
    cv = map_pixels(RobotView(pose=(1.0, 1.0, 0.0), grid=GridView(g, 0.05, 0.0, 0.0)), 40, 10)
    wall_row = int(cv.to_pixel(0.0, 201 * 0.05 + 0.025)[1])
    walled = np.all(cv.rgb[wall_row, :, :] == OCCUPIED, axis=-1)
    c, r = cv.to_pixel(333 * 0.05 + 0.025, 57 * 0.05 + 0.025)
    on_grid = (np.arange(cv.w) >= cv.to_pixel(0.0, 0)[0]) & (np.arange(cv.w) < cv.to_pixel(20.0, 0)[0])
    assert walled[on_grid].all()
    assert tuple(cv.rgb[r, c]) == OCCUPIED


def test_the_window_fits_the_known_part_of_a_big_grid():
    g = np.full((480, 480), -1, np.int8)  # a 24 x 24 m grid, mostly unknown
    g[100:160, 100:200] = 0  # 5 x 3 m explored: x -7 .. -2, y -7 .. -4
    cv = map_pixels(RobotView(pose=(-4.5, -5.5, 0.0), grid=GridView(g, 0.05, -12.0, -12.0)), 80, 30)
    known = np.any(cv.rgb != UNKNOWN, axis=-1).mean()
    assert known > 0.4  # a 24 m window would leave the 5 x 3 m room about 2 % of the pixels


def test_every_state_draws_at_any_size():
    for view in (RobotView(), idle_view(), patrolling_view()):
        for w, h in ((1, 1), (7, 3), (80, 30)):
            strips = render_map(view, w, h)
            assert len(strips) == max(h, 2) and all(s.cell_length == max(w, 4) for s in strips)
    empty = GridView(np.zeros((0, 0), np.int8), 0.05, 0.0, 0.0)
    assert len(render_map(RobotView(grid=empty, costmap=empty), 20, 5)) == 5
