"""The pinhole camera matrix from a field of view."""
from __future__ import annotations

import math

import numpy as np
import pytest

from hw.camera_model import camera_matrix


def test_a_ray_at_the_edge_of_the_fov_lands_on_the_frame_edge():
    k = camera_matrix(640, 480, 49.5)
    half = math.radians(49.5) / 2
    top = k @ np.array([0.0, -math.tan(half), 1.0])      # the top edge of the view ...
    assert top[1] == pytest.approx(-0.5)                  # ... is the top edge of pixel row 0
    assert k[0, 0] == k[1, 1] and (k[0, 2], k[1, 2]) == (319.5, 239.5)


def test_bad_arguments():
    for args in ((0, 480, 50.0), (640, 480, 0.0), (640, 480, 180.0)):
        with pytest.raises(ValueError):
            camera_matrix(*args)
