"""The eight critics, one per module on a common base (``base.Critic``), and the factory that
builds the ones the config lists, in its order (Nav2's critic plugins)."""
from __future__ import annotations

from nav.costmap.config import CostmapsConfig
from nav.mppi.config import MppiConfig
from nav.mppi.critics.base import Critic
from nav.mppi.critics.constraint import ConstraintCritic
from nav.mppi.critics.goal import GoalCritic
from nav.mppi.critics.goal_angle import GoalAngleCritic
from nav.mppi.critics.obstacles import ObstaclesCritic
from nav.mppi.critics.path_align import PathAlignCritic
from nav.mppi.critics.path_angle import PathAngleCritic
from nav.mppi.critics.path_follow import PathFollowCritic
from nav.mppi.critics.prefer_forward import PreferForwardCritic

_CLASSES: dict[str, type[Critic]] = {
    "constraint": ConstraintCritic, "obstacles": ObstaclesCritic, "goal": GoalCritic, "goal_angle": GoalAngleCritic,
    "path_align": PathAlignCritic, "path_follow": PathFollowCritic, "path_angle": PathAngleCritic,
    "prefer_forward": PreferForwardCritic,
}


def make_critics(config: MppiConfig, costmaps: CostmapsConfig) -> list[Critic]:
    """The critics ``config.critics`` names, with their parameters; an unknown name is an error."""
    c = config.critic
    if c.goal_angle.threshold_to_consider is None or c.path_angle.mode is None:
        raise ValueError("MPPI config has unresolved motion-model defaults: take it from NavConfig (nav.config), "
                         "which derives GoalAngle's reach and PathAngle's mode")
    out = []
    for name in config.critics:
        if name not in _CLASSES:
            raise ValueError(f"unknown MPPI critic {name!r}; known: {', '.join(_CLASSES)}")
        params = getattr(config.critic, name)
        if name == "constraint":
            out.append(ConstraintCritic(params, costmaps, config.vx_min, config.vx_max))
        else:
            out.append(_CLASSES[name](params, costmaps))
    return out
