"""The command line's version flag, ``python -m walker`` and strict JSON output."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from walker import __version__
from walker.cli import main

ROOT = Path(__file__).resolve().parents[1]


def _strict_loads(text):
    """json.loads that refuses NaN and Infinity, as strict (RFC 8259) parsers do."""

    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def test_version_flag(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--version"])
    assert exc.value.code == 0
    assert capsys.readouterr().out.strip() == f"walker {__version__}"


def test_python_dash_m_walker_runs_the_cli():
    out = subprocess.run(
        [sys.executable, "-m", "walker", "--version"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        check=True,
    )
    assert out.stdout.strip() == f"walker {__version__}"


def test_failed_find_json_is_strict_with_null_for_missing_numbers(capsys):
    # No period-one gait of the Hsu Chen walker exists at this slope: the search fails and the
    # state it reports is NaN, which must come out as null.
    code = main(["find", str(ROOT / "gaits/kneed_hsu.toml"), "--set", "slope=0.3", "--json"])
    assert code == 1
    record = _strict_loads(capsys.readouterr().out)
    assert record["success"] is False
    assert any(v is None for v in record["state"])


def test_successful_find_json_is_strict(capsys):
    code = main(["find", str(ROOT / "gaits/compass_goswami.toml"), "--json"])
    assert code == 0
    record = _strict_loads(capsys.readouterr().out)
    assert record["success"] is True
    assert all(isinstance(v, float) for v in record["state"])
