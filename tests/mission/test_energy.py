"""The energy budget (mission.patrol.energy) on readings made up here, and the dock in world files."""
from __future__ import annotations

import math

import numpy as np
import pytest
import yaml

from hw.errors import InputError
from hw.interfaces import PowerReading
from hw.odometry import Pose2D
from mission.patrol.config import EnergyConfig
from mission.patrol.energy import EnergyBudget
from mission.patrol.mission_file import mission_from_world
from sim.config import BatteryConfig
from sim.world import dump_world, load_default_world, parse_world

PACK = BatteryConfig(capacity_ah=1.0)


def straight(origin, points: np.ndarray) -> np.ndarray:
    return np.hypot(*(np.asarray(points, float) - np.asarray(origin, float)).T)


def budget(**config) -> EnergyBudget:
    return EnergyBudget(EnergyConfig(**config), PACK, 0.5, (0.0, 0.0), straight)


def resting(charge: float) -> float:
    return PACK.empty_voltage + (PACK.full_voltage - PACK.empty_voltage) * charge


def test_the_charge_starts_from_the_resting_voltage_and_counts_the_current_out_and_in():
    b = budget()
    b.sample(PowerReading(0.0, resting(0.8) - PACK.internal_resistance * 2.0, 2.0), Pose2D())
    assert b.charge == pytest.approx(0.8)
    b.sample(PowerReading(360.0, 12.0, 2.0), Pose2D())  # 2 A for 0.1 h: 0.2 Ah of the 1 Ah pack
    assert b.charge == pytest.approx(0.6) and not b.charging
    b.sample(PowerReading(540.0, 12.5, -2.0), Pose2D())  # the dock's charger: current into the pack
    assert b.charge == pytest.approx(0.7) and b.charging and b.lowest == pytest.approx(0.6)
    b.sample(PowerReading(540.0, 12.5, -2.0), Pose2D())  # a reading already taken changes nothing
    assert b.charge == pytest.approx(0.7)


def test_what_driving_costs_is_learned_from_the_current_while_driving():
    b = budget()
    prior = b.drive.per_unit
    b.sample(PowerReading(0.0, resting(1.0), 0.0), Pose2D())
    for k in range(1, 1001):  # 100 m at 0.2 m/s, 6 A
        b.sample(PowerReading(k * 0.5, 12.0, 6.0), Pose2D(0.1 * k, 0.0, 0.0))
    measured = 6.0 / 0.2 / 3600.0
    assert abs(b.drive.per_unit - measured) < abs(prior - measured) / 5


def test_a_pot_too_far_for_the_charge_left_sends_the_robot_home_and_says_why():
    b = budget(reserve=0.15, margin=1.0)
    b.sample(PowerReading(0.0, resting(0.5), 0.0), Pose2D())
    per_m = b.way(1.0)
    near = 0.3 / per_m / 2  # the way there and back costs 30 % of the pack
    assert b.check_pot((0.0, 0.0), (near, 0.0)) == "" and b.projected == pytest.approx(0.5 - 0.3 - b.pot())
    far = 0.4 / per_m / 2
    why = b.check_pot((0.0, 0.0), (far, 0.0))
    assert "reserve" in why and "50%" in why
    assert b.check_home((far, 0.0)) == ""  # from there the dock (20 % away) is still within reach
    assert "faster than planned" in b.check_home((0.45 / per_m, 0.0))


def test_a_world_may_name_its_dock_and_the_mission_goes_home_there():
    world = load_default_world()
    assert world.dock_pose == world.spawn and mission_from_world(world).home.x == 0.0
    data = yaml.safe_load(dump_world(world))
    data["dock"] = {"x": 1.0, "y": 1.5, "yaw": math.pi / 2}
    docked = parse_world(data, "w.yaml")
    home = mission_from_world(docked).home
    assert (home.x, home.y, home.yaw) == pytest.approx((0.0, 1.0, math.pi / 2))
    assert "dock" in dump_world(docked)
    data["dock"] = {"x": 2.0, "y": 1.0}  # on pot P01
    with pytest.raises(InputError, match=r"w\.yaml: dock overlaps pots\[0\]"):
        parse_world(data, "w.yaml")
