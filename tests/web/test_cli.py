"""`lupin web`'s command line: the password stored hashed, and the refusals (exit 2, one line)."""
from __future__ import annotations

import io

import pytest

from lupin.cli import main
from web.auth import FILE, verify


@pytest.fixture
def state(tmp_path, monkeypatch):
    monkeypatch.setenv("LUPIN_RUNTIME__STATE_DIR", str(tmp_path / "state"))
    return tmp_path / "state"


def test_set_password_stores_a_salted_hash_only_its_owner_reads(state, monkeypatch, capsys):
    monkeypatch.setattr("sys.stdin", io.StringIO("tomato-truss-7\n"))
    assert main(["web", "--set-password"]) == 0
    stored = (state / FILE).read_text()
    assert "tomato" not in stored and stored.startswith("scrypt$") and verify("tomato-truss-7", stored)
    assert not verify("tomato-truss-8", stored) and (state / FILE).stat().st_mode & 0o077 == 0
    monkeypatch.setattr("sys.stdin", io.StringIO("tomato-truss-7\n"))
    main(["web", "--set-password"])
    assert (state / FILE).read_text() != stored  # a new salt each time


@pytest.mark.parametrize("argv, says", [
    (["web", "--set-password"], "too short"),
    (["web", "--open", "--listen", "0.0.0.0:8080"], "127.0.0.1 only"),
    (["web", "--listen", "127.0.0.1:8080"], "no password set"),
    (["web", "--open", "--listen", "localhost"], "--listen localhost: give HOST:PORT"),
    (["web", "--open", "--runs", "/nonexistent/runs"], "--runs /nonexistent/runs: not a directory"),
])
def test_bad_input_is_one_line_and_exit_2(state, monkeypatch, capsys, argv, says):
    monkeypatch.setattr("sys.stdin", io.StringIO("short\n"))
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert says in err and len(err.strip().splitlines()) == 1 and "Traceback" not in err


def test_a_history_that_is_not_there_is_exit_2(state, tmp_path, capsys):
    assert main(["web", "--open", "--history", str(tmp_path / "none.db")]) == 2
    assert "no history database there" in capsys.readouterr().err
