import numpy as np
import pytest

from arm import limits
from arm.presets import ARM_JOINTS, PRESETS, UnknownPreset, move_duration, preset
from hw.errors import InputError


SEED = {
    "home": (0.04, -0.01, 0.01, -1.57), "zero": (0, 0, 0, 0), "tuck": (0, -1.40, 1.40, 0),
    "pick": (0, -0.60, 0.80, -0.40), "place": (0, 0.20, 0.80, -0.40), "inspect": (0, -0.40, 0.90, -0.80),
}


def test_the_seed_table_exactly():
    assert ARM_JOINTS == ("shoulder_pan", "shoulder_lift", "elbow", "wrist")
    assert {name: PRESETS[name] for name in SEED} == SEED  # the seed's values, by their names
    assert set(PRESETS) - set(SEED) == {"inspect_plant"}  # and Lupin's one addition
    assert list(preset("inspect").items()) == list(zip(ARM_JOINTS, PRESETS["inspect"]))


def test_every_preset_is_inside_the_joint_windows_with_room_to_sag():
    for name, q in PRESETS.items():
        assert limits.within(q), name
    # the patrol's view: 0.05 rad (the dead-band a sag may reach) from every window edge
    assert limits.within(np.asarray(PRESETS["inspect_plant"]) + 0.05) and limits.within(np.asarray(PRESETS["inspect_plant"]) - 0.05)


def test_unknown_name_is_a_clear_input_error():
    with pytest.raises(UnknownPreset, match=r"unknown arm preset 'inpsect'; known: home, zero, tuck, pick, place, inspect, "
                                           r"inspect_plant"):
        preset("inpsect")
    assert issubclass(UnknownPreset, InputError)


def test_duration_follows_the_slowest_joint_at_max_speed():
    assert move_duration(PRESETS["home"], PRESETS["inspect"], 0.5, 0.1) == pytest.approx(0.89 / 0.5)
    assert move_duration(PRESETS["zero"], PRESETS["tuck"], 0.7, 0.1) == pytest.approx(2.0)
    assert move_duration(PRESETS["zero"], PRESETS["zero"], 0.7, 0.5) == 0.5
