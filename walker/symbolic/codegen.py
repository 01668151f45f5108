"""Turn symbolic matrices into numba-compiled kernels (common subexpressions + printing).

A generated module holds one ``@njit(cache=True)`` function per :class:`Kernel`.  Arguments
are whole arrays (``q``, ``qd``, ``p``) unpacked at the top, so the parameters stay
arguments and changing one never regenerates anything.  Matrix outputs are written into a
caller-provided ``out`` array (no allocation on the hot path); scalars are returned.

Kernels use numba's numpy error model: a singular or indefinite mass matrix gives NaN
(reported by the integrator as a status), never an exception from compiled code.

Each module is stamped "generated, do not edit" with the argument order, the sympy version
and a SHA-256 hash of its symbolic input; ``scripts/generate_kernels.py`` rewrites them.
Generation refuses a free symbol that is not an argument and names it (as PyDy's matrix
generator does).
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import sympy as sp
from sympy.printing.pycode import PythonCodePrinter

__all__ = ["AccelJacobianKernel", "AccelKernel", "Kernel", "render_module", "symbolic_hash"]


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
class AccelKernel:
    """Accelerations ``qdd = -D^{-1} h`` of a Lagrangian model, fused into one function.

    The entries of the symmetric positive-definite ``D`` and of ``h`` share one
    common-subexpression pass, and the solve is an unrolled Cholesky factorization, so the
    hot path allocates nothing and evaluates each sine and cosine once.  ``D`` is never
    inverted symbolically.  Signature ``name(q, qd, p, out)``; ``out[:n]`` receives ``qdd``.

    Parameters
    ----------
    name : str
    args : tuple of (str, tuple of Symbol)
        ``(("q", q), ("qd", qd), ("p", params))``.
    D : Matrix (n, n)
    h : Matrix (n, 1)
    doc : str
    """

    name: str
    args: tuple
    D: sp.Matrix
    h: sp.Matrix
    doc: str = ""

    @property
    def expr(self):
        """``(D, h)``: what the kernel solves (for hashing and staleness checks)."""
        return [self.D, self.h]


def render_accel_kernel(kernel: AccelKernel, printer: _Printer | None = None) -> str:
    """Source text of a fused acceleration kernel (see :class:`AccelKernel`)."""
    printer = printer or _Printer()
    n = kernel.D.rows
    entries = [kernel.D[i, j] for i in range(n) for j in range(i + 1)]
    entries += [kernel.h[i] for i in range(n)]
    allowed = {s for _, syms in kernel.args for s in syms}
    free = set().union(*(sp.sympify(e).free_symbols for e in entries))
    stray = sorted(str(s) for s in free - allowed)
    if stray:
        raise ValueError(
            f"kernel `{kernel.name}`: symbols {stray} are not in its arguments "
            f"{[name for name, _ in kernel.args]}"
        )
    lines = ['@njit(cache=True, error_model="numpy")', f"def {kernel.name}(q, qd, p, out):"]
    lines.append(f'    """{kernel.doc or kernel.name}"""')
    for name, syms in kernel.args:
        for i, s in enumerate(syms):
            if s in free:
                lines.append(f"    {s} = {name}[{i}]")
    repl, reduced = sp.cse(entries, symbols=sp.numbered_symbols("x"))
    for sym, sub in repl:
        lines.append(f"    {sym} = {printer.doprint(sub)}")
    k = 0
    for i in range(n):
        for j in range(i + 1):
            lines.append(f"    d{i}{j} = {printer.doprint(reduced[k])}")
            k += 1
    for i in range(n):
        lines.append(f"    h{i} = {printer.doprint(reduced[k])}")
        k += 1
    # Cholesky D = L L^T, unrolled; then L L^T qdd = -h.
    lines += _cholesky_lines(n)
    lines += _solve_lines(n, [f"-h{i}" for i in range(n)], [f"z{i}" for i in range(n)])
    for i in range(n):
        lines.append(f"    out[{i}] = z{i}")
    return "\n".join(lines) + "\n"


@dataclass(frozen=True)
class AccelJacobianKernel:
    """Jacobian of ``qdd = -D^{-1} h`` with respect to ``(q, qd)``, fused like
    :class:`AccelKernel`: ``d qdd/d q_k = -D^{-1} (dh/dq_k + dD/dq_k qdd)`` and
    ``d qdd/d qd_k = -D^{-1} dh/dqd_k``, with one cse pass over ``D``, ``h`` and their
    derivatives and one unrolled Cholesky factorization.  Signature
    ``name(q, qd, p, out)``; ``out[:n, :2n]`` receives the Jacobian.
    """

    name: str
    args: tuple
    D: sp.Matrix
    h: sp.Matrix
    doc: str = ""

    @property
    def expr(self):
        return [self.D, self.h]


def _cholesky_lines(n):
    lines = []
    for j in range(n):
        acc = " - ".join([f"d{j}{j}"] + [f"l{j}{m}*l{j}{m}" for m in range(j)])
        lines.append(f"    l{j}{j} = math.sqrt({acc})")
        for i in range(j + 1, n):
            acc = " - ".join([f"d{i}{j}"] + [f"l{i}{m}*l{j}{m}" for m in range(j)])
            lines.append(f"    l{i}{j} = ({acc})/l{j}{j}")
    return lines


def _solve_lines(n, rhs, out):
    """Lines solving ``L L^T x = rhs`` (rhs names per row) into names ``out`` per row."""
    lines = []
    for i in range(n):
        acc = " - ".join([rhs[i]] + [f"l{i}{m}*{out[m]}_y" for m in range(i)])
        lines.append(f"    {out[i]}_y = ({acc})/l{i}{i}")
    for i in reversed(range(n)):
        acc = " - ".join([f"{out[i]}_y"] + [f"l{m}{i}*{out[m]}" for m in range(i + 1, n)])
        lines.append(f"    {out[i]} = ({acc})/l{i}{i}")
    return lines


def render_accel_jacobian_kernel(kernel: AccelJacobianKernel, printer=None) -> str:
    """Source text of a fused acceleration-Jacobian kernel."""
    printer = printer or _Printer()
    n = kernel.D.rows
    q = [s for name, syms in kernel.args if name == "q" for s in syms]
    qd = [s for name, syms in kernel.args if name == "qd" for s in syms]
    names, entries = [], []
    for i in range(n):
        for j in range(i + 1):
            names.append(f"d{i}{j}")
            entries.append(kernel.D[i, j])
    for i in range(n):
        names.append(f"h{i}")
        entries.append(kernel.h[i])
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
    allowed = {s for _, syms in kernel.args for s in syms}
    free = set().union(*(sp.sympify(e).free_symbols for e in entries))
    stray = sorted(str(s) for s in free - allowed)
    if stray:
        raise ValueError(
            f"kernel `{kernel.name}`: symbols {stray} are not in its arguments "
            f"{[name for name, _ in kernel.args]}"
        )
    lines = ['@njit(cache=True, error_model="numpy")', f"def {kernel.name}(q, qd, p, out):"]
    lines.append(f'    """{kernel.doc or kernel.name}"""')
    for name, syms in kernel.args:
        for i, sym in enumerate(syms):
            if sym in free:
                lines.append(f"    {sym} = {name}[{i}]")
    repl, reduced = sp.cse(entries, symbols=sp.numbered_symbols("x"))
    for sym, sub in repl:
        lines.append(f"    {sym} = {printer.doprint(sub)}")
    for name, e in zip(names, reduced, strict=True):
        lines.append(f"    {name} = {printer.doprint(e)}")
    lines += _cholesky_lines(n)
    lines += _solve_lines(n, [f"-h{i}" for i in range(n)], [f"a{i}" for i in range(n)])

    def dd(k, i, j):
        return f"dD{k}_{i}{j}" if j <= i else f"dD{k}_{j}{i}"

    for k in range(n):
        rhs = []
        for i in range(n):
            terms = " + ".join(f"{dd(k, i, j)}*a{j}" for j in range(n))
            rhs.append(f"-(hq{i}_{k} + {terms})")
        lines += _solve_lines(n, rhs, [f"jq{i}_{k}" for i in range(n)])
        lines += _solve_lines(
            n, [f"-hv{i}_{k}" for i in range(n)], [f"jv{i}_{k}" for i in range(n)]
        )
    for i in range(n):
        for k in range(n):
            lines.append(f"    out[{i}, {k}] = jq{i}_{k}")
            lines.append(f"    out[{i}, {n + k}] = jv{i}_{k}")
    return "\n".join(lines) + "\n"


class _Printer(PythonCodePrinter):
    """Python printer whose output numba compiles (math module, plain floats)."""

    def __init__(self):
        super().__init__({"fully_qualified_modules": True, "standard": "python3"})

    def _print_Rational(self, expr):
        return f"({float(expr.p)!r}/{float(expr.q)!r})"

    def _print_Pow(self, expr, rational=False):
        base, e = expr.as_base_exp()
        if e.is_Integer and 1 < int(e) <= 4:
            b = self._print(base)
            if not (base.is_Symbol or base.is_Function):
                b = f"({b})"
            return "*".join([b] * int(e))
        if e == -1:
            return f"1.0/({self._print(base)})"
        return super()._print_Pow(expr, rational=rational)


def _entries(kernel: Kernel):
    """Flatten the output into (index string, expression) pairs and the output kind."""
    expr = kernel.expr
    if isinstance(expr, (list, tuple)):
        out = []
        for k, m in enumerate(expr):
            for i in range(m.rows):
                for j in range(m.cols):
                    out.append((f"[{k}, {i}, {j}]", m[i, j]))
        return out, "tensor"
    if isinstance(expr, sp.MatrixBase):
        if expr.cols == 1:
            return [(f"[{i}]", expr[i, 0]) for i in range(expr.rows)], "vector"
        return [
            (f"[{i}, {j}]", expr[i, j]) for i in range(expr.rows) for j in range(expr.cols)
        ], "matrix"
    return [("", sp.sympify(expr))], "scalar"


def render_kernel(kernel: Kernel, printer: _Printer | None = None) -> str:
    """Source text of one kernel; raises ``ValueError`` naming any stray symbol."""
    printer = printer or _Printer()
    entries, kind = _entries(kernel)
    allowed = {s for _, syms in kernel.args for s in syms}
    free = set().union(*(sp.sympify(e).free_symbols for _, e in entries))
    stray = sorted(str(s) for s in free - allowed)
    if stray:
        raise ValueError(
            f"kernel `{kernel.name}`: symbols {stray} are not in its arguments "
            f"{[name for name, _ in kernel.args]}"
        )
    arg_names = [name for name, _ in kernel.args]
    sig = ", ".join(arg_names + ([] if kind == "scalar" else ["out"]))
    lines = ['@njit(cache=True, error_model="numpy")', f"def {kernel.name}({sig}):"]
    doc = kernel.doc or kernel.name
    lines.append(f'    """{doc}"""')
    for name, syms in kernel.args:
        for i, s in enumerate(syms):
            if s in free:
                lines.append(f"    {s} = {name}[{i}]")
    repl, reduced = sp.cse([e for _, e in entries], symbols=sp.numbered_symbols("x"))
    for sym, sub in repl:
        lines.append(f"    {sym} = {printer.doprint(sub)}")
    if kind == "scalar":
        lines.append(f"    return {printer.doprint(reduced[0])}")
    else:
        for (index, _), e in zip(entries, reduced, strict=True):
            lines.append(f"    out{index} = {printer.doprint(e)}")
    return "\n".join(lines) + "\n"


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
            h.update(b"accel-cholesky")
        if isinstance(k, AccelJacobianKernel):
            h.update(b"accel-jacobian-cholesky")
    return h.hexdigest()


def render_module(name: str, kernels, *, doc: str = "", extra: str = "") -> str:
    """Source text of a whole generated module.

    Parameters
    ----------
    name : str
        model name, for the header.
    kernels : sequence of Kernel
    doc : str
        module docstring body.
    extra : str
        module-level constants to append (plain Python).
    """
    kernels = list(kernels)
    digest = symbolic_hash(kernels)
    arg_lines = []
    for k in kernels:
        arg_lines.append(f"#   {k.name}(" + ", ".join(n for n, _ in k.args) + ")")
    seen = {}
    for k in kernels:
        seen[k.name] = {n: tuple(str(s) for s in syms) for n, syms in k.args}
    distinct = []
    for args in seen.values():
        for n, v in args.items():
            line = f"#   {n} = [{', '.join(v)}]"
            if line not in distinct:
                distinct.append(line)
    order_lines = distinct
    header = [
        f"# generated, do not edit: walker kernels for `{name}`",
        f"# input hash: sha256:{digest}",
        f"# sympy {sp.__version__}; regenerate with `python scripts/generate_kernels.py`",
        "# argument order:",
        *order_lines,
        "# kernels:",
        *arg_lines,
        f'"""Generated numba kernels for the `{name}` model.\n\n{doc}\n"""',
        "",
        "import math  # noqa: F401",
        "",
        "from numba import njit",
        "",
        f'KERNEL_HASH = "{digest}"',
        f"ARGUMENT_ORDER = {seen!r}",
        "",
    ]

    def render(k):
        if isinstance(k, AccelKernel):
            return render_accel_kernel(k)
        if isinstance(k, AccelJacobianKernel):
            return render_accel_jacobian_kernel(k)
        return render_kernel(k)

    body = "\n\n".join(render(k) for k in kernels)
    return "\n".join(header) + "\n" + body + ("\n" + extra if extra else "")
