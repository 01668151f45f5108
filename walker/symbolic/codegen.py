"""Turn symbolic matrices into compiled kernels (common subexpressions + lowering): the C99
functions in ``walker/_generated/<model>.c`` / ``.h`` (printed by
:mod:`walker.symbolic.codegen_c`).

Arguments are whole arrays (``q``, ``qd``, ``p``) unpacked at the top, so the parameters
stay arguments and changing one never regenerates anything.  Matrix outputs are written
into a caller-provided ``out`` array (no allocation on the hot path); scalars are returned.

The C form of a kernel ``k`` of model ``m`` is ``wk_<m>_<k>`` with the same arguments as
``const double *`` arrays and ``double *out`` (matrices row-major, ``(k, i, j)`` tensors
flattened the same way); scalar kernels return ``double``.  It is printed from one lowering
(:func:`lower`): the common subexpressions in a fixed order, squares as ``x*x``, never
``pow``, integer constants as doubles.  The C printer checks every expression against the
plain-Python spelling of :class:`_Printer` (the same operations in the same order), so a
printing slip of sympy's C printer cannot change the arithmetic.

A structural variant (e.g. ``compass_plain``) is printed only in C, from kernels whose zero
parameters were substituted before the common-subexpression pass; with ``share_trig`` the
sines and cosines of the angles are computed once per call and every sine or cosine of a
sum of them is expanded by the angle-sum identities (:func:`share_trig`).  Its fused
kernels solve with the mass matrix in closed form (``solve="adjugate"``,
:data:`VARIANT_SOLVE`): ``D^{-1} = adj(D) / det(D)`` from the cofactors of the numerical
entries, one division per call instead of a Cholesky factorization's chain of square roots
and divisions.

Kernels use IEEE semantics: a singular or indefinite mass matrix gives NaN (reported by
the integrator as a status), never an exception.

Each file is stamped "generated, do not edit" with the argument order, the sympy version
and a SHA-256 hash of its symbolic input; ``scripts/generate_kernels.py`` rewrites them.
Generation refuses a free symbol that is not an argument and names it (as PyDy's matrix
generator does).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

from walker.symbolic.mechanics import stray_symbols

__all__ = [
    "SOLVES",
    "VARIANT_SOLVE",
    "AccelAndJacobianKernel",
    "AccelJacobianKernel",
    "AccelKernel",
    "Kernel",
    "lower",
    "share_trig",
    "symbolic_hash",
    "variant_hash",
]

REGENERATE = "python scripts/generate_kernels.py"

SOLVES = ("cholesky", "adjugate")
"""How a fused kernel solves with its mass matrix ``D`` (n, n), on the numerical entries:
``"cholesky"``, an unrolled factorization ``D = L L^T`` and two triangular solves (any n);
``"adjugate"``, ``D^{-1} = adj(D) / det(D)`` from the cofactors, one division (n = 2, 3)."""

VARIANT_SOLVE = "adjugate"
"""The solve of a structural variant's fused kernels (part of its input hash,
:func:`variant_hash`)."""


@dataclass(frozen=True)
class Kernel:
    """One generated function.

    Parameters
    ----------
    name : str
        function name in the generated module.
    args : tuple of (str, tuple of Symbol)
        array arguments in order, each with the symbols of its entries, e.g.
        ``(("q", (q1, q2)), ("p", params))``.
    expr : sympy Matrix or expression
        the output.  A Matrix of shape (r, c) fills ``out[r, c]`` (a column vector fills a
        1-D ``out``); a list of Matrices fills ``out[k, r, c]``; a scalar is returned.
    doc : str
    """

    name: str
    args: tuple
    expr: object
    doc: str = ""


@dataclass(frozen=True)
class _FusedSolveKernel:
    """A kernel fused around the solve with the mass matrix: ``D`` (n, n) and ``h`` (n, 1) of
    ``D(q) qdd + h = 0``, solved on the numerical entries of ``D`` as ``solve`` (one of
    :data:`SOLVES`) says: one unrolled Cholesky factorization (the default), or the
    adjugate over the determinant (``D`` is never inverted symbolically);
    :class:`AccelKernel` gives ``qdd``, :class:`AccelJacobianKernel` its Jacobian."""

    name: str
    args: tuple
    D: sp.Matrix
    h: sp.Matrix
    doc: str = ""
    solve: str = "cholesky"

    def __post_init__(self):
        if self.solve not in SOLVES:
            raise ValueError(f"`solve` must be one of {SOLVES}, got {self.solve!r}")
        if self.solve == "adjugate" and self.D.rows not in (2, 3):
            raise ValueError(
                f"kernel `{self.name}`: `solve` 'adjugate' is printed for 2x2 and 3x3 mass "
                f"matrices, got {self.D.rows}x{self.D.rows}"
            )

    @property
    def expr(self):
        """``(D, h)``: what the kernel solves (for hashing and staleness checks)."""
        return [self.D, self.h]


@dataclass(frozen=True)
class AccelKernel(_FusedSolveKernel):
    """Accelerations ``qdd = -D^{-1} h`` of a Lagrangian model, fused into one function.

    The entries of the symmetric positive-definite ``D`` and of ``h`` share one
    common-subexpression pass, and the solve is an unrolled Cholesky factorization (or, with
    ``solve="adjugate"``, ``qdd = -adj(D) h / det(D)``), so the hot path allocates nothing
    and evaluates each sine and cosine once.  ``D`` is never inverted symbolically.
    Signature ``name(q, qd, p, out)``; ``out[:n]`` receives ``qdd``.

    Parameters
    ----------
    name : str
    args : tuple of (str, tuple of Symbol)
        ``(("q", q), ("qd", qd), ("p", params))``.
    D : Matrix (n, n)
    h : Matrix (n, 1)
    doc : str
    solve : str
        one of :data:`SOLVES`; default ``"cholesky"``.
    """


@dataclass(frozen=True)
class AccelJacobianKernel(_FusedSolveKernel):
    """Jacobian of ``qdd = -D^{-1} h`` with respect to ``(q, qd)``, fused like
    :class:`AccelKernel`: ``d qdd/d q_k = -D^{-1} (dh/dq_k + dD/dq_k qdd)`` and
    ``d qdd/d qd_k = -D^{-1} dh/dqd_k``, with one cse pass over ``D``, ``h`` and their
    derivatives and one unrolled Cholesky factorization (or, with ``solve="adjugate"``, one
    inverse ``adj(D) / det(D)`` applied to every column).  Signature
    ``name(q, qd, p, out)``; ``out[:n, :2n]`` receives the Jacobian.
    """


@dataclass(frozen=True)
class AccelAndJacobianKernel(AccelJacobianKernel):
    """:class:`AccelJacobianKernel` that also outputs the accelerations it solves for on the
    way: the same lowering (the same cse pass, the same solve steps), one more column.
    Signature ``name(q, qd, p, out)``; ``out`` (n, 2n + 1) row-major, ``out[:, :2n]`` the
    Jacobian (bit for bit that of the :class:`AccelJacobianKernel` of the same ``D``, ``h``
    and ``solve``) and ``out[:, 2n]`` ``qdd`` (equal to :class:`AccelKernel`'s up to
    round-off: its solve's steps differ).
    """


# ----------------------------------------------------------------------------- lowering
@dataclass(frozen=True)
class Lowered:
    """A kernel as straight-line code, independent of the target language.

    Attributes
    ----------
    name, doc, args : as in :class:`Kernel`.
    shape : tuple of int
        output shape; ``()`` for a scalar kernel (which returns its value).
    loads : list of (Symbol, str, int)
        argument entries read, ``sym = arg[index]``, in argument order.
    assigns : list of (Symbol or str, Expr)
        temporaries: shared sines and cosines (variants only), the cse replacements, then
        named entries (``d00``, ``h0``, ... of the fused kernels), in order.
    steps : list of (str, str, bool)
        ``(name, arithmetic on names, is a square root)``: the unrolled solves (Cholesky
        or adjugate, :data:`SOLVES`).
    outputs : list of (tuple of int, Expr or str)
        ``out[index] = value`` (a str value is a name from ``steps``); a scalar kernel has
        one output with index ``()``.
    """

    name: str
    doc: str
    args: tuple
    shape: tuple
    loads: list
    assigns: list
    steps: list
    outputs: list


def _check_and_cse(kernel, entries, rewrite):
    """Stray-symbol check, optional rewrite, loads and one cse pass over ``entries``."""
    entries = [sp.sympify(e) for e in entries]
    stray = stray_symbols(entries, {s for _, syms in kernel.args for s in syms})
    if stray:
        raise ValueError(
            f"kernel `{kernel.name}`: symbols {stray} are not in its arguments "
            f"{[name for name, _ in kernel.args]}"
        )
    defs = []
    if rewrite is not None:
        defs, entries = rewrite(kernel, entries)
    free = set().union(*(e.free_symbols for e in entries), *(e.free_symbols for _, e in defs))
    loads = [(s, name, i) for name, syms in kernel.args for i, s in enumerate(syms) if s in free]
    additive = [s for _, syms in kernel.args for s in syms if str(s) in ADDITIVE_PARAMS]
    if additive and any(e.has(additive[0]) for e in entries):
        (a,) = additive
        repl, reduced, _ = _split_additive(a, entries)
        return loads, list(defs) + repl, reduced
    repl, reduced = sp.cse(entries, symbols=sp.numbered_symbols("x"))
    return loads, list(defs) + list(repl), reduced


ADDITIVE_PARAMS = ("rotor_inertia",)
"""Parameters ``a`` every output entry is linear in, ``e = e|_{a=0} + a de/da``, printed as
the entry at ``a = 0`` (its own cse pass, the arithmetic of the model without ``a``) plus
``a`` times the rest (a second cse pass): at ``a = 0`` the entries are bit-identical to those
of the model without it (``x + 0*y == x``), so adding the rotor inertia to the actuated
walkers kept every existing number."""


def _split_additive(a, entries):
    """The cse of ``entries`` split at the additive parameter ``a``: (assignments, reduced
    entries, number of split entries)."""
    base = [e.xreplace({a: sp.S.Zero}) for e in entries]
    slope = [sp.diff(e, a) for e in entries]
    for k, d in enumerate(slope):
        if d.has(a):
            raise ValueError(f"entry {k} is not linear in the additive parameter `{a}`")
    repl, reduced = sp.cse(base, symbols=sp.numbered_symbols("x"))
    split = [k for k, d in enumerate(slope) if d != 0]
    repl = list(repl)
    reduced = list(reduced)
    if split:
        repl_a, reduced_a = sp.cse([slope[k] for k in split], symbols=sp.numbered_symbols("xa"))
        repl += list(repl_a)
        for k, d in zip(split, reduced_a, strict=True):
            without = sp.Symbol(f"xb{k}", real=True)
            repl.append((without, reduced[k]))
            reduced[k] = sp.Add(without, a * d, evaluate=False)
    return repl, reduced, len(split)


def _shape(expr):
    if isinstance(expr, (list, tuple)):
        return (len(expr), expr[0].rows, expr[0].cols)
    if isinstance(expr, sp.MatrixBase):
        return (expr.rows,) if expr.cols == 1 else (expr.rows, expr.cols)
    return ()


def _entries(kernel: Kernel):
    """Flatten the output into (index tuple, expression) pairs, row-major."""
    expr = kernel.expr
    if isinstance(expr, (list, tuple)):
        return [
            ((k, i, j), m[i, j])
            for k, m in enumerate(expr)
            for i in range(m.rows)
            for j in range(m.cols)
        ]
    if isinstance(expr, sp.MatrixBase):
        if expr.cols == 1:
            return [((i,), expr[i, 0]) for i in range(expr.rows)]
        return [((i, j), expr[i, j]) for i in range(expr.rows) for j in range(expr.cols)]
    return [((), sp.sympify(expr))]


def _cholesky_steps(n):
    steps = []
    for j in range(n):
        acc = " - ".join([f"d{j}{j}"] + [f"l{j}{m}*l{j}{m}" for m in range(j)])
        steps.append((f"l{j}{j}", acc, True))
        for i in range(j + 1, n):
            acc = " - ".join([f"d{i}{j}"] + [f"l{i}{m}*l{j}{m}" for m in range(j)])
            steps.append((f"l{i}{j}", f"({acc})/l{j}{j}", False))
    return steps


def _solve_steps(n, rhs, out):
    """Steps solving ``L L^T x = rhs`` (rhs names per row) into names ``out`` per row."""
    steps = []
    for i in range(n):
        acc = " - ".join([rhs[i]] + [f"l{i}{m}*{out[m]}_y" for m in range(i)])
        steps.append((f"{out[i]}_y", f"({acc})/l{i}{i}", False))
    for i in reversed(range(n)):
        acc = " - ".join([f"{out[i]}_y"] + [f"l{m}{i}*{out[m]}" for m in range(i + 1, n)])
        steps.append((out[i], f"({acc})/l{i}{i}", False))
    return steps


def _d(i, j):
    """Name of entry ``(i, j)`` of the symmetric ``D``: its lower-triangle ``d{i}{j}``."""
    return f"d{max(i, j)}{min(i, j)}"


def _adjugate_steps(n):
    """Steps of the cofactors ``c{i}{j}`` (lower triangle; ``adj(D)`` of the symmetric
    ``D``, n = 2 or 3), ``det`` (expanded along row 0) and ``inv_det = 1.0/det``.

    A 3x3 cofactor is ``d[i+1][j+1]*d[i+2][j+2] - d[i+1][j+2]*d[i+2][j+1]`` (indices mod 3,
    the sign included), so a diagonal one is the product of two diagonal entries minus a
    square: when ``D``'s diagonal is constant (the plain kneed walker) its variable part is
    one product."""
    if n == 2:
        steps = [("c00", "d11", False), ("c10", "-d10", False), ("c11", "d00", False)]
    else:
        steps = []
        for i in range(n):
            for j in range(i + 1):
                a, b, c, d = (i + 1) % 3, (j + 1) % 3, (i + 2) % 3, (j + 2) % 3
                steps.append((f"c{i}{j}", f"{_d(a, b)}*{_d(c, d)} - {_d(a, d)}*{_d(c, b)}", False))
    det = " + ".join(f"d{j}0*c{j}0" for j in range(n))
    return steps + [("det", det, False), ("inv_det", "1.0/det", False)]


def _inverse_product_steps(n, inverse, rhs, out, scale=""):
    """Steps ``out = -M rhs`` (names per row), ``M`` the symmetric matrix of names
    ``<inverse>{i}{j}`` (lower triangle), each row's sum times ``scale`` (e.g.
    ``"*inv_det"``) if given."""
    steps = []
    for i in range(n):
        terms = " + ".join(f"{inverse}{max(i, j)}{min(i, j)}*{rhs[j]}" for j in range(n))
        steps.append((out[i], f"-({terms}){scale}", False))
    return steps


def _lower_kernel(kernel: Kernel, rewrite=None) -> Lowered:
    entries = _entries(kernel)
    loads, assigns, reduced = _check_and_cse(kernel, [e for _, e in entries], rewrite)
    outputs = [(index, e) for (index, _), e in zip(entries, reduced, strict=True)]
    return Lowered(
        kernel.name, kernel.doc, kernel.args, _shape(kernel.expr), loads, assigns, [], outputs
    )


def _solve_entries(kernel: _FusedSolveKernel) -> tuple[list[str], list]:
    """The names ``d{i}{j}`` (lower triangle of ``D``, row by row) and ``h{i}`` and their
    expressions: what a fused kernel's solve reads."""
    n = kernel.D.rows
    names, entries = [], []
    for i in range(n):
        for j in range(i + 1):
            names.append(f"d{i}{j}")
            entries.append(kernel.D[i, j])
    for i in range(n):
        names.append(f"h{i}")
        entries.append(kernel.h[i])
    return names, entries


def _lower_accel(kernel: AccelKernel, rewrite=None) -> Lowered:
    n = kernel.D.rows
    names, entries = _solve_entries(kernel)
    loads, assigns, reduced = _check_and_cse(kernel, entries, rewrite)
    assigns += list(zip(names, reduced, strict=True))
    z = [f"z{i}" for i in range(n)]
    if kernel.solve == "adjugate":
        # qdd = -adj(D) h / det(D): the division overlaps the products with h.
        steps = _adjugate_steps(n)
        steps += _inverse_product_steps(n, "c", [f"h{i}" for i in range(n)], z, "*inv_det")
    else:
        # Cholesky D = L L^T, unrolled; then L L^T qdd = -h.
        steps = _cholesky_steps(n)
        steps += _solve_steps(n, [f"-h{i}" for i in range(n)], z)
    outputs = [((i,), f"z{i}") for i in range(n)]
    return Lowered(kernel.name, kernel.doc, kernel.args, (n,), loads, assigns, steps, outputs)


def _lower_accel_jacobian(kernel: AccelJacobianKernel, rewrite=None) -> Lowered:
    n = kernel.D.rows
    q = [s for name, syms in kernel.args if name == "q" for s in syms]
    qd = [s for name, syms in kernel.args if name == "qd" for s in syms]
    names, entries = _solve_entries(kernel)
    for k in range(n):
        dD = kernel.D.diff(q[k])
        for i in range(n):
            for j in range(i + 1):
                names.append(f"dD{k}_{i}{j}")
                entries.append(dD[i, j])
    for k in range(n):
        for i in range(n):
            names.append(f"hq{i}_{k}")
            entries.append(sp.diff(kernel.h[i], q[k]))
            names.append(f"hv{i}_{k}")
            entries.append(sp.diff(kernel.h[i], qd[k]))
    loads, assigns, reduced = _check_and_cse(kernel, entries, rewrite)
    assigns += list(zip(names, reduced, strict=True))

    def dd(k, i, j):
        return f"dD{k}_{i}{j}" if j <= i else f"dD{k}_{j}{i}"

    if kernel.solve == "adjugate":
        steps = _adjugate_jacobian_steps(n, dd)
    else:
        steps = _cholesky_steps(n)
        steps += _solve_steps(n, [f"-h{i}" for i in range(n)], [f"a{i}" for i in range(n)])
        for k in range(n):
            rhs = []
            for i in range(n):
                terms = " + ".join(f"{dd(k, i, j)}*a{j}" for j in range(n))
                rhs.append(f"-(hq{i}_{k} + {terms})")
            steps += _solve_steps(n, rhs, [f"jq{i}_{k}" for i in range(n)])
            steps += _solve_steps(
                n, [f"-hv{i}_{k}" for i in range(n)], [f"jv{i}_{k}" for i in range(n)]
            )
    # the fused kernel: the accelerations a{i} the solve computed, in one more column
    fused = isinstance(kernel, AccelAndJacobianKernel)
    outputs = []
    for i in range(n):
        for k in range(n):
            outputs.append(((i, k), f"jq{i}_{k}"))
            outputs.append(((i, n + k), f"jv{i}_{k}"))
        if fused:
            outputs.append(((i, 2 * n), f"a{i}"))
    shape = (n, 2 * n + 1) if fused else (n, 2 * n)
    return Lowered(kernel.name, kernel.doc, kernel.args, shape, loads, assigns, steps, outputs)


def _adjugate_jacobian_steps(n, dd):
    """The solves of :func:`_lower_accel_jacobian` with ``solve="adjugate"``: the inverse
    ``m{i}{j} = c{i}{j}*inv_det`` once, then ``a = -M h``, ``jq_k = -M (hq_k + dD_k a)``
    and ``jv_k = -M hv_k`` for every ``k`` (``dd(k, i, j)`` names entry ``(i, j)`` of
    ``dD/dq_k``)."""
    steps = _adjugate_steps(n)
    steps += [(f"m{i}{j}", f"c{i}{j}*inv_det", False) for i in range(n) for j in range(i + 1)]
    steps += _inverse_product_steps(
        n, "m", [f"h{i}" for i in range(n)], [f"a{i}" for i in range(n)]
    )
    for k in range(n):
        for i in range(n):
            terms = " + ".join(f"{dd(k, i, j)}*a{j}" for j in range(n))
            steps.append((f"r{i}_{k}", f"hq{i}_{k} + {terms}", False))
        steps += _inverse_product_steps(
            n, "m", [f"r{i}_{k}" for i in range(n)], [f"jq{i}_{k}" for i in range(n)]
        )
        steps += _inverse_product_steps(
            n, "m", [f"hv{i}_{k}" for i in range(n)], [f"jv{i}_{k}" for i in range(n)]
        )
    return steps


def lower(kernel, rewrite=None) -> Lowered:
    """Straight-line form of a kernel (one cse pass), shared by the Python and C printers.

    ``rewrite(kernel, entries) -> (definitions, entries)``, if given, transforms the output
    entries just before the cse pass (after the fused kernels' differentiation); its
    definitions ``(Symbol, Expr)`` are evaluated first (see :func:`share_trig`).
    """
    if isinstance(kernel, AccelKernel):
        return _lower_accel(kernel, rewrite)
    if isinstance(kernel, AccelJacobianKernel):
        return _lower_accel_jacobian(kernel, rewrite)
    return _lower_kernel(kernel, rewrite)


def share_trig(kernel, entries):
    """A :func:`lower` rewrite: sines and cosines once per angle, angle sums expanded.

    Every ``sin``/``cos`` whose argument is an integer combination of symbols (the
    generalized coordinates and the slope) is expanded by the angle-sum identities
    (``sympy.expand_trig``) into products of ``sin_<s>``/``cos_<s>``, one new symbol per
    angle ``s``, defined as ``sin(s)``/``cos(s)`` at the top of the kernel; other trigonometric
    terms are left as they are.  Definitions come in argument order, only those used.
    """
    atoms = sorted(
        set().union(*(e.atoms(sp.sin, sp.cos) for e in entries)), key=sp.default_sort_key
    )

    def integer_combination(arg):
        return all(
            isinstance(s, sp.Symbol) and c.is_Integer for s, c in arg.as_coefficients_dict().items()
        )

    atoms = [a for a in atoms if integer_combination(a.args[0])]
    angles = set().union(*(a.args[0].free_symbols for a in atoms))
    order = [s for _, syms in kernel.args for s in syms if s in angles]
    sin_of = {s: sp.Symbol(f"sin_{s}", real=True) for s in order}
    cos_of = {s: sp.Symbol(f"cos_{s}", real=True) for s in order}
    base = {sp.sin(s): sin_of[s] for s in order} | {sp.cos(s): cos_of[s] for s in order}
    expanded = {a: sp.expand_trig(a).xreplace(base) for a in atoms}
    entries = [e.xreplace(expanded) for e in entries]
    used = set().union(*(e.free_symbols for e in entries))
    defs = []
    for s in order:
        for sym, fun in ((sin_of[s], sp.sin), (cos_of[s], sp.cos)):
            if sym in used:
                defs.append((sym, fun(s)))
    return defs, entries


# ------------------------------------------------------------------------------ printers
class _Printer(PythonCodePrinter):
    """Plain-Python spelling of an expression (math module, plain floats): the reference the
    C printer's output is checked against, operation for operation."""

    def __init__(self):
        super().__init__({"fully_qualified_modules": True, "standard": "python3"})

    def _print_Rational(self, expr):
        return f"({float(expr.p)!r}/{float(expr.q)!r})"

    def _print_Pow(self, expr, rational=False):
        return _small_power(self, expr) or super()._print_Pow(expr, rational=rational)


def _small_power(printer, expr) -> str | None:
    """``b*b``, ``b*b*b``, ``b*b*b*b`` for the integer powers 2 to 4 of ``b`` and
    ``1.0/(b)`` for the power -1, as the Python and the C printers both spell them (the same
    operations in the same order); None for any other power."""
    base, e = expr.as_base_exp()
    if e.is_Integer and 1 < int(e) <= 4:
        b = printer._print(base)
        if not (base.is_Symbol or base.is_Function):
            b = f"({b})"
        return "*".join([b] * int(e))
    if e == -1:
        return f"1.0/({printer._print(base)})"
    return None


def symbolic_hash(kernels) -> str:
    """SHA-256 of the kernels' names, argument symbols and ``srepr`` of their outputs."""
    h = hashlib.sha256()
    for k in kernels:
        h.update(k.name.encode())
        for name, syms in k.args:
            h.update(name.encode())
            h.update(",".join(str(s) for s in syms).encode())
        h.update(sp.srepr(k.expr).encode())
        if isinstance(k, AccelKernel):
            h.update(f"accel-{k.solve}".encode())
        if isinstance(k, AccelJacobianKernel):
            h.update(f"accel-jacobian-{k.solve}".encode())
        if isinstance(k, AccelAndJacobianKernel):
            h.update(b"and-accel")
    return h.hexdigest()


def variant_hash(digest: str, variant: str, zeros, kernel_names, simplification: str = "") -> str:
    """Input hash of a structural variant: the general kernels' ``symbolic_hash``, the
    variant's name, its zero parameters, the kernels it keeps, how they are simplified, the
    trigonometric rewrite and the solve of its fused kernels (:data:`VARIANT_SOLVE`):
    everything a variant's expressions are derived from."""
    h = hashlib.sha256()
    h.update(digest.encode())
    h.update(f"variant {variant}; zeros {','.join(zeros)}; ".encode())
    h.update(f"kernels {','.join(kernel_names)}; ".encode())
    h.update(f"simplification {simplification}; share-trig angle-sum".encode())
    h.update(f"; solve {VARIANT_SOLVE}".encode())
    return h.hexdigest()


def _argument_order(kernels):
    seen = {}
    for k in kernels:
        seen[k.name] = {n: tuple(str(s) for s in syms) for n, syms in k.args}
    distinct = []
    for args in seen.values():
        for n, v in args.items():
            line = f"{n} = [{', '.join(v)}]"
            if line not in distinct:
                distinct.append(line)
    return seen, distinct
