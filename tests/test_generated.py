"""The generated C kernels in walker/_generated/ (compiled into walker._hybrid) against a
fresh derivation, by numbers.

Staleness is caught by evaluating every compiled kernel (through the kernel registry
``walker._hybrid.kernels()`` and the checked calls of walker/models/_compiled.py) and a fresh
``sympy.lambdify`` of the same symbolic expression (re-derived now by
:func:`walker.symbolic.kernels.kernels_for`) at random states and parameter vectors — never
by comparing text, which changes between sympy versions.  The structural variants
("compass/plain.accel", ...) are compared with the general expression at parameter vectors
whose zeroed entries are 0.  The stamp in each file's header is checked too, and the course's
double pendulum is simulated with the generated kernels to check energy conservation.
"""

from __future__ import annotations

import importlib
import re
from functools import cache
from pathlib import Path

import numpy as np
import pytest
import sympy as sp
from numpy.testing import assert_allclose
from scipy.integrate import solve_ivp

from walker.models import get_model
from walker.models._compiled import _kernel_table as kernel_table
from walker.models._compiled import call_kernel
from walker.symbolic import codegen, codegen_c
from walker.symbolic.kernels import (
    C_MODULES,
    C_VARIANTS,
    GENERATED_MODULES,
    VARIANT_SIMPLIFICATION,
    fused_name,
    kernels_for,
    variant_kernels,
)

N_SAMPLES = 100
RTOL = 1e-12

# Sampling ranges of the parameters, by name (every parameter of every generated module).
PARAM_RANGES = {
    # compass / kneed / double pendulum / three-link masses [kg] and inertias [kg m^2]
    # (Westervelt et al. 2007, model_params_three_link.m: Mh = 15, m = 5, Mt = 10)
    "mass_hip": (0.5, 20.0),
    "mass_leg": (0.5, 5.0),
    "mass_thigh": (0.1, 2.0),
    "mass_shank": (0.02, 1.0),
    "mass_1": (0.2, 3.0),
    "mass_2": (0.2, 3.0),
    "inertia_leg": (0.0, 0.5),
    "inertia_thigh": (0.001, 0.1),
    "inertia_shank": (0.001, 0.1),
    "inertia_1": (0.0, 1.0),
    "inertia_2": (0.0, 1.0),
    "mass_torso": (0.5, 15.0),
    "inertia_torso": (0.0, 1.0),
    "rotor_inertia": (0.0, 1.0),  # reflected rotor inertia; RABBIT 0.83 (Chevallereau 2003)
    # lengths [m]
    "com_from_foot": (0.2, 1.0),
    "com_to_hip": (0.2, 1.0),
    "shank_com_from_foot": (0.05, 0.6),
    "shank_com_to_knee": (0.05, 0.6),
    "thigh_com_from_knee": (0.05, 0.6),
    "thigh_com_to_hip": (0.05, 0.6),
    "offset_thigh": (-0.1, 0.1),
    "offset_shank": (-0.1, 0.1),
    "foot_radius": (0.0, 0.3),
    "length_1": (0.3, 2.0),
    "length_2": (0.3, 2.0),
    "com_1": (-0.5, 1.5),
    "com_2": (-0.5, 1.5),
    "leg_length": (0.5, 2.0),
    "torso_length": (0.1, 1.0),  # hip to the torso's mass (L = 0.5 in Westervelt et al.)
    # five-link walker (RABBIT, Westervelt, Grizzle, Koditschek 2003, Table I: M_f = 6.8,
    # M_t = 3.2 kg, I_f = 0.47, I_t = 0.20 kg m^2, L_f = L_t = 0.4, p_MT = 0.24, p_Mf = 0.11,
    # p_Mt = 0.24 m)
    "mass_femur": (0.5, 10.0),
    "mass_tibia": (0.5, 5.0),
    "inertia_femur": (0.0, 1.0),
    "inertia_tibia": (0.0, 0.5),
    "length_femur": (0.2, 0.6),
    "length_tibia": (0.2, 0.6),
    "com_torso": (0.0, 0.6),
    "com_femur": (0.0, 0.4),
    "com_tibia": (0.0, 0.4),
    # slope [rad], gravity [m/s^2]
    "slope": (-0.2, 0.2),
    "g": (1.0, 20.0),
    # viscous joint damping [N m s/rad] (the simplest walker's damping_ankle is
    # dimensionless, in units of M l^2 sqrt(g/l))
    "damping_hip": (0.0, 5.0),
    "damping_knee": (0.0, 1.0),
    "damping_ankle": (0.0, 5.0),
    "damping_1": (0.0, 5.0),
    "damping_2": (0.0, 5.0),
    # dry joint friction [N m] (in the parameter vector, read by the model, not the kernels)
    "coulomb_1": (0.0, 5.0),
    "coulomb_2": (0.0, 5.0),
}

GENERATED_DIR = Path(importlib.import_module("walker._generated").__file__).parent


@cache
def kernels(name: str):
    return kernels_for(name)


def _flatten(expr):
    """(output shape, flat list of entries) of a kernel expression, row-major."""
    if isinstance(expr, (list, tuple)):
        mats = list(expr)
        shape = (len(mats), mats[0].rows, mats[0].cols)
        return shape, [m[i, j] for m in mats for i in range(m.rows) for j in range(m.cols)]
    if isinstance(expr, sp.MatrixBase):
        shape = (expr.rows,) if expr.cols == 1 else (expr.rows, expr.cols)
        return shape, [expr[i, j] for i in range(expr.rows) for j in range(expr.cols)]
    return (), [sp.sympify(expr)]


def _sample_args(kernel, rng, n_samples):
    """Random argument arrays, one (n_samples, len(syms)) array per kernel argument."""
    out = []
    for name, syms in kernel.args:
        if name == "p":
            cols = [rng.uniform(*PARAM_RANGES[str(s)], n_samples) for s in syms]
        else:  # angles, hip positions and rates: all O(1)
            cols = [rng.uniform(-np.pi, np.pi, n_samples) for _ in syms]
        out.append(np.column_stack(cols))
    return out


def _reference(kernel, arrays, n_samples):
    """The kernel's output by a fresh lambdify, vectorized over samples: its expression, or
    for a fused acceleration kernel ``qdd = -D^{-1} h`` solved by numpy from fresh D and h."""
    if isinstance(kernel, codegen.AccelKernel):
        D = _evaluate(kernel.args, kernel.D, arrays, n_samples)
        h = _evaluate(kernel.args, kernel.h, arrays, n_samples)
        return np.linalg.solve(D, -h[..., None])[..., 0]
    if isinstance(kernel, codegen.AccelJacobianKernel):
        # d qdd/d q_k = -D^{-1} (dh/dq_k + dD/dq_k qdd), d qdd/d qd = -D^{-1} dh/dqd, from
        # freshly derived D, h and their derivatives, solved by numpy.
        q = [s for name, syms in kernel.args if name == "q" for s in syms]
        qd = [s for name, syms in kernel.args if name == "qd" for s in syms]
        D = _evaluate(kernel.args, kernel.D, arrays, n_samples)
        h = _evaluate(kernel.args, kernel.h, arrays, n_samples)
        dD = _evaluate(kernel.args, [kernel.D.diff(qk) for qk in q], arrays, n_samples)
        hq = _evaluate(kernel.args, kernel.h.jacobian(sp.Matrix(q)), arrays, n_samples)
        hv = _evaluate(kernel.args, kernel.h.jacobian(sp.Matrix(qd)), arrays, n_samples)
        qdd = np.linalg.solve(D, -h[..., None])[..., 0]
        rhs_q = -(hq + np.einsum("skij,sj->sik", dD, qdd))
        return np.linalg.solve(D, np.concatenate([rhs_q, -hv], axis=-1))
    return _evaluate(kernel.args, kernel.expr, arrays, n_samples)


def _evaluate(args, expr, arrays, n_samples):
    """``expr`` by a fresh lambdify over the kernel arguments ``args``, shape (n_samples, ...)."""
    shape, entries = _flatten(expr)
    flat_syms = [s for _, syms in args for s in syms]
    fun = sp.lambdify(flat_syms, entries, "numpy")
    columns = [a[:, j] for a in arrays for j in range(a.shape[1])]
    values = [np.broadcast_to(np.asarray(v, dtype=float), (n_samples,)) for v in fun(*columns)]
    return np.stack(values, axis=-1).reshape((n_samples, *shape))


def _compiled(key, kernel, arrays, k):
    """The compiled kernel ``key`` ("<model>.<kernel>") at sample ``k`` of ``arrays``."""
    args = {name: a[k] for (name, _), a in zip(kernel.args, arrays, strict=True)}
    out = call_kernel(key, args.pop("p"), **args)
    return np.float64(out) if np.ndim(out) == 0 else out


def _p_order(cname: str) -> tuple:
    """The parameter order the kernels of C module ``cname`` take: the ``p = [...]`` line of
    the argument order in its header (the same for every kernel)."""
    orders = {
        tuple(line.split("[", 1)[1].rstrip("]").split(", "))
        for line in (GENERATED_DIR / f"{cname}.h").read_text().splitlines()
        if line.startswith(" *   p = [")
    }
    assert len(orders) == 1, orders
    return orders.pop()


@pytest.mark.parametrize("name", sorted(GENERATED_MODULES))
def test_every_parameter_has_a_sampling_range(name):
    names = set(_p_order(name))
    assert names, f"{name} has no parameter vector"
    missing = sorted(names - set(PARAM_RANGES))
    assert not missing, f"no PARAM_RANGES entry for {missing}"
    for n in names:
        lo, hi = PARAM_RANGES[n]
        assert lo < hi, n


# the two largest derivations (15-20 s each) run with the slow tests
_SLOW_DERIVATIONS = ("compass", "five_link", "kneed")  # full re-derivations: the integration tier


@pytest.mark.parametrize(
    "name",
    [
        pytest.param(n, marks=pytest.mark.slow) if n in _SLOW_DERIVATIONS else n
        for n in sorted(GENERATED_MODULES)
    ],
)
def test_generated_kernels_equal_fresh_derivation(name):
    """Every compiled kernel of every generated module equals a fresh lambdify of its
    expression at 100 random (state, parameter) samples: rtol 1e-12, atol 1e-12 times the
    largest entry of that sample's output (entries that cancel to ~0 carry the rounding of
    the others).  Each structural variant's kernels likewise, at samples whose zeroed
    parameters are 0 (a variant's fused ``accel_and_jac``: its Jacobian columns and its
    accelerations as the last column)."""
    rng = np.random.default_rng(sum(map(ord, name)))
    p_names = _p_order(name)
    registry = kernel_table()
    prefixes = {name: ()} | {f"{name}/{v}": tuple(z) for v, z in C_VARIANTS.get(name, {}).items()}
    checked = set()
    for kernel in kernels(name):
        arrays = _sample_args(kernel, rng, N_SAMPLES)
        for prefix, zeros in prefixes.items():
            zeroed = [a.copy() for a in arrays]
            for z in zeros:
                zeroed[-1][:, p_names.index(z)] = 0.0
            ref = _reference(kernel, zeroed, N_SAMPLES)
            fused = f"{prefix}.{codegen_fused(kernel.name)}"
            targets = [(f"{prefix}.{kernel.name}", ref)]
            if fused in registry:
                accel = _reference(_accel_of(name, kernel), zeroed, N_SAMPLES)
                targets.append((fused, np.concatenate([ref, accel[..., None]], axis=-1)))
            for key, want in targets:
                if key not in registry:
                    continue
                checked.add(key)
                for k in range(N_SAMPLES):
                    got = _compiled(key, kernel, zeroed, k)
                    scale = np.abs(want[k]).max() if want[k].size else 0.0
                    assert_allclose(
                        got, want[k], rtol=RTOL, atol=RTOL * scale, err_msg=f"{key} at sample {k}"
                    )
    listed = {k for k in registry if k.split(".", 1)[0] in prefixes}
    assert checked == listed, sorted(listed - checked)


def codegen_fused(kernel_name: str) -> str:
    """The fused kernel (accelerations and their Jacobian) a variant prints beside an
    ``accel_jac`` kernel (:func:`walker.symbolic.kernels.fused_name`)."""
    return fused_name(kernel_name) if kernel_name.endswith("accel_jac") else ""


def _accel_of(name, jac_kernel):
    """The ``accel`` kernel of the same ``D`` and ``h`` as ``jac_kernel``."""
    target = jac_kernel.name[: -len("_jac")]
    return next(k for k in kernels(name) if k.name == target)


@pytest.mark.parametrize(
    "name",
    [
        pytest.param(n, marks=pytest.mark.slow) if n in _SLOW_DERIVATIONS else n
        for n in sorted(GENERATED_MODULES)
    ],
)
def test_every_kernel_is_generated(name):
    """The extension holds exactly the kernels the generator lists (none missing, none stale),
    each with the argument lengths and output shape of its symbolic kernel."""
    registry = kernel_table()
    expected = [k.name for k in kernels(name)]
    assert [k.split(".", 1)[1] for k in registry if k.split(".", 1)[0] == name] == expected
    for kernel in kernels(name):
        _, _, n_q, n_p, shape = registry[f"{name}.{kernel.name}"]
        assert (n_q, n_p, shape) == codegen_c.kernel_sizes(kernel), kernel.name


@pytest.mark.parametrize("name", sorted(GENERATED_MODULES))
def test_kernel_parameter_order_is_the_params_class_order(name):
    """Every kernel reads ``p`` in the order of the model's parameter dataclass (a prefix of
    it: the actuated walkers append controller and friction fields the kernels do not read),
    so ``params.as_array()`` is what the kernels expect."""
    from walker.params import PARAMS

    names = PARAMS[name].names()
    order = _p_order(name)
    assert names[: len(order)] == order


@pytest.mark.parametrize("name", sorted(GENERATED_MODULES))
def test_generated_header_is_stamped(name):
    """The C files carry the input hash and the sympy version, and the hash compiled into
    the extension (``walker._hybrid.kernel_hashes()``, what results record as the model's
    ``kernel_hash``) is the one stamped on the file."""
    from walker import _hybrid

    stamp = _c_stamp(name)
    assert "generated, do not edit" in stamp["first"]
    assert stamp["sympy"] is not None, "header lacks the sympy version"
    assert stamp["hash"] is not None, "header lacks the input hash"
    assert _hybrid.kernel_hashes()[name] == stamp["hash"]


@pytest.mark.slow  # a full re-derivation: the integration tier
@pytest.mark.parametrize("name", sorted(GENERATED_MODULES))
def test_generated_hash_matches_symbolic_input(name):
    """The stamped hash is ``symbolic_hash`` of today's kernels.  ``srepr`` (and so the
    hash) may legitimately change between sympy versions, so this is only asserted when the
    running sympy is the one that generated the file; the numeric test above is the real
    staleness check either way."""
    stamp = _c_stamp(name)
    if stamp["sympy"] != sp.__version__:
        pytest.skip(
            f"{name}.c was generated with sympy {stamp['sympy']}, running "
            f"{sp.__version__}: hashes of srepr are not comparable across versions"
        )
    assert stamp["hash"] == codegen.symbolic_hash(kernels(name))


def _c_stamp(cname: str) -> dict:
    """Stamps of walker/_generated/<cname>.c and .h (which must be the same)."""
    stamps = []
    for suffix in (".c", ".h"):
        text = (GENERATED_DIR / f"{cname}{suffix}").read_text()
        hash_match = re.search(r"^ \* input hash: sha256:([0-9a-f]{64})$", text, re.M)
        version_match = re.search(r"^ \* sympy (\S+);", text, re.M)
        stamps.append(
            {
                "first": text.splitlines()[0],
                "hash": hash_match.group(1) if hash_match else None,
                "sympy": version_match.group(1) if version_match else None,
            }
        )
    assert stamps[0] == stamps[1], f"{cname}.c and {cname}.h carry different stamps"
    return stamps[0]


def _c_expected_hashes(name: str, digest: str) -> dict:
    """Variant C module name -> the input hash it must carry, given the general C module's
    ``digest`` (:func:`codegen.variant_hash`)."""
    out = {}
    for variant, zeros in C_VARIANTS.get(name, {}).items():
        names = [k.name for k in variant_kernels(name, variant, kernels(name), simplify=False)]
        out[f"{name}_{variant}"] = codegen.variant_hash(
            digest, variant, zeros, names, VARIANT_SIMPLIFICATION
        )
    return out


@pytest.mark.parametrize("name", C_MODULES)
def test_c_files_are_stamped_with_the_input_hash(name):
    """The variants' C files (walker/_generated/<name>_<variant>.c/.h) carry the hash derived
    from the general module's and from the variant's definition, so a variant printed from
    other kernels than the general module beside it is caught without re-deriving anything
    (the general stamp itself is checked above, the kernels' values by the fresh
    derivation)."""
    general = _c_stamp(name)
    for cname, digest in _c_expected_hashes(name, general["hash"]).items():
        stamp = _c_stamp(cname)
        assert "generated, do not edit" in stamp["first"], cname
        assert stamp["sympy"] == general["sympy"], f"{cname} and {name}.c: different sympy"
        assert stamp["hash"] == digest, f"{cname}: stale (regenerate)"


@pytest.mark.parametrize("name", sorted(C_VARIANTS))
def test_variants_are_the_models_variants(name):
    """The generator's structural variants fix exactly the parameters the model declares
    (``VARIANTS`` of walker.models.<name>, which picks the variant at run time)."""
    model = importlib.import_module(f"walker.models.{name}")
    assert {v: set(z) for v, z in C_VARIANTS[name].items()} == {
        v: set(z) for v, z in model.VARIANTS.items()
    }


@pytest.mark.parametrize(
    "cname", sorted(f"{n}_{v}" for n, variants in C_VARIANTS.items() for v in variants)
)
def test_variant_reads_no_zero_parameter_and_shares_trigonometry(cname):
    """A structural variant never reads its zeroed parameters (they contribute no
    arithmetic), and computes the sine and cosine of an angle only once, as
    ``const double sin_<angle> = sin(<angle>);`` or by walker/_core/wk_sincos.h's
    ``wk_sincos(<angle>, &sin_<angle>, &cos_<angle>);`` (``wk_sin``, ``wk_cos`` alone)."""
    name, variant = next(
        (n, v) for n, variants in C_VARIANTS.items() for v in variants if f"{n}_{v}" == cname
    )
    zeros = C_VARIANTS[name][variant]
    text = (GENERATED_DIR / f"{cname}.c").read_text()
    bodies = re.findall(r"^(?:void|double) wk_\w+\(.*?\)\n\{\n(.*?)^\}", text, re.M | re.S)
    prototypes = re.findall(
        r"^(?:void|double) wk_\w+\([^)]*\);$", (GENERATED_DIR / f"{cname}.h").read_text(), re.M
    )
    assert len(bodies) == len(prototypes)
    p_names = _p_order(cname)
    zero_index = {p_names.index(z) for z in zeros}
    for body in bodies:
        read = {int(i) for i in re.findall(r"= p\[(\d+)\];", body)}
        assert not read & zero_index, [p_names[i] for i in read & zero_index]
        calls = re.findall(r"\b(sin|cos)\(([^()]*)\)", body)
        assert len(calls) == len(set(calls))
        for fun, arg in calls:
            assert re.search(rf"const double {fun}_{arg} = {fun}\({arg}\);", body), (fun, arg)
        # wk_sincos.h's: a sine and cosine pair in one call, or one of them alone
        fast = re.findall(r"\bwk_sincos\((\w+), &sin_(\w+), &cos_(\w+)\);", body)
        assert all(a == s == c for a, s, c in fast), fast
        single = re.findall(r"const double (sin|cos)_(\w+) = wk_(sin|cos)\((\w+)\);", body)
        assert all(f == g and a == b for f, a, g, b in single), single
        trig = [("sin", a) for a, _, _ in fast] + [("cos", a) for a, _, _ in fast]
        trig += [(f, a) for f, a, _, _ in single]
        assert len(trig) == len(set(trig)), trig
        assert not re.search(
            r"\bwk_(sincos|sin|cos)\(",
            re.sub(r"wk_sincos\(\w+, &\w+, &\w+\);|= wk_(sin|cos)\(\w+\);", "", body),
        )


@pytest.mark.slow
@pytest.mark.parametrize("name", C_MODULES)
def test_c_files_are_what_the_generator_prints(name):
    """The C files are exactly what ``scripts/generate_kernels.py`` prints now (only with the
    sympy version that generated them: the text depends on it).  Slow: the variants'
    simplification takes tens of seconds."""
    import sys

    stamp = _c_stamp(name)
    if stamp["sympy"] != sp.__version__:
        pytest.skip(f"{name}.c was generated with sympy {stamp['sympy']}, running {sp.__version__}")
    sys.path.insert(0, str(GENERATED_DIR.parents[1] / "scripts"))
    try:
        generate_kernels = importlib.import_module("generate_kernels")
    finally:
        sys.path.pop(0)
    for cname, c, h in generate_kernels.render_c(name, kernels(name)):
        assert (GENERATED_DIR / f"{cname}.c").read_text() == c, f"{cname}.c"
        assert (GENERATED_DIR / f"{cname}.h").read_text() == h, f"{cname}.h"


# ------------------------------------------------------------ course double pendulum energy
# The course's double pendulum (its double-pendulum exercise): m1 = m2 = 1,
# I1 = I2 = 0.5, l = 1, a = 0.5, g = 10, q1 = pi/2 - 0.1, q2 = pi, at rest, T = 10 s.
# The course measures both angles from the downward vertical (link i along
# (sin q_i, -cos q_i)), q2 absolute; the generated model measures q1 from +x and q2 relative
# to link 1.  Link 1 at pi/2 - 0.1 from the downward vertical points at -0.1 from +x; link 2
# at pi from the downward vertical points straight up, pi/2 from +x, so relative
# q2 = pi/2 - (-0.1).
# Frictionless joints: damping_1 = damping_2 = coulomb_1 = coulomb_2 = 0.
COURSE_P = np.array([1.0, 1.0, 0.5, 0.5, 1.0, 1.0, 0.5, 0.5, 10.0, 0.0, 0.0, 0.0, 0.0])
COURSE_Q0 = np.array([np.pi / 2 - 0.1 - np.pi / 2, np.pi - (np.pi / 2 - 0.1)])


def passive_rhs(model, p):
    """``x_dot = [qd; D(q)^-1 (-h(q, qd))]`` from a model's generated ``mass_matrix`` and
    ``bias`` kernels; returns ``f(t, x)`` for any integrator taking that signature."""
    n = model.n_x // 2

    def rhs(t, x):
        q, qd = x[:n], x[n:]
        D = model.kernel("mass_matrix", p, q)
        h = model.kernel("bias", p, q, qd)
        return np.concatenate([qd, np.linalg.solve(D, -h)])

    return rhs


def test_course_double_pendulum_conserves_energy():
    """Total energy K + P over 10 s with DOP853 at rtol = atol = 1e-12 stays within 1e-9 of
    its initial value, relative to |E0| (the course plots the per-step energy difference of
    an ode113 run at tolerance 1e-9)."""
    dp = get_model("double_pendulum")
    x0 = np.concatenate([COURSE_Q0, [0.0, 0.0]])
    sol = solve_ivp(
        passive_rhs(dp, COURSE_P),
        (0.0, 10.0),
        x0,
        method="DOP853",
        rtol=1e-12,
        atol=1e-12,
        t_eval=np.linspace(0.0, 10.0, 501),
    )
    assert sol.success, sol.message
    kinetic = np.array([dp.kernel("kinetic", COURSE_P, x[:2], x[2:]) for x in sol.y.T])
    potential = np.array([dp.kernel("potential", COURSE_P, x[:2]) for x in sol.y.T])
    energy = kinetic + potential
    # the motion is far from trivial: most of the potential energy changes hands
    assert kinetic.max() > 10.0
    drift = np.abs(energy - energy[0]).max() / abs(energy[0])
    assert drift <= 1e-9, drift
