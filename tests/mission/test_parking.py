"""Where a robot that cannot reach its dock stops (mission.patrol.parking): out of the aisles,
clear of their mouths, on a made-up greenhouse costmap."""
from __future__ import annotations

import numpy as np

from mission.patrol.parking import MOUTH_KEEP, clear_spots, parking_spot
from nav.costmap.grid import LETHAL, CostGrid

RES = 0.05


def greenhouse() -> CostGrid:
    """8 x 4 m inside walls; three rows of pots (x 2..6 m at y 1, 2, 3: 0.3 m bands, inflation
    included) leave two 0.7 m aisles between them and 1.9 m open ground west and east."""
    g = CostGrid.filled(int(8 / RES), int(4 / RES), RES, 0.0, 0.0)
    g.data[[0, -1], :] = g.data[:, [0, -1]] = LETHAL
    for y in (1.0, 2.0, 3.0):
        g.data[int((y - 0.15) / RES):int((y + 0.15) / RES), int(2.0 / RES):int(6.0 / RES)] = LETHAL
    return g


def straight(origin, points):
    return np.hypot(*(np.asarray(points, float) - np.asarray(origin, float)).T)


def test_no_spot_is_in_an_aisle_or_at_its_mouth():
    spots = clear_spots(greenhouse())
    assert len(spots) > 10
    x, y = spots.T
    in_aisle_band = ((y > 1.15) & (y < 1.85)) | ((y > 2.15) & (y < 2.85))
    assert not np.any(in_aisle_band & (x > 2.0 - MOUTH_KEEP + 0.2) & (x < 6.0 + MOUTH_KEEP - 0.2))
    assert np.all((x < 2.0 - 0.5) | (x > 6.0 + 0.5) | (y < 0.85))  # open ground only


def test_a_robot_in_an_aisle_parks_at_the_nearest_clear_spot():
    x, y, metres = parking_spot(greenhouse(), (3.0, 1.5), straight)
    assert (x < 1.0 or x > 7.0 or y < 0.85) and metres < 3.5
