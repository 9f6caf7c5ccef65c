"""`lupin survey` on the simulated greenhouse: the sim's cameras as the perception config, and
the world, which only builds the sim (the survey never reads its pots)."""
from __future__ import annotations

from mission.jobs.navigate import start_navigate
from mission.jobs.sim_patrol import sim_perception
from mission.jobs.survey import SurveyRun, start_survey, survey_config
from mission.runtime.config import LupinConfig
from sim.world import World


def start_sim_survey(world: World, config: LupinConfig) -> tuple[SurveyRun, object]:
    """The survey on a sim of ``world``; (the run, the sim run under it for judging)."""
    config = survey_config(config)
    sim_run = start_navigate(world, config)
    return start_survey(sim_run.robot, sim_run.nav, config, sim_perception(config), sim_run.close), sim_run
