"""The dashboard's unit on the robot: the runtime's config (so the runtime's history and state
directory), on the farm network with a password (never --open there), not restarted on bad input."""
from __future__ import annotations

import shlex

from lupin.cli.web import is_loopback, parse_listen
from tests.hw.test_deploy import unit


def test_the_web_unit_serves_the_robots_history_behind_a_password():
    s = unit("lupin-web.service")["Service"]
    argv = shlex.split(s["ExecStart"])
    assert argv[1:4] == ["--config", "/etc/lupin/config.yaml", "web"] and "--open" not in argv
    assert not is_loopback(parse_listen(argv[argv.index("--listen") + 1])[0])
    assert s["User"] == "lupin" and s["StateDirectory"] == "lupin" and s["RestartPreventExitStatus"] == "2"
