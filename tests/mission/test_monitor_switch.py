"""No silent off switch (issue 28 item 6): on the robot the collision monitor is turned off only
by ``--no-collision-monitor``, which is logged at ERROR at start and every minute on the runtime
clock; a config turning it off is refused there before a device opens; the sim allows it with a
warning."""
from __future__ import annotations

import logging
from contextlib import ExitStack

import pytest

from hw.backend import HwBackend
from hw.errors import InputError
from lupin.cli import main
from mission.runtime.config import LupinConfig
from mission.runtime.robot import build_robot, check_monitor_switch
from mission.runtime.scheduler import Scheduler
from sim.clock import SimClock
from tests.hw.emulated import emulated_robot

OFF = {"hw": {"collision_monitor": {"enabled": False}}}


def test_a_config_turning_the_monitor_off_is_refused_on_the_robot_only():
    off = LupinConfig.model_validate(OFF)
    with pytest.raises(InputError, match="--no-collision-monitor"):
        check_monitor_switch(off, on_robot=True, monitor_off=False)
    assert check_monitor_switch(off, on_robot=False, monitor_off=False) is off
    by_option = check_monitor_switch(LupinConfig(), on_robot=True, monitor_off=True)
    assert by_option.hw.collision_monitor.enabled is False


def test_the_serve_command_refuses_it_before_any_device_opens(tmp_path, capsys):
    cfg = tmp_path / "robot.yaml"
    cfg.write_text("hw:\n  collision_monitor:\n    enabled: false\n")
    assert main(["--config", str(cfg), "serve", "--backend", "hw", "--history", "none"]) == 2
    err = capsys.readouterr().err
    assert "hw.collision_monitor.enabled is false" in err and "--no-collision-monitor" in err
    assert main(["serve", "--backend", "sim", "--no-collision-monitor"]) == 2  # the option is the robot's


def test_turned_off_on_the_robot_it_is_an_error_at_start_and_every_minute(tmp_path, caplog):
    with ExitStack() as stack:
        emu = emulated_robot(stack, tmp_path)
        backend = stack.enter_context(HwBackend(emu.config, **emu.boundaries()))
        robot = build_robot(LupinConfig(hw=emu.config), backend.hal, on_robot=True, monitor_off=True)
        robot.scheduler = Scheduler(SimClock())  # the runtime clock, run ahead of the wall
        with caplog.at_level(logging.ERROR, logger="lupin"):
            robot.start()
            robot.scheduler.run_until(150.0)
        robot.close()
    offs = [r for r in caplog.records if r.levelno == logging.ERROR and "COLLISION MONITOR OFF" in r.getMessage()]
    assert len(offs) == 3  # at 0, 60 and 120 s
    assert robot.monitor.config.enabled is False


@pytest.mark.slow
def test_in_the_sim_it_is_allowed_with_one_warning(caplog):
    from tests.fixtures import assemble, open_floor

    with caplog.at_level(logging.WARNING, logger="lupin"):
        sim, robot = assemble(open_floor(), LUPIN_HW__COLLISION_MONITOR__ENABLED="false")
        robot.scheduler.run_until(0.5)
    sim.close()
    robot.close()
    warned = [r for r in caplog.records if "collision monitor off" in r.getMessage()]
    assert len(warned) == 1 and warned[0].levelno == logging.WARNING
