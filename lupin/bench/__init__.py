"""`lupin bench`: the project's benchmark harness.

A benchmark is a function ``(config) -> Sample`` registered under a dotted name
("sim.realtime"); ``lupin bench sim`` runs every benchmark in the ``sim`` group, ``lupin bench
nav`` every ``nav.*``. Each module of this package registers the benchmarks of one group or part
of one (``sim.py``; ``nav_mppi.py``, ``nav_costmap.py`` and ``nav_approach.py`` for ``nav``), so
benchmarks may use any layer, the simulator included, and no lower package imports this one. Each reports
the median and p95 of its samples in milliseconds plus its own figures (a real-time factor,
say). Wall time is read here, in the harness, never in the runtime or in tests.
"""
from __future__ import annotations

import importlib
import json
import pkgutil
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from hw.errors import InputError
from mission.runtime.config import LupinConfig


@dataclass
class Sample:
    """Per-iteration wall times (ms) and benchmark-specific figures."""

    times_ms: list[float]
    figures: dict = field(default_factory=dict)


BENCHMARKS: dict[str, Callable[[LupinConfig], Sample]] = {}


def time_ms(fn: Callable[[], object], n: int, warmup: int = 1) -> list[float]:
    """Wall milliseconds of ``n`` calls of ``fn`` after ``warmup`` untimed ones (numba loads
    its cache, caches fill)."""
    for _ in range(warmup):
        fn()
    out = []
    for _ in range(n):
        t0 = time.perf_counter()
        fn()
        out.append((time.perf_counter() - t0) * 1000.0)
    return out


def benchmark(name: str):
    def register(fn: Callable[[LupinConfig], Sample]):
        BENCHMARKS[name] = fn
        return fn

    return register


def _load_all() -> None:
    """Import every module of this package: each registers its group's benchmarks."""
    for info in pkgutil.iter_modules(__path__):
        importlib.import_module(f"{__name__}.{info.name}")


def select(names: list[str]) -> list[str]:
    """Benchmarks matching ``names`` exactly or as a group prefix; all when empty."""
    _load_all()
    if not names:
        return list(BENCHMARKS)
    chosen = []
    for n in names:
        hits = [b for b in BENCHMARKS if b == n or b.startswith(n + ".")]
        if not hits:
            raise InputError(f"bench: unknown benchmark {n!r}; known: {', '.join(BENCHMARKS)}")
        chosen += [h for h in hits if h not in chosen]
    return chosen


def summarise(name: str, sample: Sample) -> dict:
    """Median and p95 of the times (None when nothing was timed: every attempt failed, which
    the figures then say) and the benchmark's own figures."""
    t = np.asarray(sample.times_ms, dtype=float)
    if not t.size:
        return {"name": name, "median_ms": None, "p95_ms": None, "n": 0, **sample.figures}
    return {"name": name, "median_ms": round(float(np.median(t)), 3),
            "p95_ms": round(float(np.percentile(t, 95)), 3), "n": int(t.size), **sample.figures}


def run(names: list[str], as_json: bool, config: LupinConfig) -> list[dict]:
    out = []
    for name in select(names):
        row = summarise(name, BENCHMARKS[name](config))
        out.append(row)
        if as_json:
            print(json.dumps(row), flush=True)
        else:
            extra = ", ".join(f"{k} {v}" for k, v in row.items() if k not in ("name", "median_ms", "p95_ms", "n"))
            ms = lambda v: "      n/a" if v is None else f"{v:9.3f}"  # noqa: E731
            print(f"{name:<16} median {ms(row['median_ms'])} ms  p95 {ms(row['p95_ms'])} ms  n {row['n']:4d}"
                  + (f"  ({extra})" if extra else ""), flush=True)
    return out
