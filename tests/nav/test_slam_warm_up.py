"""The SLAM worker compiles its rare kernels before its first scan (nav/slam/worker.py
``warm_up``): compiled mid-patrol on a busy machine, one cost more CPU than ``reply_timeout`` and
the worker was killed as spinning. Run in a fresh interpreter, so nothing else compiled them."""
from __future__ import annotations

import subprocess
import sys

PROBE = """
from nav.slam import planar_icp, relocate
from nav.slam.config import SlamConfig
from nav.slam.worker import warm_up
rare = (planar_icp._place, planar_icp._drop_far, planar_icp._align, relocate._raster_scores, relocate._scores)
assert not any(k.signatures for k in rare)
warm_up(SlamConfig())
print([k.__name__ for k in rare if not k.signatures])
"""


def test_warm_up_compiles_the_rare_kernels_before_the_first_scan():
    out = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[]"
