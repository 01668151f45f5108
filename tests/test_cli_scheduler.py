"""``--scheduler`` of ``walker basin``, ``walker sweep`` and ``walker orbit-diagram``: the
tasks (chunks of grid rows, of points, blocks of values) run on a dask.distributed cluster
and give the table computed on this machine; an unreachable scheduler is one line, exit 2."""

from __future__ import annotations

import numpy as np
import pytest

from walker.cli import main
from walker.storage import read

COMPASS = "gaits/compass_goswami.toml"
SIMPLEST = "gaits/simplest_garcia.toml"


def _commands(tmp_path, tag):
    return {
        "basin": [
            "basin",
            COMPASS,
            "--n",
            "6",
            "--strides",
            "5",
            "--quiet",
            "--out",
            str(tmp_path / f"basin{tag}.h5"),
        ],
        "sweep": [
            "sweep",
            COMPASS,
            "--param",
            "slope=0.04:0.06:4",
            "--param",
            "mass_hip=8,12",
            "--quiet",
            "--out",
            str(tmp_path / f"sweep{tag}.h5"),
        ],
        "orbit": [
            "orbit-diagram",
            SIMPLEST,
            "--range",
            "0.015:0.019",
            "--n",
            "13",
            "--transient",
            "60",
            "--strides",
            "8",
            "--chains",
            "3",
            "--quiet",
            "--out",
            str(tmp_path / f"orbit{tag}.h5"),
        ],
    }


@pytest.mark.parametrize("command", ["basin", "sweep", "orbit"])
def test_unreachable_scheduler_is_one_line_exit_2(tmp_path, capsys, command):
    pytest.importorskip("distributed")
    argv = _commands(tmp_path, "")[command]
    assert main([*argv, "--scheduler", "tcp://127.0.0.1:1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert (
        err[-1].startswith("walker: error: --scheduler tcp://127.0.0.1:1:") and "connect" in err[-1]
    )


@pytest.mark.slow
def test_local_cluster_gives_the_local_tables(tmp_path, capsys):
    distributed = pytest.importorskip("distributed")
    local = _commands(tmp_path, "-local")
    remote = _commands(tmp_path, "-dask")
    with distributed.LocalCluster(
        n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None
    ) as cluster:
        for name in local:
            assert main(local[name]) == 0, name
            assert main([*remote[name], "--scheduler", cluster.scheduler_address]) == 0, name
            a, b = read(local[name][-1])[0], read(remote[name][-1])[0]
            fields = {"basin": ("outcome", "strides"), "orbit": ("values",)}.get(name)
            if fields is None:
                for column in a.columns:
                    assert np.array_equal(a.columns[column], b.columns[column], equal_nan=True)
            for field in fields or ():
                assert np.array_equal(getattr(a, field), getattr(b, field), equal_nan=True)
    capsys.readouterr()
