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
        assert proc.stdout.readline().startswith("lupin serve: sim backend, world 'default'")
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


@pytest.mark.slow
def test_a_crashed_service_comes_back_with_the_soft_stop_engaged(tmp_path):
    """ISO 13850: a restart never releases a stop. The operator engages the soft stop, the
    service is killed (SIGKILL: no clean exit), systemd starts it again: it comes back engaged,
    and only a console's release clears it; a clean stop after that starts released."""
    endpoint = free_endpoint()
    lupin = str(Path(sys.executable).parent / "lupin")
    env = {**os.environ, "LUPIN_LINK__TOKEN": "t0k", "LUPIN_LINK__COMMAND_TIMEOUT": "8",
           "LUPIN_RUNTIME__STATE_DIR": str(tmp_path / "state")}

    def start():
        proc = subprocess.Popen([lupin, "serve", "--listen", endpoint, "--runs", str(tmp_path / "runs")],
                                stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, env=env)
        while f"on {endpoint}" not in proc.stdout.readline():  # listening: a console may connect
            assert proc.poll() is None, "lupin serve did not start"
        c = LinkClient(endpoint, "mirte", clock=time.monotonic, token="t0k", timeout=10.0)
        assert wait_for(lambda: c.view().connected and c.view().controllers, 30)
        return proc, c

    proc, c = start()
    try:
        assert not c.view().estop_engaged
        assert c.send("estop", engaged=True) is None
        assert wait_for(lambda: c.view().estop_engaged, 5)
    finally:
        c.close()
        proc.kill()
        proc.wait(timeout=30)
    proc, c = start()  # "systemd" restarts it
    try:
        assert wait_for(lambda: c.view().estop_engaged, 5), "a crashed runtime came back released"
        assert "did not exit cleanly" in c.view().estop_why
        assert c.send("estop", engaged=False) is None
        assert wait_for(lambda: not c.view().estop_engaged, 5)
    finally:
        c.close()
        proc.send_signal(signal.SIGTERM)
        proc.communicate(timeout=30)
    proc, c = start()  # after a clean stop with the stop released: released
    try:
        time.sleep(1.0)
        assert not c.view().estop_engaged
    finally:
        c.close()
        proc.send_signal(signal.SIGTERM)
        proc.communicate(timeout=30)
