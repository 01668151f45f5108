"""docs/measures.md is true: its Python examples run as doctests, its commands exit 0, and
the numbers its prose quotes are the ones the commands print."""

from __future__ import annotations

import contextlib
import doctest
import io
import json
import shlex
from pathlib import Path

import pytest

from walker.cli import main

ROOT = Path(__file__).resolve().parent.parent
DOC = ROOT / "docs" / "measures.md"


def _commands() -> list[list[str]]:
    lines = DOC.read_text(encoding="utf-8").splitlines()
    return [shlex.split(line[2:])[1:] for line in lines if line.startswith("$ walker ")]


def _run(argv) -> str:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = main(argv)
    assert code == 0, (argv, buf.getvalue())
    return buf.getvalue()


@pytest.mark.slow
def test_examples_run_as_doctests(monkeypatch):
    monkeypatch.chdir(ROOT)
    text = DOC.read_text(encoding="utf-8")
    parser = doctest.DocTestParser()
    test = parser.get_doctest(text, {}, "measures.md", str(DOC), 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS)
    runner.run(test)
    assert runner.failures == 0 and runner.tries >= 6


def test_gsn_and_stepdown_numbers_are_the_commands(monkeypatch):
    monkeypatch.chdir(ROOT)
    text = DOC.read_text(encoding="utf-8")
    commands = {argv[0]: argv for argv in _commands()}
    assert set(commands) == {"mfpt", "gsn", "stepdown"}
    gsn = json.loads(_run([*commands["gsn"], "--json"]))
    assert f"{gsn['gsn']:.6f} for this gait" in text
    steps = json.loads(_run([*commands["stepdown"], "--json"]))
    assert f"step down of {steps['step_down']:.6f} m" in text
    assert f"step up of {steps['step_up']:.6f} m" in text


@pytest.mark.slow
def test_mfpt_command_prints_the_documented_keys(monkeypatch):
    monkeypatch.chdir(ROOT)
    (argv,) = [a for a in _commands() if a[0] == "mfpt"]
    record = json.loads(_run(argv))
    for key in ("mfpt", "mfpt_stderr", "runs", "failed", "rate", "failures", "mfpt_markov"):
        assert key in record
    assert "mfpt_markov_start" in record and record["markov"]["levels"]
