"""Patrol settings: the beat of the tree, the waits around the cameras, what counts as a pot's tag."""
from __future__ import annotations

from pydantic import BaseModel, ConfigDict, Field, field_validator

from arm.presets import PRESETS


class EnergyConfig(BaseModel):
    """The patrol's energy budget (``mission.patrol.energy``, issue 31): when to head home, how
    far to charge, how many trips. What the robot's work costs starts from the sim's battery
    model (``sim.battery``: its capacity, voltages, idle and motor currents) and is refined from
    the power monitor's current as the robot works."""

    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)

    reserve: float = Field(0.15, ge=0, lt=1)
    """Charge the robot must still have when it reaches the dock, share of the pack: a LiPo
    drawn below ~15 % ages fast and its voltage falls off a cliff, and it leaves room for a
    detour the plan did not see."""
    margin: float = Field(1.3, ge=1)
    """What a pot and the way home are expected to cost is multiplied by this before it is held
    against the charge: the driven path is longer than the planner's straight-celled one
    (detours round people, re-approaches), and the costs are averages."""
    charge: bool = True
    """The dock charges the robot (``lupin patrol --no-charge``: it does not; a patrol that
    needs more than one charge then ends ``battery_low`` at the dock, listing what is left)."""
    charge_to: float = Field(0.95, gt=0, le=1)
    """Charge to wait for on the dock before the next leg: the last 5 % of a CC-CV charge take
    as long as the 20 % before them."""
    charge_start_timeout: float = Field(60.0, gt=0)
    """Seconds on the dock without current into the pack before the robot says it is not
    charging (a dock it missed, a charger off) and ends the patrol ``battery_low``."""
    max_legs: int | None = Field(None, ge=1)
    """Trips out from the dock (``lupin patrol --max-legs N``); None: as many as it takes."""
    pot_seconds: float = Field(10.0, gt=0)
    """Seconds the robot is expected to stand still at a pot before it has stood at any (the tag,
    the wrist frame; the arm moves while the base turns: 3-5 s in the sim's default patrol, more
    where people hold it); then the mean of the last pots it did."""
    check_every: float = Field(1.0, gt=0)
    """Seconds between checks that the robot can still reach the dock with the reserve (one
    wavefront from the dock over the map each time): a pack draining faster than the model said
    sends it home within a second."""


class PatrolConfig(BaseModel):
    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)

    tick_rate: float = Field(10.0, gt=0)
    """Tree ticks per second, Hz: the controllers' 10 Hz beat; every leaf only polls, so a
    faster tick buys nothing but Python time."""
    travel_pose: str = "home"
    """Arm preset between pots: ``home``, the measured minimum-gravity rest pose. Not the seed's
    ``tuck`` ("folded for travel"): folded, the arm hangs in front of the front camera and hides
    the tag plate at every approach pose (seen in the sim's front frames)."""
    inspect_pose: str = "inspect_plant"
    """Arm preset the wrist frame is taken from at the ideal approach pose (and the reference the
    IK look stays nearest to elsewhere): ``inspect_plant``, which holds the whole plant top in
    the frame under the arm's real sag, not the seed's ``inspect``, which frames the plant's
    front edge and loses a back bloom or leaf when the arm sags (arm/presets.py; issue 30: the
    bloom was in view in 51 % of the ``perception.flower`` frames)."""
    @field_validator("inspect_pose")
    @classmethod
    def _a_preset(cls, name: str) -> str:
        if name not in PRESETS:
            raise ValueError(f"unknown arm preset {name!r}; known: {', '.join(PRESETS)}")
        return name

    arm_timeout: float = Field(15.0, gt=0)
    """Seconds for one arm move to arrive (a full-span move at 0.6 rad/s takes ~3 s)."""
    settle: float = Field(0.3, ge=0)
    """Seconds after the arm (or the base) stopped before a frame counts, so nothing is judged
    on a frame still swinging."""
    frame_timeout: float = Field(3.0, gt=0)
    """Seconds to wait for a fresh camera frame before the step fails (a 2 Hz camera gives one
    in 0.5 s)."""
    startup_timeout: float = Field(30.0, gt=0)
    """Seconds for the start-up gate (heal, readiness cascade) before the patrol fails: above
    the cascade's own 20 s ceiling, which names the missing stage first."""
    aim_xy: float = Field(0.03, gt=0)
    """The robot stopped this far (m) from its ideal approach pose, by its own belief: aim the
    wrist camera with IK at where ``inspect_pose`` would have looked, instead of taking it.
    Inside the goal checker's 0.25 m tolerance a bloom can leave the inspect frame (the
    perception bench shows it at the tolerance's edge)."""
    aim_yaw: float = Field(0.05, gt=0)
    """The same, for the heading error, rad."""
    bloom_height: float = Field(0.26, gt=0)
    """Height of the blooms above base_link, m: the plane the inspect view is aimed at (sim: pot
    0.25 m + bloom 0.062 m, base_link 0.051 m above the floor)."""
    tag_max_distance: float = Field(0.6, gt=0)
    """A tag read nearer than this from the approach pose is the pot's own (its plate is ~0.27 m
    from the front camera there; the next pot's is >= 0.9 m away)."""
    front_camera_mount: tuple[float, float, float] = (0.1625, 0.0, 0.15)
    """Front camera optical centre in base_link, m (the model's mount; on the robot: its URDF),
    looking along +x: places the tags it reads in the map."""
    plate_offset: float = Field(0.104, gt=0)
    """From a tag's printed face to its pot's centre along the pot's facing, m: the pot's radius
    and the plate's thickness (sim: 0.10 m pot, 3 mm card, 1 mm print). A tag read then places its
    pot (``mission.patrol.tag_sightings``)."""
    pot_radius: float = Field(0.10, gt=0)
    """The pots' radius, m (sim: 0.10 m): the lidar sees one side of a pot, and a circle this size
    fitted to it puts the pot's centre in the map (``nav.viewpoints``) for the survey's looks and
    the search for a pot not where the mission says."""
    moved_xy: float = Field(0.05, gt=0)
    """A pot its tag places farther than this from the mission's position has moved, m: the
    robot approaches it again from where it is and the report says ``moved`` (a tag read at the
    approach pose places its pot to about a centimetre, so an unmoved pot never trips it)."""
    moved_yaw: float = Field(0.15, gt=0)
    """... or turned by more than this, rad."""
    drift_radius: float = Field(3.0, gt=0)
    """Pots located within this of a pot (mission positions, m) say how far the map has
    drifted there from the mission's frame (``mission.patrol.map_drift``): an aisle's worth of
    neighbours at 1 m spacing, near enough that smooth SLAM drift is the same for them."""
    moved_approach_xy: float = Field(0.08, gt=0)
    """The approach again to a moved pot (or after a stop more than 1.5 times this off the
    approach pose) must end this close to it, m, not within the goal checker's 0.25 m: a pot
    pushed among its neighbours leaves MPPI room to stop short, and from 0.2 m off the wrist
    camera can miss the bloom. Failing that, one approach within the usual tolerance."""
    later_goes: int = Field(2, ge=0)
    """Goes a pot the robot could not get to has after the other pots, each round after the last,
    before it is recorded failed. In a greenhouse people work in, what keeps the robot from a pot
    is mostly someone working the only aisle to it, and they move on or come back: one more go
    found the same grower there in safety.people's patrols (stop 59: 14 of 144 pots lost, each
    after its one later go, beside growers pacing their aisle), a go minutes after that a
    different moment. Each round costs only the pots still not got to."""
    search_radius: float = Field(1.0, gt=0)
    """No tag where the pot should be: the pots the map shows within this distance of the
    mission's position are looked at for it before the pot is declared ``not_found``, m."""
    search_look_timeout: float = Field(30.0, gt=0)
    """Seconds for the drive to one search look."""
    search_time: float = Field(90.0, gt=0)
    """Seconds the whole search may take before the pot is ``not_found``: a search is bounded in
    time as in space, so a pot taken away costs a patrol a minute and a half, not the day."""
    watch_spacing: float = Field(0.25, gt=0)
    """Tags en route are looked for in a new front frame only once the robot has moved this far
    since the last one, m (``behaviours.perceive.WatchTags``): a robot standing at a pot would
    read the same tags over and over. A 1.5 m read range sees each plate from several places."""
    watch_turn: float = Field(0.25, gt=0)
    """... or turned this much, rad."""
    lidar_lost_after: float = Field(3.0, gt=0)
    """Seconds without a trustworthy scan (stale or blind) before the patrol pauses with fault
    ``lidar_lost`` (``mission.patrol.lidar_loss``): longer than a sun glint or a hand over the
    lidar, which the collision monitor rides out on its own, short enough that no goal is spent."""
    lidar_lost_give_up: float = Field(300.0, gt=0)
    """Seconds of a lost lidar after which the patrol ends ``aborted``, the rest ``skipped``:
    five minutes covers a cable reseated or a driver restarted by its service; past that someone
    has to come, and the report should say so rather than wait all day."""
    discovered_max_distance: float = Field(1.5, gt=0)
    """Tags seen en route are placed on the map only when read nearer than this, m: further
    away the pose from a 10 cm tag is too coarse to say which pot it is on."""
    energy: EnergyConfig = EnergyConfig()
    """When to head home to charge and how far to charge (``mission.patrol.energy``)."""
class SurveyConfig(BaseModel):
    """`lupin survey`: exploring a greenhouse and finding its pots by their tags."""

    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)

    max_time: float = Field(3600.0, gt=0)
    """Robot seconds the survey may take before it writes what it found and goes home."""
    frontier_min_cells: int = Field(10, ge=1)
    """A frontier counts from this many cells (0.5 m of boundary at 0.05 m): smaller ones are the
    shadows pots cast, which close as the robot moves."""
    standoff: float = Field(0.5, gt=0)
    """Looks at a pot stand this far from its centre, m: the patrol's approach distance, where the
    front camera frames a plate head-on."""
    pot_max_size: float = Field(0.45, gt=0)
    """Occupied clusters of the map up to this size across are pots to look at, m."""
    found_radius: float = Field(0.35, gt=0)
    """A pot of the map is found once a tag puts a pot within this distance of it, m (the map's
    cluster is the side of the pot the lidar saw, up to a radius off its centre)."""
    found_read: float = Field(0.8, gt=0)
    """... by a read from no farther than this, m."""
    goal_timeout: float = Field(40.0, gt=0)
    """Robot seconds for one drive (to a frontier or a look) before it is given up."""
    front_rate: float = Field(5.0, gt=0, le=30)
    """Front frames per second while surveying, Hz: the tags are read on the move, strafing down
    the aisles, so more frames than a patrol's 2 Hz."""
