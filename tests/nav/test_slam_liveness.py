"""Telling a wedged SLAM worker from a starved one by its CPU time (real processes)."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from nav.slam.liveness import Liveness, cpu_seconds

pytestmark = [pytest.mark.slow, pytest.mark.skipif(not os.path.exists("/proc/self/stat"), reason="needs /proc")]

SPIN = "while True: pass"
SLOW = ("import time\n"
        "while True:\n"
        "    end = time.perf_counter() + 0.05\n"
        "    while time.perf_counter() < end: pass\n"
        "    time.sleep(0.25)\n")


def watch(code: str, seconds: float, limit: float, stop: bool = False):
    """Run ``code`` in a child, watch it for ``seconds`` of wall time; the first verdict."""
    proc = subprocess.Popen([sys.executable, "-c", code])
    try:
        time.sleep(0.3)  # past the interpreter's start
        if stop:
            os.kill(proc.pid, signal.SIGSTOP)
        start = time.monotonic()
        live = Liveness(proc.pid, start)
        while (now := time.monotonic()) - start < seconds:
            why = live.wedged(now, limit)
            if why is not None:
                return why
            time.sleep(0.05)
        return None
    finally:
        proc.kill()
        proc.wait()


def test_cpu_seconds_reads_this_process_and_grows_with_work():
    before = cpu_seconds(os.getpid())
    end = time.process_time() + 0.1
    while time.process_time() < end:
        pass
    assert cpu_seconds(os.getpid()) >= before + 0.05
    assert cpu_seconds(2 ** 22 + 12345) is None  # no such process


def test_a_stopped_worker_is_hung():
    assert "hung" in watch(SPIN, 3.0, limit=0.5, stop=True)


def test_a_spinning_worker_is_wedged_by_its_cpu_time():
    assert "spinning" in watch(SPIN, 5.0, limit=0.5)


def test_a_slow_worker_that_keeps_working_is_waited_on_past_the_limit():
    # ~20 % of a core: three times the 0.6 s limit of silence passes without a verdict
    assert watch(SLOW, 1.8, limit=0.6) is None
