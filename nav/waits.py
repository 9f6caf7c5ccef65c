"""The goal's waits for people and for room (issue 28 item 2), the navigator's side of them.

Each is asked by ``Navigator.tick_control`` before it follows its plan, and each either lets the
goal go on (False) or holds it (True), counting the wait against ``person_wait`` or
``blocked_wait`` through the navigator's ``_hold`` and publishing what the robot does meanwhile
(zero, or a step out of the way from ``nav.people_nearby``). Why each exists is in
``nav.navigator``'s docstring; a mixin, so the navigator module stays the goal's life and these
its pauses.
"""
from __future__ import annotations

import logging
import math

import numpy as np

from hw.interfaces import ZERO_TWIST, Twist
from hw.odometry import Pose2D
from nav.people_nearby import NEAR_SPEED
from nav.planner import PlanningError

log = logging.getLogger("nav.navigator")

#: Why the goal holds while the robot steps out of a walker's lane (``waiting_for``).
LANE = "out of a walker's way"
#: The same for a track on another robot of the fleet (``_whom``).
ROBOT_LANE = "out of a robot's way"
#: Nearer its goal than this, m, the robot finishes its approach (the last centimetres and the
#: turn onto the goal's heading) rather than step out of a walker's lane or wait for someone in
#: the only way or walking onto its goal (someone *on* it, or a crate taken for a person, is
#: still waited for, ``mission.patrol.aside`` then looks from beside it): it stands there next, still, as it would stepping aside, and the
#: people guard (``hw.people_guard``: 0.15 m/s within 1 m, nothing towards anyone within 0.5 m,
#: still within 0.25 m) and the collision monitor below it bind that last motion as any other.
#: safety.people seed 1, 105 s: 7 cm from P32's approach pose in a 0.8 m aisle a cart pusher
#: paces, the robot stepped back out of the aisle as the cart turned 3 m off at the far end, and
#: so each time it came back; P32's aisle cost 680 s and six pots. Seed 107, 881 s: 0.14 m from
#: P18's pose, facing away from the pot, it stepped out again as the walker pacing that aisle
#: turned 1 m off (until stop 56 it finished only with everyone beyond ``wait_clearance``), and
#: so at every turn of theirs: the middle pots of an aisle someone paces failed in every patrol
#: (safety.people stop 55: 14 of its 20 failed pots). A person who yields stops for a robot
#: standing still; the rules bind its moving (issue 28 item 2).
FINISH = 0.25
#: Held this long (s) without a break while it steps out of the way, the robot steps away from
#: the people holding it instead, for ``ESCAPE_TIME`` (``hw.people_guard``'s
#: ``escape``: safety.people seed 113, 675-3,074 s, held still between a worker and a cart
#: that waited for it). Longer than a tick or two of the guard trimming a step, well short of
#: ``person_wait``.
ESCAPE_AFTER = 3.0
#: How long one escape lasts, s: about 0.3 m at ``NEAR_SPEED``, out of a person's reach.
ESCAPE_TIME = 2.0


class Waits:
    """Mixed into ``nav.navigator.Navigator``: reads its ``io``, ``people``, ``goal``,
    ``local_costmap``, ``global_costmap``, ``planner``, ``smoother`` and ``config``."""

    def _boxed_in(self, now: float, dt: float) -> bool:
        """While every cell round the robot is taken (``StartBlocked``: someone against it), hold
        still for up to ``blocked_wait``, replanning at 1 Hz, instead of failing goal after goal
        in a blink. True while waiting or when the wait ran out."""
        if not self._start_blocked:
            return False
        if not self._hold(now, dt, "boxed in: every cell round the robot is taken"):
            self.io.publish(ZERO_TWIST, now)
        return True

    def _waiting(self, now: float, dt: float) -> bool:
        """While the collision monitor holds the base, the goal's clocks (its deadline and its
        progress check) stop, for at most ``blocked_wait`` seconds of holding in all: a person
        who keeps stepping in and out of the way adds up. True when that ran out and the goal
        failed ``blocked``. When what holds it is a person (within ``wait_clearance``: a grower
        who stopped for the robot, waiting for it to leave their way), the robot steps back
        from them instead of pressing on, for up to ``person_wait``: pressing on, robot and
        grower waited for each other until the goal failed."""
        if self._escaping(now, dt):
            return True
        if not self.io.held():
            return False
        back = self._evade(self.people.layer.wait_clearance) if self.people.counted() else ZERO_TWIST
        if back == ZERO_TWIST:
            return self._hold(now, dt, "something in the way")
        self.smoother.reset()
        if not self._hold(now, dt, "a person close by", self.config.navigator.person_wait):
            self.io.publish(back, now)
        return True

    def _escaping(self, now: float, dt: float) -> bool:
        """Held ``ESCAPE_AFTER`` on end, take the guard's step away from the people holding the
        robot for ``ESCAPE_TIME`` (while there is such a step); True while stepping."""
        step = ZERO_TWIST
        if not self.io.held():
            self._held_since = None
        elif self._held_since is None:
            self._held_since = now
        elif now - self._held_since > ESCAPE_AFTER:
            self._held_since, step = None, self.io.escape(NEAR_SPEED)
            if step != ZERO_TWIST:  # held by people, not by a pot or a wall
                self._escape_until = now + ESCAPE_TIME
                log.info("held %.0f s by people close by: stepping away from them all", ESCAPE_AFTER)
        if step == ZERO_TWIST and now < self._escape_until:
            step = self.io.escape(NEAR_SPEED)
        if step == ZERO_TWIST:
            self._escape_until = -math.inf
            return False
        self.smoother.reset()
        if not self._hold(now, dt, "a person close by", self.config.navigator.person_wait):
            self.io.publish(step, now)
        return True

    def _waiting_for_people(self, now: float, dt: float) -> bool:
        """Hold still while a person stands in the only way or on the goal (module docstring).
        True while waiting (zero twist published) or when the wait ran out."""
        why, finishing = "", self._finishing()  # ``FINISH``: only someone on the goal now holds it
        if self._person_blocks and not finishing:
            why = f"{self._whom()} in the only way"
        elif self.people.in_keep_out(self.goal.x, self.goal.y, ahead=not finishing):
            why = f"{self._whom()} at the goal"
        if why != self.waiting_for:
            if why:
                log.info("waiting: %s", why)
            self.waiting_for = why
        if not why:
            return False
        self.smoother.reset()
        if not self._hold(now, dt, why, self.config.navigator.person_wait):  # at a distance: ``wait_clearance``
            self.io.publish(self._evade(self.people.layer.wait_clearance), now)
        return True

    def _out_of_a_lane(self, now: float, dt: float) -> bool:
        """Step out of the lane of someone walking this way while they are still metres off
        (``nav.people_nearby``); True while stepping (or when the wait ran out)."""
        if not self.people.in_lane(self.io.odom_pose()) or self._finishing():
            return False
        why = LANE if self._whom() == "a person" else ROBOT_LANE
        if self.waiting_for != why:
            log.info("waiting: %s", why)
            self.waiting_for = why
        self.smoother.reset()
        if not self._hold(now, dt, why, self.config.navigator.person_wait):
            self.io.publish(self._evade(reach=self.people.layer.lane_time), now)
        return True

    def _straight_in(self, pose: Pose2D) -> bool:
        """Within ``FINISH`` of the goal with only people blocking the plan (their keep-outs, a
        paused walker's whole walk, cover it): the rest of the way is the straight line in, for
        MPPI and the guard to drive. True when it is."""
        if not (self._person_blocks and self._finishing()):
            return False
        self.path = np.array([[pose.x, pose.y], [self.goal.x, self.goal.y]])
        return True

    def _finishing(self) -> bool:
        """Is the robot within ``FINISH`` of its goal?"""
        pose = self.map_pose()
        return math.hypot(pose.x - self.goal.x, pose.y - self.goal.y) < FINISH

    def _whom(self) -> str:
        """Who a wait for people waits for, in its words: "a robot" when everyone counted stands
        near where another robot of the fleet says it is (``nav.costmap.robots.PEER_REACH``)."""
        people, robots = self.people.in_map(), self.global_costmap.robots
        if people and robots is not None and all(robots.near(float(a[0]), float(a[1])) for a, _, _ in people):
            return "a robot"
        return "a person"

    def _person_close(self) -> bool:
        """Is the robot itself inside a person's keep-out (they came to it, or are coming)?"""
        pose = self.map_pose()
        return self.people.in_keep_out(pose.x, pose.y)

    def _evade(self, clearance: float | None = None, reach: float | None = None) -> Twist:
        return self.people.evade(self.io.odom_pose(), self.local_costmap.without_people(), clearance, reach)

    def _only_people_block(self, pose: Pose2D) -> bool:
        """With people about, would there be a plan once they stepped aside (or is the robot in
        a person's keep-out, so that no plan can start)?"""
        if not self.people.in_map():
            return False
        if self._person_close():
            return True
        try:
            self.planner.plan(self.global_costmap.without_people(), (pose.x, pose.y), (self.goal.x, self.goal.y))
        except PlanningError:
            return False
        return True
