"""C99 printing of walker's generated kernels (the C half of :mod:`walker.symbolic.codegen`).

The C form of a kernel ``k`` of model ``m`` is ``wk_<m>_<k>`` with the same arguments as
``const double *`` arrays and ``double *out`` (matrices row-major, ``(k, i, j)`` tensors
flattened the same way); scalar kernels return ``double``.  It is printed from one lowering
(:func:`walker.symbolic.codegen.lower`), and without a rewrite every expression is checked to
spell the plain-Python expression's operations in the same order (:func:`_same_arithmetic`).
:func:`render_c_module` prints a module's ``.c`` and ``.h``, :func:`render_kernel_table` the
registry ``kernel_table.c``.
"""

from __future__ import annotations

import re

import sympy as sp
from sympy.printing.c import C99CodePrinter

from walker.symbolic.codegen import (
    REGENERATE,
    AccelAndJacobianKernel,
    AccelJacobianKernel,
    AccelKernel,
    Lowered,
    _argument_order,
    _Printer,
    _shape,
    _small_power,
    lower,
    symbolic_hash,
)

__all__ = ["SIGNATURES", "c_signature", "render_c_module", "render_kernel_table"]


class _CPrinter(C99CodePrinter):
    """C99 printer spelling the same arithmetic as :class:`_Printer` (``x*x`` for squares,
    rationals as quotients of doubles, integers as doubles); refuses anything it cannot
    print exactly so."""

    def __init__(self):
        super().__init__({"strict": True})

    def _print_Integer(self, expr):
        return f"{int(expr.p)}.0"

    _print_Zero = _print_One = _print_NegativeOne = _print_Integer

    def _print_Rational(self, expr):
        return f"({float(expr.p)!r}/{float(expr.q)!r})"

    def _print_Mul(self, expr, **kwargs):
        for f in expr.args:
            if f.is_Pow and f.exp.is_Rational and f.exp.is_negative and f.exp != -1:
                raise NotImplementedError(f"C printer: a denominator power in {expr}")
        return super()._print_Mul(expr, **kwargs)

    def _print_Pow(self, expr, rational=False):
        text = _small_power(self, expr)
        if text is not None:
            return text
        base, e = expr.as_base_exp()
        if e == sp.S.Half:
            return f"sqrt({self._print(base)})"
        raise NotImplementedError(f"C printer: power {expr}")


_TOKEN = re.compile(r"\d+\.\d+(?:e[+-]?\d+)?|\d+|[A-Za-z_]\w*|\S")


def _same_arithmetic(py: str, c: str) -> bool:
    """Whether a Python and a C expression spell the same operations on the same operands
    in the same order (numbers compared by value, ``math.`` prefixes ignored)."""
    a = _TOKEN.findall(py.replace("math.", ""))
    b = _TOKEN.findall(c)
    if len(a) != len(b):
        return False
    for x, y in zip(a, b, strict=True):
        if x == y:
            continue
        if x[0].isdigit() and y[0].isdigit() and float(x) == float(y):
            continue
        return False
    return True


SIGNATURES = {
    (("q", "qd", "p"), False): "qqdp_v",
    (("q", "p"), False): "qp_v",
    (("q", "qd", "p"), True): "qqdp_s",
    (("q", "p"), True): "qp_s",
    (("q", "qd", "qdd", "p"), False): "qqdqddp_v",
}
"""Registry signature of a kernel by (argument names, returns a scalar); see
walker/_core/wk_models.h."""


def _returns_scalar(kernel) -> bool:
    return not isinstance(kernel, (AccelKernel, AccelJacobianKernel)) and _shape(kernel.expr) == ()


def c_signature(kernel) -> str:
    """Registry signature string of a kernel (a value of :data:`SIGNATURES`)."""
    key = (tuple(n for n, _ in kernel.args), _returns_scalar(kernel))
    if key not in SIGNATURES:
        raise ValueError(f"kernel `{kernel.name}`: no registry signature for {key}")
    return SIGNATURES[key]


def _c_prototype(cname: str, kernel) -> str:
    params = [f"const double *{n}" for n, _ in kernel.args]
    if _returns_scalar(kernel):
        return f"double wk_{cname}_{kernel.name}({', '.join(params)})"
    return f"void wk_{cname}_{kernel.name}({', '.join(params + ['double *out'])})"


def _comment(text: str) -> str:
    return text.replace("*/", "* /")


def _shape_text(shape) -> str:
    if shape == ():
        return "returns a double"
    if len(shape) == 1:
        return f"out[{shape[0]}]"
    return "out[" + "][".join(map(str, shape)) + "] row-major"


def _render_c(cname: str, kernel, low: Lowered, check: bool) -> str:
    printer = _CPrinter()
    pyprinter = _Printer() if check else None

    def expr(e):
        text = printer.doprint(e)
        if check and not _same_arithmetic(pyprinter.doprint(e), text):
            raise AssertionError(f"{cname}.{low.name}: C `{text}` is not the Python expression")
        return text

    lines = [f"/* {_comment(low.doc or low.name)} */", _c_prototype(cname, kernel), "{"]
    read = {name for _, name, _ in low.loads}
    lines += [f"    (void){name};" for name, _ in low.args if name not in read]
    for s, name, i in low.loads:
        lines.append(f"    const double {printer.doprint(s)} = {name}[{i}];")
    for sym, e in low.assigns:
        name = sym if isinstance(sym, str) else printer.doprint(sym)
        lines.append(f"    const double {name} = {expr(e)};")
    for name, rhs, is_sqrt in low.steps:
        lines.append(f"    const double {name} = {f'sqrt({rhs})' if is_sqrt else rhs};")
    if low.shape == ():
        lines.append(f"    return {expr(low.outputs[0][1])};")
    else:
        strides = [1] * len(low.shape)
        for d in reversed(range(len(low.shape) - 1)):
            strides[d] = strides[d + 1] * low.shape[d + 1]
        for index, e in low.outputs:
            flat = sum(i * s for i, s in zip(index, strides, strict=True))
            lines.append(f"    out[{flat}] = {e if isinstance(e, str) else expr(e)};")
    lines.append("}")
    return "\n".join(lines) + "\n"


def render_c_module(
    cname: str,
    kernels,
    *,
    doc: str = "",
    digest: str | None = None,
    rewrite=None,
    notes=(),
) -> tuple[str, str]:
    """C source and header of a generated module: ``(<cname>.c, <cname>.h)``.

    Parameters
    ----------
    cname : str
        C module name (``compass``, ``compass_plain``); functions are ``wk_<cname>_<kernel>``.
    kernels : sequence of Kernel
    doc : str
        one-paragraph description for the header.
    digest : str, optional
        input hash to stamp; default :func:`symbolic_hash` of ``kernels``.
    rewrite : callable, optional
        passed to :func:`lower` (e.g. :func:`share_trig`).  Without it every expression is
        checked to be the plain-Python expression's, operation for operation.
    notes : sequence of str
        extra header lines (what a structural variant fixes).
    """
    kernels = list(kernels)
    digest = digest or symbolic_hash(kernels)
    _, distinct = _argument_order(kernels)
    guard = f"WK_GENERATED_{cname.upper()}_H"
    stamp = [
        f"/* generated, do not edit: walker C kernels for `{cname}`",
        f" * input hash: sha256:{digest}",
        f" * sympy {sp.__version__}; regenerate with `{REGENERATE}`",
        *(f" * {_comment(line)}" if line else " *" for line in notes),
        " * argument order:",
        *(f" *   {line}" for line in distinct),
        " * kernels:",
        *(
            f" *   wk_{cname}_{k.name}("
            + ", ".join([n for n, _ in k.args] + ([] if _returns_scalar(k) else ["out"]))
            + ")"
            for k in kernels
        ),
        " */",
    ]
    lowered = [lower(k, rewrite) for k in kernels]
    header = [
        *stamp,
        f"#ifndef {guard}",
        f"#define {guard}",
        "",
        f"/* {_comment(doc)} */" if doc else "",
        f'#define WK_{cname.upper()}_KERNEL_HASH "{digest}"',
        "",
    ]
    for k, low in zip(kernels, lowered, strict=True):
        header.append(f"/* {_comment(k.doc or k.name)} [{_shape_text(low.shape)}] */")
        header.append(_c_prototype(cname, k) + ";")
    header += ["", "#endif", ""]
    source = [*stamp, "#include <math.h>", "", f'#include "{cname}.h"', ""]
    body = "\n".join(
        _render_c(cname, k, low, check=rewrite is None)
        for k, low in zip(kernels, lowered, strict=True)
    )
    return "\n".join(source) + "\n" + body, "\n".join(header)


def kernel_sizes(kernel) -> tuple[int, int, tuple[int, ...]]:
    """``(n_q, n_p, shape)`` of a kernel: the length of its coordinate arguments (``q``, and
    ``qd`` and ``qdd`` where it takes them), of the parameters it reads (``p[:n_p]``) and the
    shape of its output (``()`` for a kernel that returns a double); the registry's entry
    carries them so that walker.models checks every call's lengths."""
    sizes = dict((name, len(values)) for name, values in kernel.args)
    n = sizes["q"]
    if isinstance(kernel, AccelAndJacobianKernel):
        shape = (n, 2 * n + 1)
    elif isinstance(kernel, AccelJacobianKernel):
        shape = (n, 2 * n)
    elif isinstance(kernel, AccelKernel):
        shape = (n,)
    else:
        shape = _shape(kernel.expr)
    return n, sizes["p"], tuple(int(d) for d in shape)


def render_kernel_table(modules) -> str:
    """``kernel_table.c``: the registry ``wk_kernel_table`` (walker/_core/wk_models.h).

    ``modules`` is a sequence of ``(cname, registry prefix, kernels)``, e.g.
    ``("kneed_plain", "kneed/plain", [...])``; entries are ``"<prefix>.<kernel>"``.
    """
    modules = list(modules)
    lines = [
        "/* generated, do not edit: registry of walker's generated C kernels",
        " * (wk_kernel_table, declared in walker/_core/wk_models.h), one entry per kernel of",
        " * walker/_generated/<module>.c;",
        f" * regenerate with `{REGENERATE}`. */",
        "#include <stddef.h>",
        "",
        '#include "wk_models.h"',
        *(f'#include "{cname}.h"' for cname, _, _ in modules),
        "",
        "static const wk_kernel_entry KERNELS[] = {",
    ]
    for cname, prefix, kernels in modules:
        for k in kernels:
            n_q, n_p, shape = kernel_sizes(k)
            dims = ", ".join(str(d) for d in (*shape, 0, 0, 0)[:3])
            lines.append(
                f'    {{"{prefix}.{k.name}", "{c_signature(k)}", (void *)wk_{cname}_{k.name}, '
                f"{n_q}, {n_p}, {{{dims}}}}},"
            )
    lines += [
        "};",
        "",
        "static const wk_kernel_hash_entry HASHES[] = {",
        *(f'    {{"{prefix}", WK_{cname.upper()}_KERNEL_HASH}},' for cname, prefix, _ in modules),
        "};",
        "",
        "const wk_kernel_entry *wk_kernel_table(int64_t *count)",
        "{",
        "    *count = (int64_t)(sizeof(KERNELS) / sizeof(KERNELS[0]));",
        "    return KERNELS;",
        "}",
        "",
        "const wk_kernel_hash_entry *wk_kernel_hash_table(int64_t *count)",
        "{",
        "    *count = (int64_t)(sizeof(HASHES) / sizeof(HASHES[0]));",
        "    return HASHES;",
        "}",
        "",
    ]
    return "\n".join(lines)
