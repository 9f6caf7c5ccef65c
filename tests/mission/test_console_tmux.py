"""`lupin console --sim` driven as a person would: in a real terminal (tmux), keys pressed, the
screen read back. It starts its own simulated robot (a child `lupin serve`), so this is the
whole product end to end: terminal -> Textual -> Zenoh -> runtime -> sim, and back."""
from __future__ import annotations

import os
import subprocess
import sys
import time
import uuid
from pathlib import Path

import pytest

pytestmark = pytest.mark.slow

LUPIN = str(Path(sys.executable).parent / "lupin")


def tmux(*args: str) -> str:
    return subprocess.run(["tmux", *args], capture_output=True, text=True, check=False).stdout


def screen(session: str) -> str:
    return tmux("capture-pane", "-p", "-t", session)


def wait_screen(session: str, *words: str, timeout: float = 60.0) -> str:
    end = time.monotonic() + timeout
    text = ""
    while time.monotonic() < end:
        text = screen(session)
        if all(w in text for w in words):
            return text
        time.sleep(0.25)
    raise AssertionError(f"never saw {words} on the screen; last screen:\n{text}")


def serve_children(cwd: Path) -> list[int]:
    """``lupin serve`` processes started in ``cwd`` (other tests may run their own elsewhere)."""
    out = subprocess.run(["pgrep", "-f", "lupin serve --listen"], capture_output=True, text=True).stdout
    pids = []
    for pid in map(int, out.split()):
        try:
            if Path(os.readlink(f"/proc/{pid}/cwd")) == cwd:
                pids.append(pid)
        except OSError:
            pass
    return pids


def test_console_sim_as_a_person_uses_it(tmp_path):
    session = f"lupin-{uuid.uuid4().hex[:8]}"
    tmux("new-session", "-d", "-s", session, "-x", "200", "-y", "55", "-c", str(tmp_path),
         f"env -u COLUMNS -u LINES {LUPIN} console --sim; sleep 30")  # the terminal's size, not pytest's
    try:
        wait_screen(session, "mirte", "idle", timeout=90)  # the robot is up and its telemetry arrives
        tmux("send-keys", "-t", session, "m")  # start the mission
        wait_screen(session, "running", "P01", timeout=30)
        tmux("send-keys", "-t", session, "Space")  # soft e-stop
        wait_screen(session, "E-STOP ENGAGED", "wheels: estop", timeout=30)
        tmux("send-keys", "-t", session, "Space")  # a second press never releases
        tmux("send-keys", "-t", session, "u")  # release: the mission stays held until resumed
        wait_screen(session, "e-stop released: r to resume", "mission: estop", timeout=30)
        tmux("send-keys", "-t", session, "r")
        wait_screen(session, "e-stop clear", "mission: running", timeout=30)
        tmux("send-keys", "-t", session, "c")
        wait_screen(session, "Clear the map?", timeout=30)  # asks first
        tmux("send-keys", "-t", session, "n")
        end = time.monotonic() + 10
        while "Clear the map?" in screen(session) and time.monotonic() < end:
            time.sleep(0.2)
        assert "Clear the map?" not in screen(session)
        tmux("send-keys", "-t", session, "C-q")  # quit the console: its child service stops too
        end = time.monotonic() + 40
        while time.monotonic() < end and serve_children(tmp_path):
            time.sleep(0.5)
        assert not serve_children(tmp_path)
        assert (tmp_path / "lupin-runs").is_dir()  # the patrol that was running was finished (aborted)
    finally:
        tmux("kill-session", "-t", session)
