"""The deployment files agree with the CLI contract and the seed's restart policy."""
import configparser
import re
from pathlib import Path

import pytest

from lupin.cli import main
from mission.runtime.config import load_config

DEPLOY = Path(__file__).resolve().parents[2] / "deploy"


def unit(name: str) -> configparser.ConfigParser:
    p = configparser.ConfigParser(interpolation=None, strict=True)
    p.optionxform = str
    p.read_string((DEPLOY / name).read_text())
    return p


def test_onboard_runs_the_hw_backend_and_stops_cleanly():
    s = unit("lupin-onboard.service")["Service"]
    assert s["ExecStart"].endswith("serve --backend hw")
    assert s["KillSignal"] == "SIGINT"  # exit handlers run: lidar STOP, motors off
    assert s["Restart"] == "on-failure" and "2" in s["RestartPreventExitStatus"].split()


def test_heal_retries_only_a_real_failure():
    u = unit("lupin-heal.service")
    s = u["Service"]
    assert s["Type"] == "oneshot" and s["ExecStart"].endswith("heal --backend hw")
    # systemd retries non-zero exits: 1 (a controller not active) is; 0 (states unknown, seed's
    # retry storm) is a success to systemd, and 2 (bad input) is excluded explicitly
    assert s["Restart"] == "on-failure"
    assert s["RestartPreventExitStatus"].split() == ["2"]
    assert "SuccessExitStatus" not in s
    assert int(u["Unit"]["StartLimitBurst"]) <= 10


def test_cameras_unit_runs_before_the_runtime():
    u = unit("lupin-cameras.service")
    assert "lupin-onboard.service" in u["Unit"]["Before"]
    assert (DEPLOY / "kill-vendor-cameras.sh").stat().st_mode & 0o111


def test_example_config_is_valid():
    config = load_config(DEPLOY / "config.example.yaml", env={})
    assert config.hw.devices.lidar.baud == 460800


@pytest.mark.parametrize("cmd", sorted({m.group(1) for m in re.finditer(r"lupin --config \S+ (hw [a-z0-9 -]+?)\s*$",
                                                                          (DEPLOY / "README.md").read_text(), re.M)}))
def test_readme_bring_up_commands_exist(cmd, capsys):
    assert main(cmd.split() + ["--help"]) == 0
