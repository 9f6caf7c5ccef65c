"""pytest collects every ``tests/scenarios/*.yaml`` as a test item: a user adds a scenario by
adding a file, no Python. Each runs through the same runner as ``lupin scenario run`` and fails
with the expectations that did not hold (what was expected, what happened). Marked ``slow``:
each is a whole simulated patrol."""
from __future__ import annotations

import pytest

from fleet.scenario_runner import run_any
from mission.scenario.scenario_file import load_scenario


def pytest_collect_file(parent, file_path):
    if file_path.suffix == ".yaml" and file_path.parent == parent.config.rootpath / "tests" / "scenarios":
        return ScenarioFile.from_parent(parent, path=file_path)
    return None


class ScenarioFile(pytest.File):
    def collect(self):
        item = ScenarioItem.from_parent(self, name=self.path.stem)
        item.add_marker(pytest.mark.slow)
        yield item


class ScenarioFailed(Exception):
    pass


class ScenarioItem(pytest.Item):
    def runtest(self):
        scenario = load_scenario(self.path)
        result = run_any(scenario, self.config._tmp_path_factory.mktemp(self.name))
        if not result.passed:
            raise ScenarioFailed("\n".join(c.line() for c in result.checks if not c.passed) + f"\nreport: {result.report}")

    def repr_failure(self, excinfo):
        if isinstance(excinfo.value, ScenarioFailed):
            return f"scenario {self.name} failed:\n{excinfo.value}"
        return super().repr_failure(excinfo)

    def reportinfo(self):
        return self.path, 0, f"scenario: {self.name}"
