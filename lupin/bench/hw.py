"""Hardware-driver benchmarks: the lidar parser's throughput and the servo bus's transaction rate.

``hw.lidar_parse``: one second of C1 data (10 revolutions x 500 nodes = 5000 samples, 25 kB)
fed to ``ScanParser`` in 512-byte reads, about what the driver's reader thread gets per 20 ms
read window at the C1's 25 kB/s; one sample per second of data. ``samples_per_s`` is nodes parsed per wall second on one core and
``multiple_of_c1`` that over the C1's ~5000 samples/s (goal >= 20x: the parser must be a
rounding error on the robot's 4-core A55).

``hw.servo_bus``: POS_READ transactions through the real driver and pyserial against the bus
emulator on a pseudo-terminal. A pty has no baud rate, so the emulator holds each reply for the
wire time of request + reply at 115200 baud (10 bits a byte); ``wire_fraction`` is the rate
achieved over that wire limit (6 + 8 bytes = 1.22 ms, ~823 transactions/s), i.e. how much of
the bus the driver's own turnaround leaves unused.
"""
from __future__ import annotations

import time

import numpy as np

from hw.drivers.hiwonder import HiwonderBus
from hw.drivers.rplidar_protocol import ScanParser, encode_nodes
from hw.emulators.hiwonder_bus import HiwonderBusEmulator
from lupin.bench import Sample, benchmark
from mission.runtime.config import LupinConfig

C1_SAMPLES_PER_S = 5000
POINTS, REVS, CHUNK = 500, 10, 512
RUNS = 30
BAUD = 115200
TRANSACTIONS = 300
POS_READ_BYTES = 6 + 8


def _one_second_of_c1() -> bytes:
    n = POINTS * REVS
    angles = np.tile(np.arange(POINTS) * 360.0 / POINTS, REVS)
    dist = 1500.0 + 500.0 * np.sin(np.radians(angles) * 3)
    start = (np.arange(n) % POINTS == 0).astype(np.uint8)
    return encode_nodes(angles, dist, 47, start)


@benchmark("hw.lidar_parse")
def lidar_parse(config: LupinConfig) -> Sample:
    """Wall ms to parse one second of C1 scan bytes (5000 nodes) in 512-byte reads."""
    data = _one_second_of_c1()
    chunks = [data[i:i + CHUNK] for i in range(0, len(data), CHUNK)]
    times = []
    for _ in range(RUNS):
        parser = ScanParser(config.hw.devices.lidar.range_min, config.hw.devices.lidar.range_max)
        t0 = time.perf_counter()
        for c in chunks:
            parser.feed(c)
        times.append((time.perf_counter() - t0) * 1000.0)
        assert parser.nodes == POINTS * REVS
    rate = POINTS * REVS / (float(np.median(times)) / 1000.0)
    rate = round(rate)  # both figures from the printed rate, so they agree with each other
    return Sample(times, {"samples_per_s": rate, "multiple_of_c1": round(rate / C1_SAMPLES_PER_S, 1)})


@benchmark("hw.servo_bus")
def servo_bus(config: LupinConfig) -> Sample:
    """Wall ms per POS_READ transaction against the bus emulator paced at 115200 baud."""
    times = []
    with HiwonderBusEmulator(baud=BAUD) as emu:
        bus = HiwonderBus.open(emu.path, BAUD, timeout_s=0.05, retries=0)
        for i in range(TRANSACTIONS):
            t0 = time.perf_counter()
            bus.read_position(2 + i % 5)
            times.append((time.perf_counter() - t0) * 1000.0)
        bus.close()
    rate = 1000.0 / float(np.median(times))
    wire_limit = BAUD / 10.0 / POS_READ_BYTES
    return Sample(times, {"transactions_per_s": round(rate, 1), "wire_fraction": round(rate / wire_limit, 3),
                          "wire_limit_per_s": round(wire_limit, 1)})
