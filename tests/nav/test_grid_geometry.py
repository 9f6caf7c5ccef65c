"""The one grid geometry: world <-> cell <-> pixel, and growing, shifting and cropping on one
lattice so cells copy across exactly."""
from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from nav.grid_geometry import GridGeometry, paste

G = GridGeometry(0.05, -1.0, -0.5, 40, 20)  # 2 x 1 m
coords = st.floats(-50.0, 50.0, allow_nan=False)


def test_a_point_lands_in_the_cell_whose_square_holds_it():
    ix, iy = G.cell_of([-1.0, -0.951, 0.999, -1.0001], [-0.5, -0.5, 0.499, -0.5])
    assert ix.tolist() == [0, 0, 39, -1] and iy.tolist() == [0, 0, 19, 0]
    assert G.contains(ix, iy).tolist() == [True, True, True, False]
    assert G.flat_index([-1.0, 0.999, 5.0], [-0.5, 0.499, 0.0]).tolist() == [0, 19 * 40 + 39, -1]


@given(coords, coords)
def test_cell_centres_round_trip(x, y):
    ix, iy = G.cell_of(x, y)
    cx, cy = G.centre_of(ix, iy)
    assert abs(cx - x) <= G.resolution / 2 + 1e-9 and abs(cy - y) <= G.resolution / 2 + 1e-9
    assert G.cell_of(cx, cy) == (ix, iy)


def test_pictures_are_north_up_at_whole_pixels_per_cell():
    c, r = G.pixel_of([-1.0, 1.0, -1.0], [0.5, -0.5, -0.5], scale=4)
    assert c.tolist() == pytest.approx([0.0, 160.0, 0.0]) and r.tolist() == pytest.approx([0.0, 80.0, 80.0])


def test_covering_lies_on_the_world_lattice_whatever_the_box():
    g = GridGeometry.covering(-12.0, -12.0, 12.0, 12.0, 0.05)
    assert (g.width, g.height, g.origin_x, g.origin_y) == (480, 480, -12.0, -12.0)  # -12 / 0.05 is not -240 in floats
    h = GridGeometry.covering(0.33, -0.07, 0.4, 0.0, 0.05)
    assert h.offset_in(g) == (246, 238) and h.extent[0] <= 0.33 and h.extent[1] >= 0.4


@settings(max_examples=60)
@given(coords, coords, coords, coords, st.integers(1, 64))
def test_growing_covers_the_box_never_shrinks_and_keeps_the_lattice(x0, y0, x1, y1, step):
    grown = G.grown_to_cover(min(x0, x1), min(y0, y1), max(x0, x1), max(y0, y1), step)
    gx0, gx1, gy0, gy1 = grown.extent
    ox0, ox1, oy0, oy1 = G.extent
    assert gx0 <= min(x0, x1, ox0) + 1e-9 and gx1 >= max(x0, x1, ox1) - 1e-9
    assert gy0 <= min(y0, y1, oy0) + 1e-9 and gy1 >= max(y0, y1, oy1) - 1e-9
    dx, dy = G.offset_in(grown)
    assert dx % step == 0 and dy % step == 0 and (grown.width - G.width) % step == 0


def test_growing_inside_the_grid_changes_nothing():
    assert G.grown_to_cover(-0.5, -0.2, 0.5, 0.2, step=32) is G


def test_paste_copies_cells_exactly_when_grown_shifted_or_cropped():
    data = np.arange(G.width * G.height, dtype=np.int32).reshape(G.shape)
    grown = G.grown_to_cover(-2.0, -0.5, 1.0, 1.3)
    out = paste(data, G, grown, fill=-7)
    dx, dy = G.offset_in(grown)
    assert np.array_equal(out[dy:dy + G.height, dx:dx + G.width], data)
    assert (out == -7).sum() == grown.width * grown.height - data.size
    shifted = G.shifted(5, -3)
    moved = paste(data, G, shifted, fill=-1)
    assert moved[3, 0] == data[0, 5] and (moved[:3] == -1).all() and (moved[:, -5:] == -1).all()
    crop = G.cropped(10, 4, 20, 9)
    assert np.array_equal(paste(data, G, crop, fill=0), data[4:9, 10:20])


def test_grids_off_the_lattice_refuse_to_paste():
    with pytest.raises(ValueError, match="fraction of a cell"):
        paste(np.zeros(G.shape), G, GridGeometry(0.05, -1.01, -0.5, 40, 20), 0)
    with pytest.raises(ValueError, match="share a lattice"):
        paste(np.zeros(G.shape), G, GridGeometry(0.1, -1.0, -0.5, 40, 20), 0)
