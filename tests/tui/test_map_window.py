"""The map panel's window without a terminal: the fit, zoom steps about the centre shown, the
limits, panning by a quarter window, following the robot, and a fit that grows with the map."""
from __future__ import annotations

import pytest

from tests.tui.fakes import greenhouse_grid, greenhouse_view
from tui.widgets.map_panel import map_pixels
from tui.widgets.map_window import FOLLOW_SPAN, MAX_SCALE, ZOOM_STEP, MapWindow, fit_scale

FIT = (0.0, 30.0, 0.0, 10.0)
W, H = 90, 60  # pixels: the fit is 3 px/m across (30 m), and 6 px/m would fit the height


def test_the_default_window_is_the_fit_centred_on_it():
    f = MapWindow().frame(FIT, (3.0, 4.0), W, H)
    assert f.scale == pytest.approx(3.0) and f.zoom == pytest.approx(1.0)
    x0, x1, y0, y1 = f.bounds
    assert (x0, x1) == pytest.approx((0.0, 30.0)) and (y0 + y1) / 2 == pytest.approx(5.0)
    assert y1 - y0 == pytest.approx(20.0)  # the panel's aspect: 60 px at 3 px/m


def test_zoom_steps_about_the_centre_shown_and_back_out_to_the_fit():
    w = MapWindow()
    w.zoom(1, w.frame(FIT, (3.0, 4.0), W, H))
    w.zoom(1, w.frame(FIT, (3.0, 4.0), W, H))
    f = w.frame(FIT, (3.0, 4.0), W, H)
    assert f.zoom == pytest.approx(ZOOM_STEP ** 2) and f.centre == pytest.approx((15.0, 5.0))
    assert f.bounds[1] - f.bounds[0] == pytest.approx(30.0 / ZOOM_STEP ** 2)
    w.zoom(-1, f)
    w.zoom(-1, w.frame(FIT, (3.0, 4.0), W, H))
    assert w.fitted
    w.zoom(-1, w.frame(FIT, (3.0, 4.0), W, H))  # past the fit: still the fit
    assert w.fitted and w.frame(FIT, (3.0, 4.0), W, H).zoom == pytest.approx(1.0)


def test_zoom_in_stops_at_two_pixels_a_map_cell():
    w = MapWindow()
    for _ in range(30):
        w.zoom(1, w.frame(FIT, (3.0, 4.0), W, H))
    assert w.frame(FIT, (3.0, 4.0), W, H).scale == pytest.approx(MAX_SCALE)


def test_a_zoomed_window_keeps_its_scale_and_centre_while_the_map_grows():
    w = MapWindow()
    w.zoom(2, w.frame(FIT, (3.0, 4.0), W, H))
    before = w.frame(FIT, (3.0, 4.0), W, H)
    after = w.frame((0.0, 60.0, -5.0, 15.0), (3.0, 4.0), W, H)  # the fit doubled
    assert after.scale == pytest.approx(before.scale) and after.centre == pytest.approx(before.centre)
    assert after.zoom == pytest.approx(2 * before.zoom)


def test_pan_moves_a_quarter_window_and_stops_following():
    w = MapWindow()
    w.toggle_follow(w.frame(FIT, (3.0, 4.0), W, H), W)
    f = w.frame(FIT, (3.0, 4.0), W, H)
    w.pan(1, 0, f)
    g = w.frame(FIT, (3.0, 4.0), W, H)
    assert not w.follow
    assert g.centre == pytest.approx((3.0 + (f.bounds[1] - f.bounds[0]) / 4, 4.0))
    w.pan(0, -1, g)
    h = w.frame(FIT, (3.0, 4.0), W, H)
    assert h.centre == pytest.approx((g.centre[0], 4.0 - (g.bounds[3] - g.bounds[2]) / 4))
    assert h.scale == pytest.approx(f.scale)  # panning does not zoom


def test_follow_centres_the_robot_zooms_in_from_the_fit_and_lets_go_where_it_was():
    w = MapWindow()
    w.toggle_follow(w.frame(FIT, (3.0, 4.0), W, H), W)
    f = w.frame(FIT, (3.0, 4.0), W, H)
    assert f.centre == (3.0, 4.0) and f.bounds[1] - f.bounds[0] == pytest.approx(FOLLOW_SPAN)
    g = w.frame(FIT, (7.5, 2.0), W, H)  # the robot moved
    assert g.centre == (7.5, 2.0) and g.scale == pytest.approx(f.scale)
    w.toggle_follow(g, W)
    assert not w.follow and w.frame(FIT, (20.0, 9.0), W, H).centre == (7.5, 2.0)
    w.fit()
    assert w.fitted


def test_following_a_zoomed_in_window_keeps_its_zoom():
    w = MapWindow()
    for _ in range(5):
        w.zoom(1, w.frame(FIT, (3.0, 4.0), W, H))
    scale = w.frame(FIT, (3.0, 4.0), W, H).scale
    w.toggle_follow(w.frame(FIT, (3.0, 4.0), W, H), W)
    assert w.frame(FIT, (3.0, 4.0), W, H).scale == pytest.approx(scale)


def test_the_canvas_draws_the_window_it_is_given():
    """Following in the greenhouse: the robot is the centre pixel, at the window's scale."""
    v = greenhouse_view()
    w = MapWindow()
    cv = map_pixels(v, 94, 29, w)
    w.toggle_follow(cv.frame, 94)
    cv = map_pixels(v, 94, 29, w)
    c, r = cv.to_pixel(v.pose[0], v.pose[1])
    assert abs(int(c) - cv.w // 2) <= 1 and abs(int(r) - cv.h // 2) <= 1
    assert cv.scale == pytest.approx(cv.frame.scale)


def test_the_fit_grows_with_the_map():
    """The SLAM grid grows eastward as the robot explores bay 2: the fitted window takes it in."""
    v = greenhouse_view()
    v.pots = []  # only the map decides
    v.pose = (2.0, 2.0, 0.0)
    v.goal, v.plan = None, v.plan[:0]
    v.grid = greenhouse_grid(east=14.0)
    small = map_pixels(v, 94, 29).frame
    v.grid = greenhouse_grid(east=31.0)
    grown = map_pixels(v, 94, 29).frame
    assert small.scale == pytest.approx(fit_scale((-1.5, 14.5, -1.5, 11.5), 94, 58))  # the known part and the margin
    assert grown.scale == pytest.approx(fit_scale((-1.5, 31.5, -1.5, 11.5), 94, 58))
    assert small.bounds[0] <= -1.5 and small.bounds[1] >= 14.5 and grown.bounds[0] <= -1.5 and grown.bounds[1] >= 31.5
    grid = v.grid.geometry.extent
    assert grown.bounds[1] - grown.bounds[0] < 0.75 * (grid[1] - grid[0])  # the grid's unknown margin is left out
