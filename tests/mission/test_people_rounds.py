"""A pot people kept the robot from is tried again after the others, up to ``people_rounds``
goes; any other failure once (mission.patrol.leg_plan.goes_again)."""
from __future__ import annotations

from mission.patrol.config import PatrolConfig
from mission.patrol.leg_plan import goes_again, later_label

ROUNDS = PatrolConfig().people_rounds
PEOPLE = "approach P30: blocked: a person in the only way for 60 s"
OTHER = "approach P30: no progress: moved less than 0.1 m in 20 s, 0.60 m from the goal"


def goes(why: str, searched: bool = False) -> int:
    """How many goes after the others a pot gets when every go fails saying ``why``."""
    later = 0
    while goes_again(later, ROUNDS, why, searched):
        later += 1
    return later


def test_a_pot_people_keep_the_robot_from_gets_people_rounds_goes_after_the_others():
    assert ROUNDS > 1 and goes(PEOPLE) == ROUNDS


def test_any_other_failure_gets_one_go_after_the_others_and_a_pot_not_found_none():
    assert goes(OTHER) == 1
    assert goes(PEOPLE, searched=True) == 0


def test_a_later_go_that_fails_for_another_reason_ends_the_pot():
    assert goes_again(1, ROUNDS, PEOPLE, False) and not goes_again(1, ROUNDS, OTHER, False)


def test_the_goes_are_named_apart():
    assert [later_label("P30", k) for k in range(3)] == ["P30", "P30 later", "P30 later 2"]
