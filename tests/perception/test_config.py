"""Perception config: defaults from the seed and upstream, calibrations all-or-none."""
from __future__ import annotations

import numpy as np
import pytest
from pydantic import ValidationError

from mission.runtime.config import load_config
from perception.config import CameraModelConfig, PerceptionConfig


def test_defaults_are_the_upstream_numbers():
    c = PerceptionConfig()
    assert c.tag.whitelist == tuple(range(22)) and c.tag.tag_size == 0.10
    assert c.flower.min_area_px == 150 and c.flower.kernel_px == 5 and c.flower.confidence_area_px == 2000
    assert c.flower.bug.v_hi == 49
    assert (c.flower.classes["red"].h_lo, c.flower.classes["red"].h_hi, c.flower.classes["red"].s_lo) == (150, 8, 150)
    assert list(c.flower.classes) == ["red", "white", "pink"]


def test_a_calibration_overrides_the_field_of_view():
    cal = CameraModelConfig(fx=600.0, fy=602.0, cx=330.0, cy=250.0, distortion=(0.1, -0.2, 0.0, 0.0))
    assert np.array_equal(cal.matrix(), [[600, 0, 330], [0, 602, 250], [0, 0, 1]])
    assert cal.dist_coeffs().shape == (4,)
    with pytest.raises(ValidationError, match="fx, fy, cx, cy"):
        CameraModelConfig(fx=600.0)
    with pytest.raises(ValidationError, match="distortion"):
        CameraModelConfig(distortion=(0.1, 0.2))


def test_environment_overrides_reach_perception():
    c = load_config(env={"LUPIN_PERCEPTION__FLOWER__MIN_AREA_PX": "300", "LUPIN_PERCEPTION__RATES__FRONT": "5"})
    assert c.perception.flower.min_area_px == 300 and c.perception.rates.front == 5.0


def test_unknown_keys_are_errors():
    with pytest.raises(ValidationError):
        PerceptionConfig.model_validate({"flower": {"min_area": 3}})
