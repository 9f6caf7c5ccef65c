"""The inflation layer: Nav2's formula and values, unknown cells, both implementations agree."""
from __future__ import annotations

import math

import numpy as np
import pytest

from nav.costmap.config import CostmapsConfig
from nav.costmap.grid import FREE, INSCRIBED, LETHAL, UNKNOWN
from nav.costmap.inflation import InflationLayer, cell_radius


def layer(cfg: CostmapsConfig | None = None) -> InflationLayer:
    cfg = cfg or CostmapsConfig()
    return InflationLayer(cfg.resolution, cfg.robot_radius, cfg.inflation_radius, cfg.cost_scaling_factor)


def nav2_cost(k: int) -> int:
    """Nav2's computeCost for a squared cell distance k at the seed's numbers, written out."""
    d = math.sqrt(k) * 0.05
    if k == 0:
        return 254
    if d <= 0.22:
        return 253
    if math.sqrt(k) > 5:
        return 0
    return int(252 * math.exp(-5.0 * (d - 0.22)))


def test_halo_around_one_lethal_cell_follows_nav2():
    m = np.zeros((21, 21), np.uint8)
    m[10, 10] = LETHAL
    out = layer().apply(m)
    for dy in range(-10, 11):
        for dx in range(-10, 11):
            assert out[10 + dy, 10 + dx] == nav2_cost(dx * dx + dy * dy), (dx, dy)
    # The seed's thin halo: inscribed out to sqrt(19) cells (0.218 m), then 247 .. 216, then free.
    assert out[10, 14] == INSCRIBED and out[12, 14] == 247 and out[10, 15] == 216 and out[10, 16] == FREE
    assert cell_radius(0.25, 0.05) == 5


def test_a_0p8_m_aisle_keeps_a_free_spine():
    m = np.zeros((40, 40), np.uint8)
    m[:, 4] = m[:, 4 + 16] = LETHAL  # walls 16 cells = 0.8 m apart
    out = layer().apply(m)
    spine = out[:, 4 + 6:4 + 11]  # cells more than 0.25 m from both walls
    assert np.all(spine == FREE)
    assert np.all(out[:, 4 + 4] == INSCRIBED) and np.all(out[:, 4 + 5] == 216)


def test_unknown_cells_are_no_source_and_only_take_inscribed_cost():
    m = np.full((21, 21), UNKNOWN, np.uint8)
    assert np.array_equal(layer().apply(m), m)  # unknown alone inflates nothing
    m[10, 10] = LETHAL
    out = layer().apply(m)
    assert out[10, 14] == INSCRIBED  # inscribed wins over unknown (Nav2, inflate_unknown false)
    assert out[12, 14] == UNKNOWN and out[10, 15] == UNKNOWN  # lower costs leave it unknown
    assert out[10, 10] == LETHAL


def test_existing_costs_keep_the_maximum():
    m = np.zeros((21, 21), np.uint8)
    m[10, 10] = LETHAL
    m[10, 15] = 230  # higher than the 216 the halo brings
    m[10, 14] = 100  # lower than inscribed
    out = layer().apply(m)
    assert out[10, 15] == 230 and out[10, 14] == INSCRIBED


@pytest.mark.parametrize("seed", range(4))
def test_stamping_matches_the_exact_distance_transform(seed):
    rng = np.random.default_rng(seed)
    m = np.zeros((97, 131), np.uint8)
    m[rng.random(m.shape) < 0.02] = LETHAL
    m[30:45, 60:90] = LETHAL  # a solid block: interior cells are skipped, the halo must not change
    m[rng.random(m.shape) < 0.2] = UNKNOWN
    m[0, :] = LETHAL  # sources on the border
    for cfg in (CostmapsConfig(), CostmapsConfig(inflation_radius=0.55, cost_scaling_factor=3.0)):
        lay = layer(cfg)
        assert np.array_equal(lay.apply(m), lay.apply_edt(m))
