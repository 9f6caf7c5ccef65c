"""Which robot a command runs: the config's ``runtime.backend`` unless ``--backend`` says
otherwise, named on the first line of output (issue: the robot knows it is the robot)."""
from pathlib import Path

import pytest

from lupin.cli import main

DEPLOY = Path(__file__).resolve().parents[2] / "deploy" / "config.example.yaml"


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_the_deploy_config_runs_the_robot(capsys, tmp_path):
    """On the robot, `lupin patrol` without --backend is the hw patrol, so it wants a mission
    (not the built-in sim greenhouse); exit 2 before anything opens."""
    code, out, err = run(capsys, "--config", str(DEPLOY), "patrol", "--report", str(tmp_path / "r.json"))
    assert code == 2
    assert "--backend hw: give --mission" in err


def test_backend_option_overrides_the_config(capsys, tmp_path):
    code, _, err = run(capsys, "--config", str(DEPLOY), "patrol", "--backend", "sim", "--mission",
                       str(tmp_path / "missing.yaml"))
    assert code == 2 and "missing.yaml" in err and "--backend hw" not in err


@pytest.mark.slow
def test_a_sim_patrol_names_its_backend_and_world_first(capsys, tmp_path):
    mission = tmp_path / "one.yaml"
    mission.write_text("name: one\nhome: {x: 0.0, y: 0.0, yaw: 0.0}\n"
                       "pots:\n- {id: P01, x: 1.0, y: 0.5, facing: -1.5708, tag: 1}\n")
    code, out, _ = run(capsys, "patrol", "--mission", str(mission), "--report", str(tmp_path / "r" / "report.json"),
                       "--history", "none")
    assert code == 0
    assert out.splitlines()[0] == "lupin patrol: sim backend, world 'default'"


def test_an_hw_command_names_its_backend_first(capsys, tmp_path, monkeypatch):
    """The hw heal announces itself before it opens a device (which fails here: no bus)."""
    monkeypatch.setenv("LUPIN_RUNTIME__BACKEND", "hw")
    monkeypatch.setenv("LUPIN_HW__DEVICES__I2C__BUS", "97")
    code, out, err = run(capsys, "heal")
    assert out.splitlines()[0] == "lupin heal: hw backend (the robot's devices)"
    assert code == 2 and "97" in err
