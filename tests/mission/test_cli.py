"""The `lupin` command: help, exit codes, one-line errors, and the sim/bench plumbing."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

from lupin import bench
from lupin.cli import main
from sim.world import load_world

LUPIN = Path(sys.executable).parent / "lupin"


def run(capsys, *argv):
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_console_script_help():
    p = subprocess.run([str(LUPIN), "--help"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0
    for cmd in ("sim", "bench"):
        assert cmd in p.stdout


@pytest.mark.parametrize("argv", [["sim", "--help"], ["sim", "drive", "--help"], ["sim", "generate", "--help"],
                                  ["sim", "snapshot", "--help"], ["bench", "--help"]])
def test_every_subcommand_has_help(capsys, argv):
    code, out, _ = run(capsys, *argv)
    assert code == 0 and "Usage" in out


def test_generate_writes_a_valid_world(capsys, tmp_path):
    out = tmp_path / "w.yaml"
    code, stdout, _ = run(capsys, "sim", "generate", "--rows", "2", "--pots-per-row", "3", "--seed", "5", "-o", str(out))
    assert code == 0 and "wrote" in stdout
    world = load_world(out)
    assert len(world.pots) == 6


def test_generate_to_stdout_is_deterministic(capsys):
    a = run(capsys, "sim", "generate", "--rows", "3", "--pots-per-row", "2", "--seed", "9")[1]
    b = run(capsys, "sim", "generate", "--rows", "3", "--pots-per-row", "2", "--seed", "9")[1]
    assert a == b and "pots:" in a


@pytest.mark.parametrize("argv, needle", [
    (["sim", "drive", "--bogus"], "No such option"),
    (["sim", "drive", "--world", "/nonexistent/w.yaml"], "/nonexistent/w.yaml"),
    (["sim", "drive", "--route", "moon"], "--route"),
    (["sim", "snapshot", "--pose", "1,2", "-o", "x.png"], "--pose"),
    (["sim", "snapshot", "--camera", "rear", "-o", "x.png"], "--camera"),
    (["sim", "generate", "--rows", "0", "--pots-per-row", "3", "--seed", "1"], "rows"),
    (["sim", "generate", "--rows", "two", "--pots-per-row", "3", "--seed", "1"], "--rows"),
    (["bench", "warp-drive"], "warp-drive"),
])
def test_bad_input_is_exit_2_and_one_line(capsys, argv, needle):
    code, _, err = run(capsys, *argv)
    assert code == 2
    assert needle in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_bad_config_file_is_exit_2(capsys, tmp_path):
    bad = tmp_path / "c.yaml"
    bad.write_text("hw: {base: {wheel_radius: fast}}\n")
    code, _, err = run(capsys, "--config", str(bad), "sim", "drive")
    assert code == 2 and "hw.base.wheel_radius" in err


def test_bad_world_file_is_exit_2_naming_the_entry(capsys, tmp_path):
    w = tmp_path / "w.yaml"
    w.write_text("name: x\nfloor: {x: 4, y: 4}\nspawn: {x: 1, y: 1}\npots:\n"
                 "  - {id: A, x: 2, y: 2, facing: 0, flower: blue}\n  - {id: B, x: 3, y: 2, facing: 0, blooms: 7}\n")
    code, _, err = run(capsys, "sim", "drive", "--world", str(w))
    assert code == 2 and "pots[0] (id A)" in err and "flower" in err
    assert "pots[1] (id B)" in err and "blooms" in err  # every problem, still one line
    assert len(err.strip().splitlines()) == 1


def test_bench_json_plumbing(capsys, monkeypatch):
    bench._load_all()
    monkeypatch.setitem(bench.BENCHMARKS, "unit.fake", lambda config: bench.Sample([1.0, 2.0, 3.0, 4.0], {"widgets": 7}))
    code, out, _ = run(capsys, "bench", "unit", "--json")
    assert code == 0
    (row,) = [json.loads(line) for line in out.strip().splitlines()]
    assert row == {"name": "unit.fake", "median_ms": 2.5, "p95_ms": 3.85, "n": 4, "widgets": 7}


def test_generate_bays(capsys, tmp_path):
    out = tmp_path / "bays.yaml"
    code, _, _ = run(capsys, "sim", "generate", "--rows", "2", "--pots-per-row", "3", "--seed", "5", "--bays", "2", "-o", str(out))
    assert code == 0 and len(load_world(out).pots) == 12 and len(load_world(out).obstacles) >= 1
    code, _, err = run(capsys, "sim", "generate", "--rows", "2", "--pots-per-row", "3", "--seed", "5", "--bays", "0")
    assert code == 2 and "bays must be a whole number" in err
