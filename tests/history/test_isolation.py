"""An exported ``LUPIN_HISTORY__URL`` (the farm server's, on a developer's shell or the robot)
never receives the tests' patrols: tests/conftest.py forces the tests' own history location."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from lupin.cli.patrol import open_patrol_history
from mission.runtime.config import load_config

ROOT = Path(__file__).resolve().parents[2]


def test_a_patrol_in_the_tests_records_nowhere_by_default():
    """What every test sees: the configured history is off, so a patrol records nothing."""
    assert os.environ["LUPIN_HISTORY__URL"] == "none"
    assert open_patrol_history(load_config(), None) is None


@pytest.mark.slow
def test_an_exported_history_url_is_overridden_for_the_tests(tmp_path):
    exported = tmp_path / "farm-server.db"
    env = {**os.environ, "LUPIN_HISTORY__URL": str(exported)}
    done = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:xdist",
                           f"{Path(__file__).relative_to(ROOT)}::test_a_patrol_in_the_tests_records_nowhere_by_default"],
                          cwd=ROOT, env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0 and "1 passed" in done.stdout, done.stdout + done.stderr
    assert not exported.exists()  # nothing was opened, let alone written, there
    assert load_config(env=env).history.url == str(exported)  # the variable does name it outside the tests
