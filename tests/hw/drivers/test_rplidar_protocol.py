import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from hw.drivers.rplidar_protocol import (SCAN_DESCRIPTOR, Req, ScanParser, descriptor, encode_nodes,
                                         parse_descriptor, parse_health, parse_info, request)


def test_requests_and_descriptors_from_the_reference():
    assert request(Req.SCAN) == b"\xA5\x20"
    assert request(Req.EXPRESS_SCAN, bytes(5)) == bytes([0xA5, 0x82, 5, 0, 0, 0, 0, 0, 0xA5 ^ 0x82 ^ 5])
    d = parse_descriptor(SCAN_DESCRIPTOR)
    assert (d.length, d.mode, d.dtype) == (5, 1, 0x81)
    assert descriptor(20, 0, 4) == bytes.fromhex("A5 5A 14 00 00 00 04")
    assert parse_descriptor(bytes.fromhex("A5 5A 03 00 00 00 06")).length == 3
    with pytest.raises(ValueError):
        parse_descriptor(b"\xA5\x00" + bytes(5))


def test_info_and_health_payloads():
    info = parse_info(bytes([0x41, 1, 1, 18]) + bytes(range(16)))
    assert info.model == 0x41 and info.firmware == "1.01" and info.hardware == 18
    assert info.serial == bytes(range(16)).hex().upper()
    assert parse_health(bytes([2, 0x34, 0x12])) == ("error", 0x1234)


def test_node_layout_by_hand():
    # quality 15, S=1, angle 90.0 deg (q6 5760), 1000 mm (q2 4000)
    b = encode_nodes([90.0], [1000.0], quality=15, start=[1])
    assert b == bytes([15 << 2 | 0 << 1 | 1, (5760 & 0x7F) << 1 | 1, 5760 >> 7, 4000 & 0xFF, 4000 >> 8])


def revolutions(n=3, points=400):
    ang = np.tile(np.arange(points) * 360.0 / points, n)
    dist = np.tile(1000.0 + np.arange(points), n)
    start = np.tile(np.r_[1, np.zeros(points - 1)], n)
    return encode_nodes(ang, dist, 40, start) + encode_nodes([0.0], [500.0], 40, [1])


def test_revolutions_split_on_s_and_come_out_ccw_in_metres():
    scans = ScanParser().feed(revolutions(3))
    assert len(scans) == 3
    angles, ranges = scans[0]
    assert angles.dtype == np.float32 and angles.size == 400
    assert np.all(np.diff(angles) >= 0) and angles.min() >= 0 and angles.max() < 2 * np.pi
    # lidar 90 deg clockwise is REP-103 270 deg (-90): CCW conversion
    i = np.argmin(np.abs(angles - np.radians(270)))
    assert ranges[i] == pytest.approx((1000 + 100) / 1000, abs=1e-3)


def test_no_return_and_out_of_range_are_inf():
    data = encode_nodes([0, 1, 2, 3, 0], [0, 30, 500, 13000, 0], 10, [1, 0, 0, 0, 1])
    (angles, ranges), = ScanParser(0.05, 12.0).feed(data)
    assert np.isinf(ranges).sum() == 3 and np.isfinite(ranges).sum() == 1


def test_resync_after_garbage_mid_stream():
    clean = revolutions(3)
    cut = 5 * 450 + 2
    garbled = clean[:cut] + bytes([0xFF, 0x00, 0x13]) + clean[cut:]
    p = ScanParser()
    scans = p.feed(garbled)
    assert p.resyncs >= 1
    assert len(scans) == 3
    assert scans[2][0].size == 400  # the revolution after the garbage is whole


@settings(max_examples=120, deadline=None)
@given(st.binary(max_size=300), st.integers(0, 4), st.lists(st.integers(1, 97), max_size=8))
def test_random_bytes_never_raise_and_the_stream_resynchronises(garbage, skew, cuts):
    """Garbage (plus a partial node) before a clean stream: the parser never raises, and the
    revolutions after it are exact."""
    stream = garbage + revolutions(1, 200)[skew:] + revolutions(2, 200)
    p = ScanParser()
    scans, pos = [], 0
    for c in cuts:
        scans += p.feed(stream[pos:pos + c])
        pos += c
    scans += p.feed(stream[pos:])
    assert len(scans) >= 2
    for angles, ranges in scans[-2:]:
        assert angles.size == 200
        assert np.all(np.isfinite(ranges))
