"""The hw benchmarks' figures come from the wall times they measure: the parser and the servo
bus run for real, but the benchmark's clock is a stopwatch whose every timed section lasts a
duration the test chooses, so the figures are known (real wall times are machine-dependent)."""
import itertools
from types import SimpleNamespace

import pytest

import lupin.bench.hw  # noqa: F401  (registers the group)
from lupin.bench import BENCHMARKS, summarise
from mission.runtime.config import LupinConfig

WIRE_MS = (6 + 8) * 10 / 115200 * 1000
"""One POS_READ on the wire: 6-byte request + 8-byte reply, 10 bits a byte at 115200 baud."""


class Stopwatch:
    """``perf_counter`` for the benchmark: timed sections (start, stop pairs of calls) last
    ``durations_ms`` in turn; ``sections`` counts them."""

    def __init__(self, durations_ms):
        self._durations = itertools.cycle(durations_ms)
        self._now, self._running, self.sections = 0.0, False, 0

    def perf_counter(self) -> float:
        if self._running:
            self._now += next(self._durations) / 1000.0
            self.sections += 1
        self._running = not self._running
        return self._now


def run(monkeypatch, name, durations_ms):
    watch = Stopwatch(durations_ms)
    monkeypatch.setattr(lupin.bench.hw, "time", SimpleNamespace(perf_counter=watch.perf_counter))
    return summarise(name, BENCHMARKS[name](LupinConfig())), watch


def test_lidar_parse_reports_the_median_runs_rate(monkeypatch):
    monkeypatch.setattr(lupin.bench.hw, "RUNS", 5)
    row, watch = run(monkeypatch, "hw.lidar_parse", [10.0, 2.0, 5.0])
    assert row["n"] == watch.sections and row["median_ms"] == 5.0
    assert row["samples_per_s"] == 1_000_000 and row["multiple_of_c1"] == 200.0  # 5000 nodes in 5 ms; C1 5000/s
    row, _ = run(monkeypatch, "hw.lidar_parse", [2.5])  # twice as fast: twice the rate
    assert row["samples_per_s"] == 2_000_000 and row["multiple_of_c1"] == 400.0
    row, _ = run(monkeypatch, "hw.lidar_parse", [40.0, 2.5, 2.5])  # one slow run does not move the median
    assert row["samples_per_s"] == 2_000_000


def test_servo_bus_reports_its_rate_against_the_wire(monkeypatch):
    monkeypatch.setattr(lupin.bench.hw, "TRANSACTIONS", 20)
    row, watch = run(monkeypatch, "hw.servo_bus", [2 * WIRE_MS])
    assert row["n"] == watch.sections
    assert row["wire_limit_per_s"] == pytest.approx(822.9, abs=0.05)
    assert row["transactions_per_s"] == pytest.approx(411.4, abs=0.05) and row["wire_fraction"] == 0.5
    row, _ = run(monkeypatch, "hw.servo_bus", [WIRE_MS, 10 * WIRE_MS, WIRE_MS])  # at the wire's pace but for one
    assert row["wire_fraction"] == 1.0
