"""One configuration schema for the whole runtime, validated once at start-up.

Layers, lowest first: defaults in code (each field's docstring says why, citing the seed),
a YAML override file, then ``LUPIN_*`` environment variables. Environment names use ``__``
between levels, e.g. ``LUPIN_HW__BASE__PID__P=2.0`` or ``LUPIN_SIM__SEED=7``; values are
parsed as YAML scalars. Variables whose first level is not a section of the schema are left
alone (they belong to other tools). The config actually used is saved beside each run's output.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Mapping

import yaml
from pydantic import BaseModel, ConfigDict, ValidationError, model_validator

from arm.config import ArmConfig
from hw.config import HwConfig
from hw.atomic_file import write_atomic
from hw.errors import InputError
from hw.input_file import read_yaml
from mission.history.config import HistoryConfig
from mission.link.config import LinkConfig
from mission.link.fleet_config import FleetConfig
from mission.patrol.config import PatrolConfig, SurveyConfig
from mission.runtime.settings import RuntimeConfig
from nav.config import NavConfig
from perception.config import PerceptionConfig
from sim.config import SimConfig

ENV_PREFIX = "LUPIN_"
CONFIG_FILENAME = "config.yaml"


class LupinConfig(BaseModel):
    """The root: one sub-model per package."""

    model_config = ConfigDict(extra="forbid", use_attribute_docstrings=True)

    hw: HwConfig = HwConfig()
    """Hardware services: base control, twist_mux, e-stop bridge, LEDs, servo bus."""
    nav: NavConfig = NavConfig()
    """Navigation: costmaps, planner, MPPI, velocity smoother, goal checker, navigator."""
    arm: ArmConfig = ArmConfig()
    """The arm: limits, trajectory controller, gripper, stall handling, IK."""
    perception: PerceptionConfig = PerceptionConfig()
    """The flower detector, the tag reader and the camera pipeline."""
    sim: SimConfig = SimConfig()
    """The MuJoCo greenhouse backend."""
    patrol: PatrolConfig = PatrolConfig()
    """The patrol mission: its beat, the waits around the cameras, what counts as a pot's tag."""
    survey: SurveyConfig = SurveyConfig()
    """`lupin survey`: exploring a greenhouse and finding its pots by their tags."""
    link: LinkConfig = LinkConfig()
    """The operator link (Zenoh): robot name, endpoint, token, telemetry rates."""
    fleet: FleetConfig = FleetConfig()
    """A fleet patrol's dispatcher: when a stopped robot's pots go to the others, the docks."""
    history: HistoryConfig = HistoryConfig()
    """The patrol history (spec/history.md): where every patrol is recorded."""
    runtime: RuntimeConfig = RuntimeConfig()
    """Which backend this machine runs by default, and where the runtime keeps its state."""

    @model_validator(mode="after")
    def _monitor_covers_the_footprint(self) -> "LupinConfig":
        """A collision-monitor stop zone that does not reach past the footprint would let the
        body touch what the zone was meant to keep off it."""
        radius = self.nav.costmap.robot_radius
        stop = self.hw.collision_monitor.stop
        for name in ("length", "half_width"):
            if getattr(stop, name) < radius:
                raise ValueError(f"hw.collision_monitor.stop.{name} {getattr(stop, name):g} m is inside the footprint "
                                 f"(nav.costmap.robot_radius {radius:g} m): the stop zone must cover the robot's body")
        return self


def _merge(base: dict, override: Mapping) -> dict:
    out = dict(base)
    for key, value in override.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), dict):
            out[key] = _merge(out[key], value)
        else:
            out[key] = value
    return out


def _env_overrides(env: Mapping[str, str]) -> dict:
    sections = set(LupinConfig.model_fields)
    tree: dict[str, Any] = {}
    for name, raw in sorted(env.items()):
        if not name.startswith(ENV_PREFIX):
            continue
        path = [part.lower() for part in name[len(ENV_PREFIX):].split("__")]
        if path[0] not in sections:
            continue
        try:
            value = yaml.safe_load(raw) if raw != "" else ""
        except yaml.YAMLError:
            value = raw
        node = tree
        for part in path[:-1]:
            node = node.setdefault(part, {})
        node[path[-1]] = value
    return tree


def _format(err: ValidationError, source: str) -> str:
    parts = []
    for e in err.errors():
        where = ".".join(str(x) for x in e["loc"]) or "(top level)"
        parts.append(f"{where}: {e['msg']}")
    return f"invalid config ({source}): " + "; ".join(parts)


def load_config(path: str | Path | None = None, env: Mapping[str, str] | None = None) -> LupinConfig:
    """Defaults <- YAML file <- environment, validated once; InputError names what is wrong."""
    env = os.environ if env is None else env
    data: dict = {}
    sources = ["defaults"]
    if path is not None:
        loaded = read_yaml(path, "config file")
        if not isinstance(loaded, Mapping):
            raise InputError(f"{path}: top level: must be a mapping of sections ({', '.join(LupinConfig.model_fields)})")
        data = _merge(data, loaded)
        sources.append(str(path))
    overrides = _env_overrides(env)
    if overrides:
        data = _merge(data, overrides)
        sources.append("LUPIN_* environment")
    try:
        return LupinConfig.model_validate(data)
    except ValidationError as exc:
        raise InputError(_format(exc, " + ".join(sources))) from None


def with_seed(config: LupinConfig, seed: int) -> LupinConfig:
    """The same config with another sim seed (``--seed``, benchmark runs)."""
    return config.model_copy(update={"sim": config.sim.model_copy(update={"seed": seed})})


def with_overrides(config: LupinConfig, overrides: Mapping) -> LupinConfig:
    """``config`` with nested ``overrides`` applied and validated again, so values derived from
    others (the smoother's limits, the critics' modes that follow the motion model) follow the
    change instead of keeping what was derived before it (``model_copy`` would)."""
    return LupinConfig.model_validate(_merge(config.model_dump(exclude_unset=True), overrides))


def save_config(config: LupinConfig, directory: str | Path) -> Path:
    """Write the config actually used next to a run's output, so any run can be reproduced."""
    directory = Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    out = directory / CONFIG_FILENAME
    write_atomic(out, yaml.safe_dump(config.model_dump(mode="json"), sort_keys=False).encode())
    return out
