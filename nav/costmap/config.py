"""Configuration of the costmaps (seed: "Costmaps for narrow aisles").

Both costmaps model the robot as a circle of ``robot_radius`` at ``resolution``; the inflation
is deliberately thin so ~0.8 m plant-row aisles stay drivable. The two maps differ in extent and
in how far they mark and clear (the seed's "Local vs global obstacle ranges" table): the local
map only needs the immediate window, the global one clears out to the lidar's full reach but
marks only to 5 m, because raw 12 m returns make a noisy global map.
"""
from __future__ import annotations

from pydantic import Field, model_validator

from hw.config import Strict


class PersonLayerConfig(Strict):
    """The person layer (``nav.costmap.people``, issue 28 item 2): tracked people kept at a
    distance by the planner and MPPI; pots, benches and walls keep the inflation's distances."""

    clearance: float = Field(0.3, ge=0)
    """Body to body, m, the robot keeps from a person when passing (issue 28: "at least 0.3 m
    body to body when passing"): the lethal disc is the person's radius, this and the robot's
    inscribed radius."""
    gradient: float = Field(0.25, ge=0)
    """Reach of the cost falloff beyond the lethal disc, m. The falloff is the inflation's own
    (252 exp(-k d), k = ``cost_scaling_factor``) so MPPI's obstacle critic, which reads a cost
    back as a distance, reads the distance past the keep-out; 0.25 m (cost 72) is as far as the
    critic's repulsion stays positive (it counts out to ``inflation_radius``)."""
    wait_clearance: float = Field(1.0, ge=0)
    """Body to body, m, the robot backs off to while it waits for a person (on its goal, or in
    the only way): issue 28's "the robot waits at a distance", the guard's 1.0 m slow zone. A
    grower who stops for the robot at arm's length waits for it to leave their way; a robot that
    waited there too would wait for ever (walker-following, once a standing pair of legs was a
    person). Backing off makes room, and a walker coming on is stepped aside from."""
    predict_time: float = Field(1.0, ge=0)
    """A walker's next seconds of straight walking at its velocity are kept out of like the
    walker, s (Nav2's social layers stretch their costs the same way): a grower who does not
    yield walks on into a robot that stepped into their way (the no-yield crossing scenario:
    hit at 8 s with the stretch merely costly). 1 s is a walker's 1 m at walking speed, beyond
    which a straight line is a guess."""
    lane_time: float = Field(4.0, ge=0)
    """How far ahead a walker's straight walk is their lane, s: a robot standing in the lane of
    someone coming its way steps out of it before they are at arm's length (``nav.people_nearby``).
    Within 1 m of a person the robot may move at 0.15 m/s (issue 28), too slow to clear a lane a
    walker is already in at 1 m/s; 4 s of their walking is 4 m, time for the robot to cross the
    ~0.9 m out of a cart's way (0.35 m half width, 0.3 m clearance, its own 0.22 m) at ``step_speed``."""
    step_speed: float = Field(0.3, gt=0)
    """Speed of a step out of a person's way, m/s (the people guard brings it down to 0.15 m/s
    within 1 m of anyone)."""
    whole_walk_back: bool = False
    """Keep a paused walker's whole last walk out, back to where it began, not only
    ``predict_time`` of it (``nav.walks.Walks.way_back``): the planner's (global) costmap does,
    so it plans no way along an aisle a pacer stands at the far end of (safety.people seed 104,
    650 s). The local costmap keeps MPPI's near view."""
    min_confidence: float = Field(0.5, ge=0, le=1)
    """Tracks at least this confident count (the tracker reports anything the map and the known
    pots do not explain at 0.5: a person until shown otherwise)."""


class RobotsLayerConfig(Strict):
    """The robots layer (``nav.costmap.robots``, issue 34): the fleet's other robots kept out of
    like people, where each says it is (its own belief, through the router), since the lidar sees
    only a robot's lidar puck and arm (its chassis is below the scan plane)."""

    margin: float = Field(0.1, ge=0)
    """Body to body, m, beyond the two footprints (each ``robot_radius``: the chassis box, 0.165 x
    0.13 m half sizes, is 0.21 m to its corner): the lethal disc is 0.22 + 0.1 + 0.22 m centre to
    centre. It holds the two robots' beliefs of where they are against where they are (the SLAM
    maps agree to a few cm, ``lupin bench slam``) and a pose 0.1 s old at 0.3 m/s (3 cm); and it
    stays under ``mission.patrol.aisle_gate.SIDE`` (0.6 m), so a robot waiting beside an aisle's
    mouth does not close the way out for the one leaving it."""
    gradient: float = Field(0.25, ge=0)
    """Reach of the cost falloff past the lethal disc, m: the person layer's (MPPI's obstacle
    critic reads it back as a distance)."""
    still_margin: float = Field(0.02, ge=0)
    """``margin`` for a robot that has gone silent (``nav.costmap.robots.Peer.silent``: its
    computer died, it stands where it last said): only the two beliefs' few cm, no pose going
    stale as it moves. With the full margin and falloff a robot dead on a pot's approach pose
    kept the others 0.6 m and more off it, out of the wrist's reach of the pot from every side
    its tag reads from (``mission.patrol.aside``; ``fleet.handover_small``'s P20)."""
    still_gradient: float = Field(0.05, ge=0)
    """``gradient`` for a silent robot, m: it will not come closer, so MPPI need not keep farther."""


class LocalCostmapConfig(Strict):
    """The 3 x 3 m window rolling with the robot, in ``odom`` (obstacle + inflation layers)."""

    size: float = Field(3.0, gt=0)
    """Width and height of the rolling window, m (seed: a 3x3 m rolling window)."""
    obstacle_max_range: float = Field(2.5, gt=0)
    """Returns are marked as obstacles up to this range, m (seed: local obstacle_max_range 2.5)."""
    raytrace_max_range: float = Field(3.0, gt=0)
    """Free space is cleared along each beam up to this range, m (seed: local raytrace_max_range 3.0)."""
    track_unknown_space: bool = False
    """Unseen cells are free (Nav2's local default: the seed tracks unknown space only globally)."""
    inf_is_valid: bool = False
    """Clear along beams with no return out to ``raytrace_max_range`` (Nav2's obstacle-layer
    ``inf_is_valid``, default false: a missing return may be a dark surface, not free space)."""
    people: PersonLayerConfig = PersonLayerConfig()
    """The person layer: MPPI keeps its distance from people as it drives."""


class GlobalCostmapConfig(Strict):
    """The global map in ``map`` (static + obstacle + inflation). It has no set size: it grows
    to take in the map, the robot and each goal (``nav.costmap.layered``)."""

    obstacle_max_range: float = Field(5.0, gt=0)
    """Returns are marked up to this range, m (seed: global obstacle_max_range 5.0, which covers
    across-room geometry without the long-tail noise of raw 12 m returns)."""
    raytrace_max_range: float = Field(12.0, gt=0)
    """Free space is cleared up to this range, m (seed: global raytrace_max_range 12.0, the
    lidar's full reach)."""
    track_unknown_space: bool = True
    """Unseen cells stay unknown (255) until observed (seed: the global costmap tracks unknown
    space), so the planner can tell explored from unexplored ground."""
    inf_is_valid: bool = False
    """As the local map's ``inf_is_valid``."""
    people: PersonLayerConfig = PersonLayerConfig(whole_walk_back=True)
    """The person layer: NavFn goes round a person by another aisle where the one they stand in
    is too narrow to pass them at ``clearance``."""
    occupied_thresh: float = Field(0.65, gt=0, le=1)
    """Static map cells with occupancy >= this are lethal (seed's map: occupied_thresh 0.65,
    map_server trinary mode)."""
    free_thresh: float = Field(0.25, ge=0, lt=1)
    """Static map cells with occupancy <= this are free; in between is unknown (seed's map:
    free_thresh 0.25)."""

    @model_validator(mode="after")
    def _thresholds_ordered(self) -> "GlobalCostmapConfig":
        if self.free_thresh >= self.occupied_thresh:
            raise ValueError(f"free_thresh {self.free_thresh} must be below occupied_thresh {self.occupied_thresh}")
        return self


class CostmapsConfig(Strict):
    """The local and global costmaps."""

    resolution: float = Field(0.05, gt=0)
    """Cell size, m (seed: resolution 0.05 for both costmaps and the SLAM map)."""
    robot_radius: float = Field(0.22, gt=0)
    """Circular footprint radius, m (seed: robot_radius 0.22); the inscribed radius of inflation."""
    inflation_radius: float = Field(0.25, gt=0)
    """Inflation halo radius, m (seed: 0.25, ~0.03 m past the footprint; a textbook 0.55 m halo
    on a 0.22 m robot would close a 0.8 m aisle completely)."""
    cost_scaling_factor: float = Field(5.0, gt=0)
    """Exponential falloff of inflated cost (seed: 5.0, steep so the halo stays thin and MPPI
    keeps drivable space mid-aisle)."""
    obstacle_min_range: float = Field(0.25, ge=0)
    """Lidar returns closer than this are dropped, m (seed: 0.25 in both costmaps, AMCL and SLAM:
    the lidar sees the robot's own arm at ~0.10 m)."""
    robots: RobotsLayerConfig = RobotsLayerConfig()
    """The fleet's other robots in both costmaps (a robot alone has none)."""
    local_costmap: LocalCostmapConfig = LocalCostmapConfig()
    """The rolling local window MPPI scores against (seed: local costmap)."""
    global_costmap: GlobalCostmapConfig = GlobalCostmapConfig()
    """The global map NavFn plans on (seed: global costmap)."""
