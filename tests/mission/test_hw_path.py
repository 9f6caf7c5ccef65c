"""The robot's own runtime never loads the simulator: `lupin serve --backend hw` and
`lupin patrol --backend hw` get as far as opening the devices (which this machine lacks: exit 2
naming the bus) with MuJoCo made unimportable, and with no simulator module loaded but the
config schema's section (``sim.config``, plain pydantic)."""
from __future__ import annotations

import json
import subprocess
import sys

import pytest

PROBE = """
import json, sys
sys.modules["mujoco"] = None  # any import of it now raises
from lupin.cli import main
code = main(sys.argv[1:])
print(json.dumps({"code": code, "sim": sorted(m for m in sys.modules if m == "sim" or m.startswith("sim."))}))
"""


@pytest.mark.parametrize("argv", [["serve", "--backend", "hw"], ["patrol", "--backend", "hw", "--mission", "MISSION"]])
def test_the_hw_backend_never_imports_the_simulator(tmp_path, argv):
    mission = tmp_path / "m.yaml"
    mission.write_text("name: m\npots:\n  - {id: P01, x: 1.0, y: 0.5, facing: 0.0}\n")
    argv = [str(mission) if a == "MISSION" else a for a in argv]
    out = subprocess.run([sys.executable, "-c", PROBE, *argv], capture_output=True, text=True, cwd=tmp_path, timeout=120)
    result = json.loads(out.stdout.strip().splitlines()[-1])
    assert result["code"] == 2 and "/dev/" in out.stderr and "mujoco" not in out.stderr  # got to the devices
    assert result["sim"] == ["sim", "sim.config"]


def test_the_mission_file_needs_no_simulator():
    out = subprocess.run([sys.executable, "-c", "import sys; sys.modules['mujoco'] = None; "
                          "import mission.patrol.mission_file, mission.patrol.climate; "
                          "print(sorted(m for m in sys.modules if m == 'sim' or m.startswith('sim.')))"],
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0 and out.stdout.strip() == "[]", out.stderr

