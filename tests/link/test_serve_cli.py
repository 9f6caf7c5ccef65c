"""`lupin serve` as a user runs it: it says where it listens and the token, consoles attach,
SIGTERM stops it cleanly; bad options are exit 2 before anything starts."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from lupin.cli import main
from mission.link.client import LinkClient
from mission.link.server import free_endpoint
from tests.link.sim_service import wait_for


@pytest.mark.slow
def test_serve_prints_its_token_answers_a_console_and_stops_on_sigterm(tmp_path):
    endpoint = free_endpoint()
    lupin = str(Path(sys.executable).parent / "lupin")
    proc = subprocess.Popen([lupin, "serve", "--listen", endpoint, "--runs", str(tmp_path)],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env={**os.environ, "LUPIN_LINK__TOKEN": "", "LUPIN_LINK__COMMAND_TIMEOUT": "8"})
    try:
        line = proc.stdout.readline()
        assert f"on {endpoint}" in line and "operator token" in line
        token = line.rsplit(" ", 1)[-1].strip()
        c = LinkClient(endpoint, "mirte", clock=time.monotonic, token=token, timeout=10.0)
        try:
            assert wait_for(lambda: c.view().connected and c.view().controllers, 20)
            assert c.send("arm_preset", name="tuck") is None
            assert "unknown" in c.send("arm_preset", name="wave").lower()
        finally:
            c.close()
        proc.send_signal(signal.SIGTERM)
        out, _ = proc.communicate(timeout=30)
        assert proc.returncode == 0 and "stopped" in out
    finally:
        if proc.poll() is None:
            proc.kill()


@pytest.mark.parametrize("args, words", [
    (["--listen", "nonsense"], "--listen nonsense"),
    (["--backend", "hw", "--world", "x.yaml"], "--world"),
    (["--world", "no/such.yaml"], "no/such.yaml"),
])
def test_bad_options_are_exit_2(capsys, args, words):
    assert main(["serve", *args]) == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err


def test_foxglove_port_is_optional_on_the_command_line():
    from lupin.cli import complete_optional_values

    assert complete_optional_values(["serve", "--foxglove"]) == ["serve", "--foxglove", "8765"]
    assert complete_optional_values(["serve", "--foxglove", "--listen", "x"]) == ["serve", "--foxglove", "8765", "--listen", "x"]
    assert complete_optional_values(["serve", "--foxglove", "9000"]) == ["serve", "--foxglove", "9000"]


@pytest.mark.parametrize("args, words", [
    ([], "exactly one of --sim or --connect"),
    (["--sim", "--connect", "tcp/127.0.0.1:7447"], "exactly one of"),
    (["--connect", "tcp/127.0.0.1:7447", "--world", "w.yaml"], "--world goes with --sim"),
    (["--connect", "127.0.0.1"], "not a Zenoh endpoint"),
])
def test_console_bad_options_are_exit_2(capsys, args, words):
    assert main(["console", *args]) == 2
    err = capsys.readouterr().err
    assert words in err and "Traceback" not in err
