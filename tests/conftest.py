"""Keeps the fast lane fast: ``pytest -m "not slow"`` is the edit-test loop, so a test that
compiles a MuJoCo model (every sim run and every render starts there) must be marked ``slow``.

While a test that is not marked slow is set up and run, the model builders are wrapped to note
the build (the test itself runs unchanged, so a CLI that turns errors into exit codes cannot
hide it), and the test then fails with one line saying what to mark. Tests that only start a
real-time service or a ``lupin`` subprocess are not seen here: they are marked by hand.
"""
from __future__ import annotations

import contextlib

import pytest

import sim  # noqa: F401  (selects EGL rendering before mujoco is first imported)
import mujoco  # noqa: E402

BUILDERS = ("from_xml_string", "from_xml_path", "from_binary_path")


@contextlib.contextmanager
def _noting_builds(item: pytest.Item):
    if item.get_closest_marker("slow") is not None:
        yield []
        return
    built: list[str] = []
    originals = {name: vars(mujoco.MjModel)[name] for name in BUILDERS}

    def noting(name):
        builder = getattr(mujoco.MjModel, name)

        def build(*args, **kwargs):
            built.append(name)
            return builder(*args, **kwargs)
        return staticmethod(build)

    for name in BUILDERS:
        setattr(mujoco.MjModel, name, noting(name))
    try:
        yield built
    finally:
        for name, raw in originals.items():
            setattr(mujoco.MjModel, name, raw)


@pytest.hookimpl(wrapper=True)
def pytest_runtest_setup(item):
    with _noting_builds(item) as built:
        result = yield
    _fail_if_built(item, built, "its fixtures build")
    return result


@pytest.hookimpl(wrapper=True)
def pytest_runtest_call(item):
    with _noting_builds(item) as built:
        result = yield
    _fail_if_built(item, built, "it builds")
    return result


def _fail_if_built(item: pytest.Item, built: list[str], what: str) -> None:
    if built:
        pytest.fail(f"{item.nodeid}: {what} a MuJoCo model (MjModel.{built[0]}) but is not marked slow: "
                    "add pytestmark = pytest.mark.slow (or @pytest.mark.slow)", pytrace=False)


@pytest.fixture(autouse=True, scope="session")
def _no_shared_history():
    """Patrols run by tests record no history unless a test names a database: by default a patrol
    records into ./lupin-history.db and reports its changes against the previous patrol of the
    mission, which, shared by tests running in parallel, would make each report depend on the
    others. Forced, not defaulted: a ``LUPIN_HISTORY__URL`` exported in the shell (a farm
    server's) must never receive test patrols (tests/history/test_isolation.py). The history's
    own tests set ``--history`` or ``LUPIN_HISTORY__URL`` themselves."""
    import os

    os.environ["LUPIN_HISTORY__URL"] = "none"
    yield
