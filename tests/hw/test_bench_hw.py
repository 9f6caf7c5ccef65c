"""The hw benchmarks run and report their figures (values are machine-dependent: not asserted)."""
from lupin.bench import BENCHMARKS, summarise
from mission.runtime.config import LupinConfig
import lupin.bench.hw  # noqa: F401  (registers the group)


def test_hw_benchmarks_report_their_figures(monkeypatch):
    monkeypatch.setattr(lupin.bench.hw, "RUNS", 3)
    monkeypatch.setattr(lupin.bench.hw, "TRANSACTIONS", 20)
    config = LupinConfig()
    lidar = summarise("hw.lidar_parse", BENCHMARKS["hw.lidar_parse"](config))
    assert lidar["n"] == 3 and lidar["samples_per_s"] > 0
    assert lidar["multiple_of_c1"] == round(lidar["samples_per_s"] / 5000, 1)
    servo = summarise("hw.servo_bus", BENCHMARKS["hw.servo_bus"](config))
    assert servo["n"] == 20 and 0 < servo["wire_fraction"] <= 1.0  # paced at the wire: never above it
    assert servo["wire_limit_per_s"] == round(115200 / 10 / 14, 1)
