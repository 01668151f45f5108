"""walker._jit: numba's njit applied on first use, so that importing walker and running the
compiled path (walker find, walker basin) does not import numba.

The checks that depend on numba not having been imported yet run in a new interpreter
(``_fresh``): in this process other tests may already have called a numba function.
"""

import pickle
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest

from walker import _jit

ROOT = Path(__file__).resolve().parents[1]


def _fresh(code: str) -> str:
    """Run ``code`` in a new interpreter from the repository root; its stdout."""
    proc = subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=600,
    )
    assert proc.returncode == 0, proc.stderr
    return proc.stdout


def test_find_and_basin_do_not_import_numba():
    """The compiled path end to end: a kneed fixed point and a small compass basin, through
    the public API, with numba never imported."""
    out = _fresh(
        """
        import sys
        from walker import load_scene
        from walker.basin import basin_map
        from walker.fixedpoint import find_fixed_point
        from walker.stride import StrideMap

        for name in ("kneed_hsu", "compass_goswami"):
            s = load_scene(f"gaits/{name}.toml")
            c = s.compute
            P = StrideMap(s.model, s.params, method=c.method, rtol=c.rtol, atol=c.atol,
                          t_max=c.t_max)
            fp = find_fixed_point(P, P.project(s.state))
            assert fp.success, fp.status
        z = fp.section
        ranges = tuple((z[a] - 0.01, z[a] + 0.01) for a in (0, 1))
        bm = basin_map(P, fp, ranges=ranges, n=(3, 3), n_strides=3, progress=False,
                       executor="serial")
        assert bm.outcome.shape == (3, 3)
        print("numba" in sys.modules)
        """
    )
    assert out.strip() == "False"


def test_first_call_turns_every_lazy_function_into_a_dispatcher():
    """Before a call the model functions are LazyJits; the first call (a model rhs whose
    body calls generated kernels through module globals) compiles, and then the globals of
    the loaded modules, this script's included, hold numba dispatchers."""
    out = _fresh(
        """
        import sys
        import numpy as np
        from walker import _jit
        from walker.models import compass
        from walker._generated import compass as K
        from walker.models.compass import rhs as imported_rhs

        assert type(compass.rhs) is _jit.LazyJit and not _jit.is_live()
        assert "numba" not in sys.modules
        x = np.array([0.2, -0.2, -1.0, -0.3])
        p = np.array([10.0, 5.0, 0.5, 0.5, 0.0, 0.0, 0.0525, 9.81, 0.0, 0.0])
        dx = np.empty(4)
        imported_rhs(0, 0.0, x, p, dx)
        from numba.core.dispatcher import Dispatcher
        assert _jit.is_live()
        for fn in (compass.rhs, compass.swing_foot, K.accel, imported_rhs):
            assert isinstance(fn, Dispatcher), type(fn)
        ref = np.empty(2)
        K.accel.py_func(x[:2], x[2:], p, ref)
        assert np.array_equal(dx[:2], x[2:]) and np.allclose(dx[2:], ref, rtol=1e-14)
        print("ok")
        """
    )
    assert out.strip() == "ok"


def test_lazy_function_calls_and_reads_like_its_dispatcher():
    """Whether or not numba is in use in this process: a LazyJit kept aside calls through,
    reads the dispatcher's attributes and pickles by reference."""
    from walker._generated import compass as K

    kept = [K.mass_matrix]  # kept in a list: not swapped when numba goes live
    q = np.array([0.2, -0.2])
    p = np.array([10.0, 5.0, 0.5, 0.5, 0.0, 0.0, 0.0525, 9.81, 0.0, 0.0])
    out, ref = np.empty((2, 2)), np.empty((2, 2))
    kept[0](q, p, out)
    _jit.dispatcher(kept[0]).py_func(q, p, ref)
    np.testing.assert_array_equal(out, ref)
    assert kept[0].py_func is _jit.dispatcher(kept[0]).py_func
    assert kept[0].__name__ == "mass_matrix"
    assert len(kept[0].signatures) >= 1
    assert pickle.loads(pickle.dumps(kept[0])) is K.mass_matrix


def test_njit_defined_after_first_use_is_a_dispatcher_and_bad_use_is_refused():
    from numba.core.dispatcher import Dispatcher

    from walker.models import compass

    compass.swing_foot(np.zeros(4), np.zeros(10))  # numba is in use from here on

    @_jit.njit(cache=False)
    def twice(x):
        return 2.0 * x

    assert isinstance(twice, Dispatcher) and twice(1.5) == 3.0
    assert _jit.dispatcher(twice) is twice
    with pytest.raises(TypeError, match="njit takes a function or keyword options only"):
        _jit.njit(twice, cache=True)


def test_without_numba_the_compiled_path_runs_and_a_numba_function_names_the_extra(tmp_path):
    """numba is optional: with its import blocked, a fixed point and a stored run of the
    three-link walker work; its plot leaves out the torque figure (numba twins) with a
    one-line warning naming the function and the extra, and writes the others; a numba
    function called from the API raises NumbaMissing."""
    run_file, figures = tmp_path / "run.h5", tmp_path / "figures"
    out = _fresh(
        f"""
        import contextlib, io, sys
        sys.modules["numba"] = None  # `import numba` raises ImportError
        from walker import _jit
        from walker.cli import main
        from walker.models import compass

        assert main(["find", "gaits/compass_goswami.toml"]) == 0
        assert main(["run", "gaits/three_link_grizzle.toml", "--out", {str(run_file)!r}]) == 0
        err = io.StringIO()
        with contextlib.redirect_stderr(err):
            code = main(["plot", {str(run_file)!r}, "--out", {str(figures)!r}])
        print("plot", code, err.getvalue().strip().replace("\\n", " | "))
        try:
            compass.swing_foot([0.1, -0.1, 0.0, 0.0], [0.0] * 10)
        except _jit.NumbaMissing as exc:
            print("api", exc)
        """
    )
    lines = out.strip().splitlines()
    plot = next(ln for ln in lines if ln.startswith("plot "))
    api = next(ln for ln in lines if ln.startswith("api "))
    assert plot.startswith("plot 0 walker: warning: no torque figure: "), plot
    assert "walker.models.three_link.torques is compiled by numba" in plot and "|" not in plot
    assert "walker-hybrid[numba]" in plot
    written = sorted(p.name for p in figures.iterdir())
    assert "run_angles.png" in written and "run_zero_dynamics.png" in written, written
    assert not any("torques" in name for name in written)
    assert "walker.models.compass.swing_foot is compiled by numba" in api
    assert "python -m pip install 'walker-hybrid[numba]'" in api


def test_a_hybrid_system_of_numba_twins_not_yet_compiled_is_bridged():
    """A HybridSystem made of a model module's functions while they are still LazyJits
    (numba not yet in use) is bridged to the C integrator like numba dispatchers: one
    compass stride bit for bit as the compiled general entry (its C port, tests/
    test_models_c.py)."""
    out = _fresh(
        """
        import numpy as np
        from walker import _jit, load_scene
        from walker.integrate import HybridSystem, hybrid_solve
        from walker.models import compass, get_model

        assert type(compass.rhs) is _jit.LazyJit and not _jit.is_live()
        compiled = get_model("compass").system
        twins = HybridSystem(
            name="compass twins", n_x=4, n_phases=1, n_guards=3, n_impulse=2,
            directions=compass.DIRECTIONS, phase_names=compass.PHASE_NAMES,
            guard_names=compass.GUARD_NAMES, n_params=10,
            rhs=compass.rhs, guards=compass.guards, reset=compass.reset, jac=compass.jac,
        )
        s = load_scene("gaits/compass_goswami.toml")
        p = s.params.as_array()
        a = hybrid_solve(compiled, s.state, p, rtol=1e-12, atol=1e-12, jacobian=True)
        b = hybrid_solve(twins, s.state, p, rtol=1e-12, atol=1e-12, jacobian=True)
        assert a.status == b.status and a.n_strides == b.n_strides == 1
        assert np.array_equal(a.x, b.x) and a.t == b.t and np.array_equal(a.jac, b.jac)
        print(_jit.is_live())
        """
    )
    assert out.strip() == "True"


def test_a_lazy_function_made_directly_after_numba_is_live_compiles_alone():
    from walker.models import compass

    compass.swing_foot(np.zeros(4), np.zeros(10))  # numba is in use from here on
    lazy = _jit.LazyJit(lambda x: x + 1.0, {"cache": False})
    assert lazy(1.0) == 2.0
    assert _jit.dispatcher(lazy) is lazy._dispatcher is not None


def test_first_calls_from_two_threads_at_once():
    """Two threads make the process's first numba calls at the same moment (different
    models, each calling generated kernels through module globals): both get numba's
    result."""
    out = _fresh(
        """
        import threading
        import numpy as np
        from walker.models import compass, kneed

        start = threading.Barrier(2)
        results = {}

        def call(name, fn, x, p):
            start.wait()
            dx = np.empty(len(x))
            fn(0, 0.0, x, p, dx)
            results[name] = bool(np.isfinite(dx).all())

        from walker import load_scene

        jobs = []
        for name, fn in (("compass", compass.rhs), ("kneed", kneed.rhs)):
            scene = load_scene(f"gaits/{name}_{'goswami' if name == 'compass' else 'hsu'}.toml")
            jobs.append((name, fn, np.asarray(scene.state, float), scene.params.as_array()))
        threads = [threading.Thread(target=call, args=job) for job in jobs]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        print(sorted(results.items()))
        """
    )
    assert out.strip() == "[('compass', True), ('kneed', True)]"
