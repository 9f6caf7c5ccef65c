import pytest

from hw.config import HwConfig
from hw.controller_manager import ControllerManager, ControllerState, ControllerTransitionError

NAMES = HwConfig().controllers
S = ControllerState


def test_all_five_start_active_by_default():
    cm = ControllerManager(NAMES)
    assert len(cm.names) == 5
    assert cm.states() == {n: S.ACTIVE for n in NAMES}
    assert all(cm.is_active(n) for n in NAMES) and cm.all_active()


def test_initial_mapping_sets_some_and_leaves_rest_active():
    cm = ControllerManager(NAMES, {"pid_wheels_controller": "missing"})
    assert cm.state("pid_wheels_controller") is S.MISSING
    assert cm.state("mirte_base_controller") is S.ACTIVE
    assert not cm.all_active()


def test_states_are_str_valued():
    assert S.UNCONFIGURED == "unconfigured" and S("inactive") is S.INACTIVE


def test_full_lifecycle_path():
    cm = ControllerManager(NAMES, S.MISSING)
    n = "pid_wheels_controller"
    cm.load(n)
    assert cm.state(n) is S.UNCONFIGURED
    cm.configure(n)
    assert cm.state(n) is S.INACTIVE
    cm.activate(n)
    assert cm.is_active(n)
    cm.deactivate(n)
    assert cm.state(n) is S.INACTIVE


@pytest.mark.parametrize(
    "start, action",
    [
        (S.ACTIVE, "load"),
        (S.INACTIVE, "load"),
        (S.MISSING, "configure"),
        (S.ACTIVE, "configure"),
        (S.MISSING, "activate"),
        (S.UNCONFIGURED, "activate"),
        (S.ACTIVE, "activate"),
        (S.INACTIVE, "deactivate"),
        (S.MISSING, "deactivate"),
    ],
)
def test_illegal_transitions_raise_and_change_nothing(start, action):
    cm = ControllerManager(NAMES, start)
    with pytest.raises(ControllerTransitionError, match=f"cannot {action} controller 'mirte_base_controller'"):
        getattr(cm, action)("mirte_base_controller")
    assert cm.state("mirte_base_controller") is start


def test_unknown_controller():
    cm = ControllerManager(NAMES)
    with pytest.raises(KeyError, match="unknown controller 'nope'"):
        cm.activate("nope")
    with pytest.raises(KeyError):
        ControllerManager(NAMES, {"nope": S.MISSING})


def test_force_is_the_boot_race_and_heal_undoes_it():
    cm = ControllerManager(NAMES)
    changes = []
    cm.subscribe(lambda n, old, new: changes.append((n, old, new)))
    cm.force("mirte_base_controller", "unconfigured")
    cm.force("pid_wheels_controller", S.MISSING)
    cm.force("joint_state_broadcaster", S.ACTIVE)  # no change, no notification
    assert changes == [
        ("mirte_base_controller", S.ACTIVE, S.UNCONFIGURED),
        ("pid_wheels_controller", S.ACTIVE, S.MISSING),
    ]
    assert cm.heal("pid_wheels_controller") == ["load", "configure", "activate"]
    assert cm.heal("mirte_base_controller") == ["configure", "activate"]
    assert cm.heal("joint_state_broadcaster") == []
    assert cm.all_active()
    assert len(changes) == 2 + 3 + 2


def test_duplicate_names_rejected():
    with pytest.raises(ValueError):
        ControllerManager(["a", "a"])
