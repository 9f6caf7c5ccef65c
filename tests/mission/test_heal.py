"""The boot heal on the simulated robot: each broken state, the tri-state, the arm park."""
import pytest

from arm.presets import preset
from hw.controller_manager import ControllerState, ControllerTransitionError
from lupin.cli import main
from mission.runtime.heal import ACTIONS, boot_heal, heal_controllers
from lupin.cli.heal import sim_boot_race
from tests.fixtures import assemble, open_floor

NAMES = ("joint_state_broadcaster", "pid_wheels_controller", "mirte_master_arm_controller",
         "mirte_master_gripper_controller", "mirte_base_controller")


@pytest.fixture
def rig():
    sim, robot = assemble(open_floor())
    calls = []
    robot.controllers.subscribe(lambda name, old, new: calls.append((name, old.value, new.value)))
    yield sim, robot, calls
    sim.close()


@pytest.mark.slow
def test_the_five_controllers_are_the_seeds():
    sim, robot = assemble(open_floor())
    try:
        assert tuple(robot.config.hw.controllers) == NAMES
    finally:
        sim.close()


@pytest.mark.slow
@pytest.mark.parametrize("state, actions", [
    ("missing", ["load", "configure", "activate"]),
    ("unconfigured", ["configure", "activate"]),
    ("inactive", ["activate"]),
])
def test_each_broken_state_gets_exactly_what_it_needs_then_the_arm_is_homed(rig, state, actions):
    sim, robot, calls = rig
    sim.faults.controller_race(["mirte_master_arm_controller", "pid_wheels_controller"], state)
    calls.clear()
    report = boot_heal(robot, env={})
    assert report.healed is True and report.homed and report.exit_code == 0
    assert report.before["mirte_master_arm_controller"] is ControllerState(state)
    assert report.actions == [("pid_wheels_controller", a) for a in actions] + \
        [("mirte_master_arm_controller", a) for a in actions]
    assert robot.controllers.all_active()
    for j, q in preset("home").items():
        assert sim.servos.joint_position(j) == pytest.approx(q, abs=0.05)


@pytest.mark.slow
def test_nothing_broken_means_no_actions(rig):
    sim, robot, calls = rig
    report = boot_heal(robot, env={})
    assert report.healed is True and report.actions == [] and calls == []


@pytest.mark.slow
def test_unreadable_states_issue_no_load_or_switch_and_exit_0(rig):
    sim, robot, calls = rig
    sim.faults.controller_race(["mirte_base_controller"], "inactive")
    calls.clear()
    asked = []

    def wedged():  # list_controllers that never answers inside its timeout
        asked.append(robot.scheduler.clock.now())
        raise TimeoutError("list_controllers timed out")

    t0 = robot.scheduler.clock.now()
    report = boot_heal(robot, env={}, list_states=wedged, budget=3.0)
    assert report.healed is None and report.exit_code == 0
    assert calls == [] and report.actions == []  # zero load / configure / switch calls
    assert robot.controllers.state("mirte_base_controller") is ControllerState.INACTIVE
    assert "UNREADABLE" in report.message and "NO load or switch" in report.message
    assert len(asked) >= 3 and asked[-1] - t0 <= 3.0  # it polled, within the budget
    assert not report.homed


@pytest.mark.slow
def test_garbage_answers_count_as_unreadable(rig):
    sim, robot, calls = rig
    report = heal_controllers(robot.controllers, NAMES, robot.scheduler.clock, lambda: None, budget=1.0)
    assert report.healed is None and calls == []


@pytest.mark.slow
def test_a_controller_that_will_not_activate_is_false_exit_1(rig):
    sim, robot, calls = rig
    sim.faults.controller_race(["mirte_base_controller"], "unconfigured")
    real = robot.controllers.activate

    def broken_activate(name):
        if name == "mirte_base_controller":
            raise ControllerTransitionError("switch failed")
        real(name)

    robot.controllers.activate = broken_activate
    report = boot_heal(robot, env={})
    assert report.healed is False and report.exit_code == 1
    assert report.after["mirte_base_controller"] is ControllerState.INACTIVE
    assert "mirte_base_controller inactive" in report.message
    assert not report.homed  # no park unless every controller is active


@pytest.mark.slow
def test_auto_home_false_skips_everything(rig):
    sim, robot, calls = rig
    sim.faults.controller_race(["mirte_base_controller"], "missing")
    calls.clear()
    report = boot_heal(robot, env={"LUPIN_AUTO_HOME": "false"})
    assert report.skipped and report.exit_code == 0 and calls == []


@pytest.mark.slow
def test_a_latched_lift_fails_the_park(rig):
    sim, robot, calls = rig
    robot.scheduler.run_for(0.3)
    sim.faults.servo_stall("shoulder_lift", mode="latch")
    sim.servos.place({"shoulder_lift": -0.5})  # latched away from home
    report = boot_heal(robot, env={})
    assert report.healed is True and not report.homed and report.exit_code == 1
    assert "power cycle" in report.message


def test_sim_boot_race_is_seeded_and_always_breaks_something():
    for seed in range(20):
        race = sim_boot_race(NAMES, seed)
        assert race and set(race) <= set(NAMES) and race == sim_boot_race(NAMES, seed)
        assert all(s in ACTIONS and s is not ControllerState.ACTIVE for s in race.values())


@pytest.mark.slow
def test_cli_heals_the_sim_and_exits_0(capsys):
    assert main(["heal", "--backend", "sim"]) == 0
    out = capsys.readouterr().out
    assert "arm parked at home" in out and "=> active" in out


def test_cli_auto_home_false(monkeypatch, capsys):
    monkeypatch.setenv("LUPIN_AUTO_HOME", "false")
    assert main(["heal"]) == 0
    assert "skipped" in capsys.readouterr().out


def test_cli_bad_backend_is_exit_2(capsys):
    assert main(["heal", "--backend", "ros"]) == 2
