"""The patrol's run.png: pots coloured by result where the map says they are, the path, thumbnails."""
from __future__ import annotations

import numpy as np
import pytest

from mission.patrol.run_picture import GREEN, GREY, ORANGE, PATH, RED, PotMark, canvas, contact_sheet, draw_run
from nav.map_render import default_scale, render_map, to_pixel
from nav.occupancy import OccupancyMap

MAGENTA = (255, 0, 255)


def room() -> OccupancyMap:
    """A 6 x 4 m room, walls round it, a 0.5 m unknown band to the west; origin 0.5 m in."""
    occ = np.zeros((80, 120), np.int8)
    occ[0, :] = occ[-1, :] = occ[:, 0] = occ[:, -1] = 100
    occ[:, 1:10] = -1
    return OccupancyMap(occ, 0.05, -0.5, -0.5)


def pot(id_="P01", x=1.0, y=2.0, status="inspected", anomaly=False, label=None, thumbnail=None):
    return PotMark(id_, x, y, status, anomaly, label or id_, thumbnail)


def at(img, m, scale, x, y):
    c, r = to_pixel(m, scale, x, y)
    return tuple(int(v) for v in img[r, c])


def test_each_pot_is_a_disc_in_its_result_colour_on_the_maps_own_pixels():
    m = room()
    pots = [pot("A", 1.0, 2.0), pot("B", 2.0, 2.0, anomaly=True), pot("C", 3.0, 2.0, "failed", anomaly=True),
            pot("D", 4.0, 2.0, "skipped"), pot("E", 4.0, 1.0, "pending"), pot("F", 3.0, 1.0, "inspected", True)]
    img = draw_run(m, np.empty((0, 2)), pots, home=(0.5, 0.5))
    c, s = canvas(m, np.empty((0, 2)), pots, (0.5, 0.5))
    # everything lies 0.6 m or more inside the map: it is drawn as it is, at render_map's default scale
    assert (c.width, c.height, c.origin_x, c.origin_y) == (m.width, m.height, m.origin_x, m.origin_y)
    assert s == default_scale(m)
    expected = [GREEN, ORANGE, RED, GREY, GREY, ORANGE]
    assert [at(img, m, s, p.x, p.y) for p in pots] == expected
    for p, colour in zip(pots, expected):  # a disc, not a dot: 3 cm off centre is still the pot
        assert at(img, m, s, p.x + 0.03, p.y - 0.03) == colour
    plain = render_map(m)
    assert img[:plain.shape[0], :plain.shape[1]][plain == 0].max() < 60  # walls stay black (the map, not re-drawn)
    assert at(img, m, s, 5.4, 0.5) == at(plain, m, s, 5.4, 0.5) == (255, 255, 255)  # free floor, away from it all


def test_an_unknown_status_is_grey_not_an_error():
    m = room()
    img = draw_run(m, np.empty((0, 2)), [pot(status="lost")])
    assert at(img, m, default_scale(m), 1.0, 2.0) == GREY


def test_the_driven_path_is_a_line_along_its_points():
    m = room()
    path = np.column_stack([np.linspace(0.5, 4.5, 50), np.full(50, 1.5)])
    img = draw_run(m, path, [pot("A", 2.0, 2.5)])
    s = default_scale(m)
    assert canvas(m, path, [pot("A", 2.0, 2.5)])[0].occupancy.shape == m.occupancy.shape
    for x in np.arange(0.8, 4.3, 0.25):
        assert at(img, m, s, x, 1.5) == PATH, x
    assert at(img, m, s, 2.5, 2.5) == (255, 255, 255)  # and not elsewhere
    top = img[:render_map(m).shape[0]]
    rows = np.nonzero(np.all(top == PATH, axis=2).any(axis=1))[0]
    r = to_pixel(m, s, 0.0, 1.5)[1]
    assert rows.min() >= r - 8 and rows.max() <= r + 8  # a thin band round y = 1.5 (start dot included)


def test_an_empty_path_draws_no_path():
    m = room()
    img = draw_run(m, np.empty((0, 2)), [pot()], home=(0.0, 0.0))
    top = img[:render_map(m).shape[0]]
    assert not np.all(top == PATH, axis=2).any()


def test_thumbnails_sit_under_the_map_framed_in_their_pots_colour():
    m = room()
    map_h = render_map(m).shape[0]
    thumb = np.zeros((50, 100, 3), np.uint8)
    thumb[:] = MAGENTA
    bare = draw_run(m, np.empty((0, 2)), [])
    one = draw_run(m, np.empty((0, 2)), [pot("A", status="failed", thumbnail=thumb)])
    assert one.shape[0] > bare.shape[0] + 80
    strip = one[map_h:]
    ys, xs = np.nonzero(np.all(strip == MAGENTA, axis=2))
    assert len(ys)
    w, h = xs.max() - xs.min() + 1, ys.max() - ys.min() + 1
    assert 150 <= w <= 170 and abs(w / h - 2.0) < 0.1  # ~160 px wide, the aspect kept
    assert tuple(strip[ys.min() - 2, xs.min() + 20]) == RED  # the border, in the failed pot's red
    assert not np.all(one[:map_h] == MAGENTA, axis=2).any()


def test_a_pot_without_an_image_gets_a_placeholder_and_tiles_keep_their_order():
    m = room()
    map_h = render_map(m).shape[0]
    red, blue = np.zeros((60, 80, 3), np.uint8), np.zeros((60, 80, 3), np.uint8)
    red[:] = (0, 0, 255)
    blue[:] = (255, 0, 0)
    img = draw_run(m, np.empty((0, 2)), [pot("A", thumbnail=blue), pot("B", 2.0), pot("C", 3.0, thumbnail=red)])
    strip = img[map_h:]
    placeholder = np.all(strip == (215, 215, 215), axis=2)
    assert placeholder.sum() > 100 * 80
    xb = np.nonzero(np.all(strip == (255, 0, 0), axis=2))[1]
    xr = np.nonzero(np.all(strip == (0, 0, 255), axis=2))[1]
    xp = np.nonzero(placeholder.sum(axis=0) > 50)[0]  # the box's columns (not stray anti-aliased text pixels)
    assert xb.max() < xp.min() and xp.max() < xr.min()


def test_many_pots_wrap_into_more_rows_and_odd_images_are_fine():
    m = room()
    grey = np.full((480, 40), 90, np.uint8)  # grey-scale, very tall
    pots = [pot(f"P{k}", 0.5 + 0.5 * k, 1.0, thumbnail=grey if k % 2 else None,
                label="P%d red x2 bug tag_mismatch no_bloom no_tag unreachable" % k) for k in range(7)]
    six, seven = draw_run(m, np.empty((0, 2)), pots[:6]), draw_run(m, np.empty((0, 2)), pots)
    assert seven.shape[0] > six.shape[0] + 100
    assert seven.shape[1] < 1400


def test_without_a_map_a_blank_canvas_covers_path_pots_and_home():
    path = np.array([[-2.0, -1.0], [3.0, -1.0], [3.0, 2.0]])
    pots = [pot("A", 1.0, 1.0), pot("B", 5.0, 4.0, "failed")]
    img = draw_run(None, path, pots, home=(-3.0, -2.0))
    m, s = canvas(None, path, pots, (-3.0, -2.0))
    assert at(img, m, s, 1.0, 1.0) == GREEN and at(img, m, s, 5.0, 4.0) == RED
    assert at(img, m, s, 0.0, -1.0) == PATH and at(img, m, s, 3.0, 0.5) == PATH
    assert m.origin_x <= -3.6 + 1e-9 and m.origin_y <= -2.6 + 1e-9  # 0.6 m round everything
    assert m.origin_x + m.width * m.resolution >= 5.6 - 1e-9 and m.origin_y + m.height * m.resolution >= 4.6 - 1e-9
    assert (m.occupancy == 0).all() and at(img, m, s, 2.5, 3.5) == (255, 255, 255)


def test_without_a_map_and_nothing_to_draw_still_a_picture():
    img = draw_run(None, np.empty((0, 2)), [])
    assert img.ndim == 3 and img.dtype == np.uint8 and min(img.shape[:2]) >= 40


def test_a_pot_off_the_map_grows_it_with_unknown_and_is_drawn():
    m = room()
    pots = [pot("A", 1.0, 2.0), pot("far", 8.0, 6.0, "failed")]
    img = draw_run(m, np.empty((0, 2)), pots)
    c, s = canvas(m, np.empty((0, 2)), pots)
    assert c.origin_x + c.width * c.resolution >= 8.6 - 1e-9 and c.origin_y + c.height * c.resolution >= 6.6 - 1e-9
    assert at(img, c, s, 8.0, 6.0) == RED and at(img, c, s, 1.0, 2.0) == GREEN
    assert at(img, c, s, 7.0, 5.0) == (160, 160, 160)  # the growth is unknown, not free


def test_a_pot_far_off_is_drawn_at_the_edge_of_a_sanely_sized_picture():
    m = room()
    pots = [pot("A", 1.0, 2.0), pot("far", 40.0, 2.0, "failed")]
    img = draw_run(m, np.empty((0, 2)), pots)
    c, s = canvas(m, np.empty((0, 2)), pots)
    assert c.origin_x + c.width * c.resolution < 5.5 + 10.0 + 0.1  # grown 10 m at most
    col, row = to_pixel(c, s, 40.0, 2.0)
    w = render_map(c, s).shape[1]
    assert col > w and tuple(img[row, w - 3]) == RED


@pytest.mark.parametrize("occupancy", [room(), None])
def test_absurd_coordinates_do_not_crash_nor_make_a_huge_picture(occupancy):
    pots = [pot("A", 1.0, 2.0), pot("wild", 1e6, -1e9, "failed"), pot("nan", float("nan"), 1.0)]
    path = np.array([[0.0, 0.0], [np.nan, np.nan], [1.0, 0.0], [1e12, 0.0]])
    img = draw_run(occupancy, path, pots, home=(float("inf"), 0.0))
    assert max(img.shape[:2]) < 2000
    c, s = canvas(occupancy, path, pots, (float("inf"), 0.0))
    assert at(img, c, s, 1.0, 2.0) == GREEN


def test_a_big_patrol_keeps_its_map_readable_and_puts_its_thumbnails_on_a_contact_sheet():
    m = room()
    thumb = np.full((120, 160, 3), 200, np.uint8)
    pots = [pot(f"P{k:03d}", 0.2 + 0.02 * k, 1.0, thumbnail=thumb) for k in range(200)]
    img = draw_run(m, np.empty((0, 2)), pots)
    assert img.shape[0] < render_map(m).shape[0] + 100  # the map and a legend line, no tiles
    sheet = contact_sheet(pots)
    assert sheet is not None and sheet.shape[0] >= 20 * 150 and sheet.shape[1] >= 10 * 160  # 20 rows of 10
    assert contact_sheet(pots[:24]) is None and draw_run(m, np.empty((0, 2)), pots[:24]).shape[0] > img.shape[0]
