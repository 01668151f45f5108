"""The generated C kernels (walker/_generated/<module>.c, compiled into walker._hybrid)
against their numba twins (walker/_generated/<model>.py), through the kernel registry.

Every kernel the registry ``walker._hybrid.kernels()`` lists (name -> (signature, address))
is called through ctypes at 50 random states and parameter vectors (the sampling ranges of
tests/test_generated.py) and compared with the numba kernel of the same name.

Tolerances:

- general kernels ("compass.accel", ...) must agree to the bit (NaN where numba gives NaN):
  both are printed from one lowering, the same cse'd expressions in the same order, the
  generator checks that the two spellings are the same operations, both call the same libm,
  and neither contracts multiply-adds (setup.py: ``-ffp-contract=off``; numba does not
  contract without fastmath).
- structural variants ("compass/plain.accel", ...) are printed from expressions simplified
  with their zero parameters substituted (walker.symbolic.kernels.variant_kernels) and with
  sines and cosines of angle sums expanded, and their accel and accel_jac solve with the
  adjugate over the determinant instead of Cholesky, so they differ from the general kernel
  by round-off only.  They are compared with the numba general kernel at parameter vectors
  whose zeroed entries are 0, to ``PLAIN_RTOL`` = 1e-13 times the largest entry of that
  sample's output.  The difference grows with the condition number of the mass matrix
  (at most ~5e-16 cond(D) seen): over these 50 samples it is at most 2e-14 (kneed's
  unlocked accel_jac; at most 8e-15 elsewhere), over 5000 samples at most 1e-13 (condition
  numbers up to 3e5 with the sampled light shanks).  Against 40-digit references the
  variants and the general kernels are equally accurate (median ~5e-16 relative).
- a variant's fused kernels ("kneed/plain.unlocked_accel_and_jac", ...; no numba twin, see
  walker.symbolic.kernels.fused_name) are its accel_jac with the accelerations as one more
  column, from the same lowering: the Jacobian columns must be the variant's own accel_jac
  to the bit, the last column the numba general accel to ``PLAIN_RTOL`` (as the variant's
  accel is: it solves with the same adjugate, in other steps).
"""

from __future__ import annotations

import ctypes
import importlib
import re
from functools import cache
from pathlib import Path

import numpy as np
import pytest
from _cmodel import assert_bits
from test_generated import PARAM_RANGES

from walker.symbolic.kernels import C_MODULES, C_VARIANTS, fused_name, is_variant_kernel

N_SAMPLES = 50
PLAIN_RTOL = 1e-13

GENERATED_DIR = Path(importlib.import_module("walker._generated").__file__).parent
_PROTOTYPE = re.compile(r"^(void|double) (wk_\w+)\(([^)]*)\);$", re.M)


def _c_modules():
    """``{C module name: (numba module name, registry prefix, zeroed parameter names)}`` of
    every generated C module (the general ones and their structural variants)."""
    out = {}
    for name in C_MODULES:
        out[name] = (name, name, ())
        for variant, zeros in C_VARIANTS.get(name, {}).items():
            out[f"{name}_{variant}"] = (name, f"{name}/{variant}", tuple(zeros))
    return out


@cache
def _header_kernels():
    """Parse every walker/_generated/*.h: ``{registry name: (sig, C module, kernel name)}``."""
    modules = _c_modules()
    out = {}
    for path in sorted(GENERATED_DIR.glob("*.h")):
        cname = path.stem
        if cname == "indices":  # the named indices (walker.symbolic.indices), no kernels
            continue
        assert cname in modules, f"{path.name} is not a known generated C module"
        prefix = modules[cname][1]
        for ret, fname, params in _PROTOTYPE.findall(path.read_text()):
            assert fname.startswith(f"wk_{cname}_"), fname
            kernel = fname[len(f"wk_{cname}_") :]
            names = [a.split("*")[-1].strip() for a in params.split(",")]
            if ret == "void":
                assert names[-1] == "out", fname
                names = names[:-1]
            sig = "".join(names) + ("_s" if ret == "double" else "_v")
            out[f"{prefix}.{kernel}"] = (sig, cname, kernel)
    return out


def _registry():
    return importlib.import_module("walker._hybrid").kernels()


_P = ctypes.POINTER(ctypes.c_double)
_CTYPES = {
    "qqdp_v": ctypes.CFUNCTYPE(None, _P, _P, _P, _P),
    "qp_v": ctypes.CFUNCTYPE(None, _P, _P, _P),
    "qqdp_s": ctypes.CFUNCTYPE(ctypes.c_double, _P, _P, _P),
    "qp_s": ctypes.CFUNCTYPE(ctypes.c_double, _P, _P),
    "qqdqddp_v": ctypes.CFUNCTYPE(None, _P, _P, _P, _P, _P),
}


def _ptr(a):
    return a.ctypes.data_as(_P)


def _sample(order, zeros, rng):
    """One random argument tuple for a kernel with argument order ``order``."""
    args = []
    for name, syms in order.items():
        if name == "p":
            a = [0.0 if s in zeros else rng.uniform(*PARAM_RANGES[s]) for s in syms]
        else:  # angles, hip positions, rates and accelerations: all O(1)
            a = rng.uniform(-np.pi, np.pi, len(syms))
        args.append(np.ascontiguousarray(a, dtype=np.float64))
    return args


def _assert_close(c, ref, what, rtol):
    c = np.asarray(c, dtype=np.float64)
    ref = np.asarray(ref, dtype=np.float64)
    assert c.shape == ref.shape, what
    assert (np.isnan(c) == np.isnan(ref)).all(), what
    ok = ~np.isnan(ref)
    scale = float(np.abs(ref[ok]).max()) if ok.any() else 0.0
    err = float(np.abs(c[ok] - ref[ok]).max()) if ok.any() else 0.0
    assert err <= rtol * scale, f"{what}: max difference {err:.3g} at scale {scale:.3g}"


@pytest.mark.parametrize("cname", sorted(_c_modules()))
def test_every_c_module_is_generated(cname):
    """Each C module has a header and a source, and holds the kernels of its numba twin: all
    of them for a general module, those :func:`is_variant_kernel` keeps for a variant, in
    the numba module's order."""
    assert (GENERATED_DIR / f"{cname}.h").exists()
    assert (GENERATED_DIR / f"{cname}.c").exists()
    model, _, zeros = _c_modules()[cname]
    module = importlib.import_module(f"walker._generated.{model}")
    expected = [k for k in module.ARGUMENT_ORDER if not zeros or is_variant_kernel(k)]
    if zeros:  # each accel_jac followed by its fused kernel
        expected = [f for k in expected for f in (k, *_fused_of(k))]
    got = [kernel for _, c, kernel in _header_kernels().values() if c == cname]
    assert got == expected
    for registry_name, (sig, c, kernel) in _header_kernels().items():
        if c == cname:
            args = "".join(module.ARGUMENT_ORDER[_twin(kernel)])
            assert sig.startswith(args + "_"), registry_name


def _fused_of(kernel):
    """``(fused_name(kernel),)`` for an accel_jac kernel, else ``()``."""
    return (fused_name(kernel),) if kernel.endswith("accel_jac") else ()


def _twin(kernel):
    """The numba kernel whose arguments C kernel ``kernel`` takes: itself, or for a fused
    kernel the accel_jac it extends."""
    if kernel.endswith("accel_and_jac"):
        return kernel[: -len("accel_and_jac")] + "accel_jac"
    return kernel


def _is_fused(registry_name):
    return registry_name.endswith("accel_and_jac")


def test_registry_lists_every_c_kernel():
    """``walker._hybrid.kernels()`` lists exactly the kernels declared in the generated
    headers, each with the signature of its prototype."""
    registry = _registry()
    expected = {name: sig for name, (sig, _, _) in _header_kernels().items()}
    assert {name: sig for name, (sig, _) in registry.items()} == expected
    assert all(isinstance(address, int) and address for _, address in registry.values())


@pytest.mark.parametrize("registry_name", sorted(n for n in _header_kernels() if not _is_fused(n)))
def test_c_kernel_agrees_with_numba(registry_name):
    """The C kernel at 50 random (state, parameter) samples against the numba kernel: to the
    bit for a general kernel, to ``PLAIN_RTOL`` for a structural variant (whose zeroed
    parameters are 0 in the samples).  The fused kernels, which have no numba twin, are
    checked by :func:`test_fused_kernel_is_accel_jac_and_accel`."""
    registry = _registry()
    assert registry_name in registry, f"{registry_name} missing from walker._hybrid.kernels()"
    sig, address = registry[registry_name]
    _, cname, kernel = _header_kernels()[registry_name]
    model, _, zeros = _c_modules()[cname]
    module = importlib.import_module(f"walker._generated.{model}")
    numba_fun = getattr(module, kernel)
    c_fun = _CTYPES[sig](address)
    order = module.ARGUMENT_ORDER[kernel]
    rng = np.random.default_rng(sum(map(ord, registry_name)))
    shape = None
    for k in range(N_SAMPLES):
        args = _sample(order, zeros, rng)
        if sig.endswith("_s"):
            ref = np.float64(numba_fun(*args))
            got = np.float64(c_fun(*map(_ptr, args)))
        else:
            if shape is None:
                shape = _shape(module, kernel, args)
            ref = np.full(shape, np.nan)
            numba_fun(*args, ref)
            got = np.full(shape, np.nan)
            c_fun(*map(_ptr, args), _ptr(got))
        what = f"{registry_name} at sample {k}"
        if zeros:
            _assert_close(got, ref, what, PLAIN_RTOL)
        else:
            assert_bits(got, ref, what)


@pytest.mark.parametrize("registry_name", sorted(n for n in _header_kernels() if _is_fused(n)))
def test_fused_kernel_is_accel_jac_and_accel(registry_name):
    """A variant's fused kernel at 50 random samples: shape (n, 2n + 1); its first 2n
    columns the variant's own accel_jac to the bit (the same lowering), its last the numba
    general accel to ``PLAIN_RTOL``."""
    registry = _registry()
    assert registry_name in registry, f"{registry_name} missing from walker._hybrid.kernels()"
    sig, address = registry[registry_name]
    assert sig == "qqdp_v", registry_name
    _, cname, kernel = _header_kernels()[registry_name]
    model, prefix, zeros = _c_modules()[cname]
    jac_name = _twin(kernel)
    accel_name = jac_name[: -len("_jac")]
    jac_sig, jac_address = registry[f"{prefix}.{jac_name}"]
    fused_fun, jac_fun = _CTYPES[sig](address), _CTYPES[jac_sig](jac_address)
    module = importlib.import_module(f"walker._generated.{model}")
    numba_accel = getattr(module, accel_name)
    order = module.ARGUMENT_ORDER[jac_name]
    n = len(order["q"])
    assert _shape_in(cname, kernel) == (n, 2 * n + 1)
    assert _shape_in(cname, jac_name) == (n, 2 * n)
    rng = np.random.default_rng(sum(map(ord, registry_name)))
    for k in range(N_SAMPLES):
        args = _sample(order, zeros, rng)
        got = np.full((n, 2 * n + 1), np.nan)
        fused_fun(*map(_ptr, args), _ptr(got))
        jac = np.full((n, 2 * n), np.nan)
        jac_fun(*map(_ptr, args), _ptr(jac))
        accel = np.full(n, np.nan)
        numba_accel(*args, accel)
        what = f"{registry_name} at sample {k}"
        assert_bits(got[:, : 2 * n], jac, f"{what}: Jacobian columns vs {jac_name}")
        _assert_close(got[:, 2 * n], accel, f"{what}: qdd column vs {accel_name}", PLAIN_RTOL)


def _shape(module, kernel, args):
    """Output shape of an array kernel, as the generated header states it in the comment
    above the prototype (``[out[r][c] row-major]``)."""
    return _shape_in(module.__name__.rsplit(".", 1)[1], kernel)


def _shape_in(cname, kernel):
    """Output shape of array kernel ``kernel`` as header ``<cname>.h`` states it."""
    text = (GENERATED_DIR / f"{cname}.h").read_text()
    m = re.search(
        r"\[out((?:\[\d+\])+)[^\]]*\] \*/\nvoid wk_" + re.escape(f"{cname}_{kernel}") + r"\(",
        text,
    )
    assert m, f"no output shape for {cname}.{kernel} in {cname}.h"
    return tuple(int(n) for n in re.findall(r"\d+", m.group(1)))


@pytest.mark.parametrize("name", sorted(C_VARIANTS))
def test_variants_are_the_models_variants(name):
    """The generator's structural variants fix exactly the parameters the model declares
    (``VARIANTS`` of walker.models.<name>, which picks the variant at run time)."""
    model = importlib.import_module(f"walker.models.{name}")
    assert {v: set(z) for v, z in C_VARIANTS[name].items()} == {
        v: set(z) for v, z in model.VARIANTS.items()
    }


@pytest.mark.parametrize("cname", sorted(c for c, (_, _, zeros) in _c_modules().items() if zeros))
def test_variant_reads_no_zero_parameter_and_shares_trigonometry(cname):
    """A structural variant never reads its zeroed parameters (they contribute no
    arithmetic), and calls ``sin``/``cos`` only once per angle, as
    ``const double sin_<angle> = sin(<angle>);``."""
    model, _, zeros = _c_modules()[cname]
    module = importlib.import_module(f"walker._generated.{model}")
    text = (GENERATED_DIR / f"{cname}.c").read_text()
    bodies = re.findall(r"^(?:void|double) wk_\w+\(.*?\)\n\{\n(.*?)^\}", text, re.M | re.S)
    assert len(bodies) == len(_PROTOTYPE.findall((GENERATED_DIR / f"{cname}.h").read_text()))
    p_names = next(iter(module.ARGUMENT_ORDER.values()))["p"]
    zero_index = {p_names.index(z) for z in zeros}
    for body in bodies:
        read = {int(i) for i in re.findall(r"= p\[(\d+)\];", body)}
        assert not read & zero_index, [p_names[i] for i in read & zero_index]
        calls = re.findall(r"\b(sin|cos)\(([^()]*)\)", body)
        assert len(calls) == len(set(calls))
        for fun, arg in calls:
            assert re.search(rf"const double {fun}_{arg} = {fun}\({arg}\);", body), (fun, arg)
