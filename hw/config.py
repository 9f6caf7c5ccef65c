"""Configuration of the hardware services (base control, mux, e-stop, LEDs, servos).

Every default is a number from the hardware seed (../shared/seeds/000_*) or the hardware
reference; the field docstrings say which and why. Override in YAML or ``LUPIN_HW__...``.
"""
from __future__ import annotations

import math

from pydantic import BaseModel, ConfigDict, Field, field_validator


class Strict(BaseModel):
    """Config sections: unknown keys are errors (a typo must not be silently ignored) and each
    field's docstring is its description."""

    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True, validate_assignment=True)


class PidGains(Strict):
    p: float = 1.5
    """Proportional gain of pid_wheels_controller (seed: p 1.5)."""
    i: float = 0.5
    """Integral gain (seed: i 0.5)."""
    d: float = 0.01
    """Derivative gain (seed: d 0.01)."""
    i_clamp: float = Field(15.0, gt=0)
    """Anti-windup clamp on the integral term, +-rad/s of wheel command (seed: i_clamp +-15)."""
    antiwindup: bool = True
    """Seed: antiwindup on. Stops integrating while the output saturates."""
    feedforward: float = 1.0
    """Reference feed-forward gain. The seed's PID closes the loop on wheel *velocity* at only
    10 Hz; with p 1.5 alone the integral would have to carry the whole command. ros2_control's
    pid_controller feeds the reference forward, and so do we (untuned on the robot)."""


class BaseConfig(Strict):
    wheel_radius: float = Field(0.051, gt=0)
    """Mecanum wheel radius, m (seed: wheels_radius 0.051)."""
    lx_plus_ly: float = Field(0.225, gt=0)
    """Sum of the wheel centre projections, m (seed: 0.18/2 + 0.27/2 = 0.225)."""
    ticks_per_rev: int = Field(1320, gt=0)
    """Encoder ticks per wheel revolution with 4x decoding (vendor: 11 ppr * 30 reduction * 4)."""
    max_wheel_speed: float = Field(6 * math.pi, gt=0)
    """Wheel speed at 100 % duty, rad/s (hardware reference: 100 % = 6*pi rad/s)."""
    duty_dead_zone: float = Field(0.10, ge=0, lt=1)
    """|duty| below which the motors do not turn (hardware reference: 10 % dead-zone). Duties
    for a non-zero wheel reference are mapped past it, so slow moves (the last centimetres of a
    tight approach) do not wait seconds for the integral to climb out of the dead band."""
    control_rate: float = Field(10.0, gt=0)
    """Controller-manager update rate, Hz (seed: update_rate 10, every command is a 100 ms beat)."""
    pid: PidGains = PidGains()
    """Per-wheel velocity PID (seed: pid_wheels_controller)."""
    encoder_signs: tuple[int, int, int, int] = (1, 1, 1, 1)
    """Per-wheel encoder sign in WHEELS order, for wiring that counts backwards."""
    motor_signs: tuple[int, int, int, int] = (1, 1, 1, 1)
    """Per-wheel duty sign in WHEELS order (the seed's drive inversion was fixed at the pin level)."""


class MuxSource(Strict):
    priority: int
    """Higher wins while live."""
    timeout: float = Field(gt=0)
    """Seconds of silence after which the source stops counting (twist_mux.yaml)."""


def _default_sources() -> dict[str, MuxSource]:
    return {
        "joy": MuxSource(priority=100, timeout=0.3),
        "manual": MuxSource(priority=50, timeout=0.5),
        "auto": MuxSource(priority=10, timeout=0.5),
    }


class MuxConfig(Strict):
    sources: dict[str, MuxSource] = Field(default_factory=_default_sources)
    """Seed twist_mux table: dead-man joy 100/0.3 s, operator manual 50/0.5 s, autonomy
    auto 10/0.5 s. The idle zero guard (priority 1) is built in and always live."""
    zero_guard_priority: int = 1
    """Seed: the bus's idle zero publisher sits at priority 1, below every real source."""


class EStopConfig(Strict):
    engaged_level: int = Field(1, ge=0, le=1)
    """Pin level that means 'pressed'. UNVERIFIED on the robot (seed): logged loudly at start-up;
    press the button and check the state goes true, else flip this."""
    publish_rate: float = Field(5.0, gt=0)
    """E-stop state publish rate, Hz (seed: estop_bridge publishes /e_stop_state at 5 Hz)."""


class LedConfig(Strict):
    color_order: str = "BRG"
    """Wire order of the strip's three bytes. Mirte-247264's strip is BRG (seed)."""
    num_leds: int = Field(8, gt=0)
    """Pixels on the strip (vendor strip length; only affects how many pixels are written)."""

    @field_validator("color_order")
    @classmethod
    def _permutation_of_rgb(cls, v: str) -> str:
        if sorted(v.upper()) != ["B", "G", "R"]:
            raise ValueError("must be a permutation of 'RGB', e.g. 'BRG' or 'GRB'")
        return v.upper()


class ServoCalib(Strict):
    id: int = Field(ge=0, le=253)
    """Hiwonder bus id (seed: ids 2-6)."""
    home: int
    """Vendor home, centidegrees (mirte_master_config.yaml); rad = (raw - home)/100 * pi/180."""
    min: int
    """Vendor raw software limit, centidegrees."""
    max: int
    """Vendor raw software limit, centidegrees."""


def _default_servos() -> dict[str, ServoCalib]:
    return {
        "shoulder_pan": ServoCalib(id=2, home=12000, min=3400, max=21000),
        "shoulder_lift": ServoCalib(id=3, home=11450, min=2832, max=20000),
        "elbow": ServoCalib(id=4, home=11750, min=120, max=21000),
        "wrist": ServoCalib(id=5, home=12200, min=1128, max=21000),
        "gripper": ServoCalib(id=6, home=10524, min=6168, max=14224),
    }


class ServoBusConfig(Strict):
    joints: dict[str, ServoCalib] = Field(default_factory=_default_servos)
    """Joint -> servo id and vendor raw range (hardware reference, MIRTE vendor config)."""
    centideg_per_count: float = 24.0
    """Hiwonder position: 0..1000 counts over 240 deg, i.e. 24 centidegrees per count."""

    def counts_to_rad(self, calib: ServoCalib, counts: float) -> float:
        """The one counts -> joint radians map: rad = (counts * 24 - home) / 100 * pi / 180."""
        return math.radians((counts * self.centideg_per_count - calib.home) / 100.0)

    def rad_to_counts(self, calib: ServoCalib, rad: float) -> float:
        """Joint radians -> (fractional) counts, the inverse of ``counts_to_rad``."""
        return (math.degrees(rad) * 100.0 + calib.home) / self.centideg_per_count


class StopZone(Strict):
    """Points here stop the base: 8 cm ahead of the 0.22 m footprint and as wide as it (what
    the footprint sweeps going straight: a pot passed 1 cm to the side is not in the way). It
    cannot reach further ahead: at an approach pose the pot's rim is 0.40 m from the centre, and
    the monitor cannot tell a pot from a person, so a longer box stops every head-on approach
    short (0.42 m cost the default patrol ten stops and 1.6 s). Keeping further from a person
    is the approach mode's and the costmap's part."""

    length: float = Field(0.30, gt=0)
    """From the base centre along the direction of travel, m."""
    half_width: float = Field(0.22, gt=0)
    """To either side of the direction of travel, m."""


class SlowdownZone(Strict):
    """Points here cap the speed: 0.43 m ahead of the footprint, narrow enough that the pots
    beside a 0.8 m aisle (0.40 m from the centre line) do not slow every aisle."""

    length: float = Field(0.65, gt=0)
    """From the base centre along the direction of travel, m."""
    half_width: float = Field(0.26, gt=0)
    """To either side of the direction of travel, m."""
    speed: float = Field(0.15, gt=0)
    """Most linear speed with points in this zone, m/s."""


class ApproachConfig(Strict):
    time_before_collision: float = Field(1.2, gt=0)
    """The time to contact along the commanded twist the monitor keeps, s (Nav2's approach
    polygon; its example uses 1.2 s): half a second to stop from the robot's top speed, with
    room for a walker closing in at 1 m/s."""
    time_step: float = Field(0.1, gt=0)
    """Step of the footprint carried along the twist, s (Nav2 simulation_time_step 0.1)."""


class BlindRule(Strict):
    """When a scan that arrives on time still cannot be trusted (hw.scan_trust): covered, sun-
    blinded, everything under range_min, so most returns are invalid (inf). An honest scan in a
    greenhouse can have many invalid returns too: an aisle looking out of an open end or down a
    long house beyond the C1's 12 m. So the rule is a floor far below any honest scan plus a
    *sudden* fall against the last trusted scans, never a fixed share of one arc."""

    min_valid: float = Field(0.10, ge=0, lt=1)
    """Least share of all beams with a valid return, else blind. Even standing in an open door
    the rows and posts behind and beside the robot return well over this (the sim's honest
    scans: no fewer than 0.75, the bench ``safety.blind`` shows them); a covered or sun-blinded
    C1 returns next to nothing."""
    front_arc: float = Field(math.radians(120.0), gt=0, le=2 * math.pi)
    """Width of the arc ahead of the lidar judged on its own, rad: what a hand, a leaf or the
    low sun covers first, and where the base drives most."""
    collapse: float = Field(0.5, gt=0, lt=1)
    """A scan whose valid share (all beams, or the front arc) falls below this fraction of its
    median over the last trusted scans, *and* by at least ``min_drop``, is blind."""
    min_drop: float = Field(0.3, gt=0, lt=1)
    """... the fall, as a share of the beams (of all, or of the arc). Between two revolutions
    (0.1 s) the base moves 5 cm and turns 6 deg at most, so an honest front arc gains or loses
    about 5 % of its beams per edge; turning into an open end empties it over many revolutions
    and a share already near zero (facing out) cannot fall by this much. A hand over the lidar
    or sun glare takes far more at once."""
    history: int = Field(3, ge=1)
    """Trusted scans the median is taken over (0.3 s of the C1): one odd scan sets no baseline,
    and a turn moves the view only ~20 % of the arc over it. Blind scans never enter it: a
    lidar that stays covered stays blind."""


class CollisionMonitorConfig(Strict):
    """Nav2's collision monitor between the twist_mux and the base controller (hw.collision_monitor).
    The zones' sizes are checked against the navigation footprint when the config is loaded."""

    enabled: bool = True
    """Off only where the bare controller must be seen (sim benches, bump tests): logged at
    WARNING once in the sim; on the robot refused unless the command says
    ``--no-collision-monitor`` (then logged at ERROR every minute and shown in the console)."""
    chassis: tuple[float, float] = (0.165, 0.13)
    """Half length and half width of the chassis rectangle, m: the body the monitor protects
    and the self-filter (robot model: the ``chassis`` box 0.33 x 0.26 m, centred on base_link;
    sim/models/mirte_master/README.md). The arm as it stands is added from its joint states."""
    self_margin: float = Field(0.02, ge=0)
    """Returns within this of the outline are the robot's own, m: twice the C1's range noise
    (sim noise_std 0.01), so a leg 5 cm off the side (issue 28) is still seen."""
    blind: BlindRule = BlindRule()
    """When an on-time scan is blind all the same (its class says why these numbers)."""
    stop: StopZone = StopZone()
    """The stop zone (its class says why these sizes)."""
    slowdown: SlowdownZone = SlowdownZone()
    """The slowdown zone (its class says why these sizes)."""
    approach: ApproachConfig = ApproachConfig()
    """Time-to-collision scaling along the commanded twist."""
    min_points: int = Field(3, ge=1)
    """Points needed in a zone before it acts (Nav2 min_points): one stray return is noise."""
    scan_timeout: float = Field(0.5, gt=0)
    """A scan older than this stops the linear motion, s (Nav2 source_timeout; five C1 revolutions)."""

    @field_validator("slowdown")
    @classmethod
    def _slowdown_contains_stop(cls, v, info):
        stop = info.data.get("stop")
        if stop is not None and (v.length < stop.length or v.half_width < stop.half_width):
            raise ValueError("the slowdown zone must contain the stop zone")
        return v


class PeopleGuardConfig(Strict):
    """The speed rules for people (issue 28 item 2), below the mux beside the collision monitor
    (``hw.people_guard``), on the person tracker's people: pots, benches and walls are not
    people, so they keep today's approach distances."""

    slow_distance: float = Field(1.0, gt=0)
    """Body to body, m, inside which the robot drives slowly (issue 28: "at most 0.15 m/s within
    1.0 m of a person")."""
    slow_speed: float = Field(0.15, gt=0)
    """Most linear speed within ``slow_distance`` of a person, m/s (issue 28)."""
    still_distance: float = Field(0.25, ge=0)
    """Body to body, m, inside which the base does not move at all, turning included (the arm
    sweeps): someone at arm's length, who came to the robot (a grower who does not yield walked
    up beside it while it inspected), is waited out, never driven past or away from under their
    nose (spec/scenario.md judges every moment the robot moves against 0.25 m), for up to
    ``still_wait``."""
    still_lookahead: float = Field(0.5, ge=0)
    """Someone whose walk brings them within ``still_distance`` in this many seconds counts as
    there already, s: a grower crossing at 0.8 m/s closes 0.4 m in it, the tracker's scan of
    lag and the base's stopping included."""
    still_wait: float = Field(5.0, ge=0)
    """Seconds the base stands still for someone at arm's length before it may step away from
    them (never towards): a grower who stopped for the robot at arm's length waits for it to
    move, and two who wait for each other would wait for ever (walker-following). A grower who
    walked up to it only in passing has gone on within it (people-crossing-no-yield: 1 s coming,
    2 s standing at the end of their round, 3 s was too short)."""
    near_distance: float = Field(0.5, gt=0)
    """Body to body, m, inside which no motion towards the person is allowed (issue 28: "never
    drive towards a person nearer than 0.5 m"): the share of the twist towards them is removed,
    sideways and away still pass."""
    ring_closing: float = Field(0.02, ge=0)
    """Ringed round by people nearer than ``near_distance`` (every way closes on one of them),
    the most speed towards any of them the base may creep at, m/s, along the way that closes
    least (``hw.people_guard.PeopleGuard.escape``): standing still there, the robot waited for
    good while the people waited for it (safety.people seed 113, 960-2,850 s: a worker 0.48 m
    off on one side, a cart that yields 0.28 m off on the other, 168 deg apart, the cart
    waiting for the robot to leave its turning place). 4 cm in the navigator's 2 s step; 0:
    never."""
    min_confidence: float = Field(0.5, ge=0, le=1)
    """Tracks at least this confident count (the tracker reports anything unexplained at 0.5:
    a person until shown otherwise, the safe side)."""


class HwConfig(Strict):
    """Hardware services: the same in sim and on the robot."""

    base: BaseConfig = BaseConfig()
    """Mecanum base: kinematics, encoders, wheel PID (seed: mirte_base_control.yaml)."""
    mux: MuxConfig = MuxConfig()
    """The twist_mux: the only path from any velocity source to the wheels."""
    collision_monitor: CollisionMonitorConfig = CollisionMonitorConfig()
    """The last check between the mux and the wheels, on the raw scan."""
    people_guard: PeopleGuardConfig = PeopleGuardConfig()
    """The speed rules near tracked people, above the collision monitor."""
    estop: EStopConfig = EStopConfig()
    """The e-stop bridge: physical button OR operator soft stop."""
    leds: LedConfig = LedConfig()
    """The status LED strip and its wire colour order."""
    servos: ServoBusConfig = ServoBusConfig()
    """The Hiwonder servo bus: ids and vendor raw ranges."""
    devices: devices_config.DevicesConfig = Field(default_factory=lambda: devices_config.DevicesConfig())
    """The real devices for the hardware backend and ``lupin hw``: every address, channel,
    bus, port, baud rate and scale (hardware reference; unused by the sim)."""
    controllers: tuple[str, ...] = (
        "joint_state_broadcaster",
        "pid_wheels_controller",
        "mirte_master_arm_controller",
        "mirte_master_gripper_controller",
        "mirte_base_controller",
    )
    """The five controllers the boot heal brings to active (seed: auto_home.py)."""


# Last: devices_config builds its sections on Strict, so it may be imported first or second.
from hw import devices_config  # noqa: E402
