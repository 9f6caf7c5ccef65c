"""The critic base: read your parameters once, then ``score(data)`` adds to ``data.costs``.

As in Nav2, every term is ``(weight * term) ** power`` with power 1 here, so a critic's weight
is the exchange rate between its term and every other critic's.
"""
from __future__ import annotations

from nav.costmap.config import CostmapsConfig
from nav.mppi.critic_data import CriticData


class Critic:
    def __init__(self, params, costmaps: CostmapsConfig):
        self.params = params
        self.costmaps = costmaps

    def score(self, data: CriticData) -> None:  # pragma: no cover - abstract
        raise NotImplementedError
