"""walker without numba: numba is only the optional extra for a user's own @njit system, so
the whole package imports and every command works with it absent.

A fresh interpreter with numba blocked (``sys.modules["numba"] = None``, so ``import numba``
raises ImportError as if it were not installed) imports every module of the package and runs
the commands: find, run and plot of the kneed walker's gait, an actuated walker's run and its
figures (the torque figure comes from the compiled controller), continue, basin, sweep,
orbit-diagram, models, params and scene new.  Each must exit 0 and numba must stay
unimported.
"""

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]

SCRIPT = textwrap.dedent(
    """
    import importlib, os, pkgutil, sys
    sys.modules["numba"] = None  # `import numba` raises ImportError: as if not installed
    import walker
    for info in pkgutil.walk_packages(walker.__path__, "walker."):
        importlib.import_module(info.name)
    from walker.cli import main
    out = sys.argv[1]
    commands = [
        ["find", "gaits/kneed_hsu.toml", "--out", f"{out}/gait.h5"],
        ["run", "gaits/kneed_hsu.toml", "--out", f"{out}/run.h5"],
        ["plot", f"{out}/run.h5", "--out", f"{out}/figures"],
        ["run", "gaits/three_link_grizzle.toml", "--out", f"{out}/three.h5"],
        ["plot", f"{out}/three.h5", "--out", f"{out}/three"],
        ["continue", "gaits/compass_goswami.toml", "--param", "slope", "--to", "0.0524",
         "--step", "0.00002", "--natural", "--out", f"{out}/branch.h5"],
        ["basin", "gaits/simplest_garcia.toml", "--n", "3", "--strides", "3", "--jobs", "1",
         "--quiet", "--out", f"{out}/basin.h5"],
        ["sweep", "gaits/compass_goswami.toml", "--param", "slope=0.05:0.06:2", "--jobs", "1",
         "--quiet", "--out", f"{out}/sweep.h5"],
        ["orbit-diagram", "gaits/simplest_garcia.toml", "--param", "slope", "--range",
         "0.009:0.01", "--n", "2", "--transient", "2", "--strides", "2",
         "--out", f"{out}/orbit.h5"],
        ["models"],
        ["params", "three_link"],
        ["scene", "new", "compass", "--out", f"{out}/new.toml"],
    ]
    for args in commands:
        code = main(args)
        assert code == 0, (args, code)
    figures_of = sorted(os.listdir(f"{out}/three"))
    assert any("torques" in name for name in figures_of), figures_of
    assert sys.modules["numba"] is None  # nothing imported numba behind the block
    print("ok")
    """
)


@pytest.mark.slow
def test_every_command_works_without_numba(tmp_path):
    proc = subprocess.run(
        [sys.executable, "-c", SCRIPT, str(tmp_path)],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip().endswith("ok"), proc.stdout[-2000:]


@pytest.mark.slow  # a fresh interpreter: the integration tier
def test_package_imports_and_finds_a_gait_without_numba(tmp_path):
    """The quick version for the default suite: every module imports, and ``walker find``
    and the checked calls of a compiled model run, with numba blocked."""
    script = textwrap.dedent(
        """
        import importlib, pkgutil, sys
        sys.modules["numba"] = None
        import walker
        for info in pkgutil.walk_packages(walker.__path__, "walker."):
            importlib.import_module(info.name)
        from walker.cli import main
        assert main(["find", "gaits/kneed_hsu.toml"]) == 0
        model = walker.get_model("three_link")
        scene = walker.load_scene("gaits/three_link_grizzle.toml")
        assert model.torques(scene.state, scene.params).shape == (2,)
        assert sys.modules["numba"] is None
        print("ok")
        """
    )
    proc = subprocess.run(
        [sys.executable, "-c", script], cwd=REPO, capture_output=True, text=True, timeout=600
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert proc.stdout.strip().endswith("ok"), proc.stdout[-2000:]
