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


def _render_c(cname: str, kernel, low: Lowered, check: bool, hoisted=None, fast_trig=False) -> str:
    """C text of one kernel; with ``hoisted`` (a :func:`_hoist` plan), its hoisted twin
    ``wk_<cname>_<kernel>_hoisted``: the parameter-only temporaries read from the parameter
    vector's tail ``p[WK_<CNAME>_CONSTANTS_AT + k]`` instead of being computed, every other
    line as in the kernel.  ``fast_trig``: the shared sines and cosines (``sin_<s> = sin(s)``
    of :func:`walker.symbolic.codegen.share_trig`) from walker/_core/wk_sincos.h, a pair of
    one angle in one ``wk_sincos`` call."""
    printer = _CPrinter()
    pyprinter = _Printer() if check else None

    def expr(e):
        text = printer.doprint(e)
        if check and not _same_arithmetic(pyprinter.doprint(e), text):
            raise AssertionError(f"{cname}.{low.name}: C `{text}` is not the Python expression")
        return text

    prototype = _c_prototype(cname, kernel)
    doc = low.doc or low.name
    index = {}
    used = None
    if hoisted is not None:
        index = hoisted["index"]
        used = _names_used(low, set(index))
        prototype = prototype.replace(
            f"wk_{cname}_{kernel.name}(", f"wk_{cname}_{kernel.name}_hoisted("
        )
        doc = f"{doc} Hoisted: the parameter-only terms read from p's tail (wk_{cname}_constants)."
    lines = [f"/* {_comment(doc)} */", prototype, "{"]
    loads = [(s, n, i) for s, n, i in low.loads if used is None or printer.doprint(s) in used]
    read = {name for _, name, _ in loads} | ({"p"} if index else set())
    lines += [f"    (void){name};" for name, _ in low.args if name not in read]
    for s, name, i in loads:
        lines.append(f"    const double {printer.doprint(s)} = {name}[{i}];")
    at = f"WK_{cname.upper()}_CONSTANTS_AT"
    assigns = [(s if isinstance(s, str) else printer.doprint(s), e) for s, e in low.assigns]
    i = 0
    while i < len(assigns):
        name, e = assigns[i]
        i += 1
        if name in index:
            if name in used:
                lines.append(f"    const double {name} = p[{at} + {index[name]}];")
            continue
        trig = _trig_of(name, e) if fast_trig else None
        if trig is None:
            lines.append(f"    const double {name} = {expr(e)};")
            continue
        after = _trig_of(*assigns[i]) if i < len(assigns) else None
        if trig[0] == "sin" and after == ("cos", trig[1]) and assigns[i][0] not in index:
            lines.append(f"    double {name}, {assigns[i][0]};")
            lines.append(f"    wk_sincos({trig[1]}, &{name}, &{assigns[i][0]});")
            i += 1
            continue
        lines.append(f"    const double {name} = wk_{trig[0]}({trig[1]});")
    for name, rhs, is_sqrt in low.steps:
        lines.append(f"    const double {name} = {f'sqrt({rhs})' if is_sqrt else rhs};")
    if low.shape == ():
        lines.append(f"    return {expr(low.outputs[0][1])};")
    else:
        strides = [1] * len(low.shape)
        for d in reversed(range(len(low.shape) - 1)):
            strides[d] = strides[d + 1] * low.shape[d + 1]
        for index_, e in low.outputs:
            flat = sum(i * s for i, s in zip(index_, strides, strict=True))
            lines.append(f"    out[{flat}] = {e if isinstance(e, str) else expr(e)};")
    lines.append("}")
    return "\n".join(lines) + "\n"


def _trig_of(name: str, e) -> tuple[str, str] | None:
    """``("sin", "q1")`` for the shared sine ``sin_q1 = sin(q1)`` (likewise cosines), else
    None."""
    for fn, kind in ((sp.sin, "sin"), (sp.cos, "cos")):
        if isinstance(e, fn) and e.args[0].is_Symbol and name == f"{kind}_{e.args[0]}":
            return kind, str(e.args[0])
    return None


def _names_used(low: Lowered, hoisted: set) -> set:
    """Names the kernel's lines other than the hoisted temporaries read: the operands of
    its other temporaries, its solve steps and its outputs."""
    printer = _CPrinter()
    used = set()
    for sym, e in low.assigns:
        name = sym if isinstance(sym, str) else printer.doprint(sym)
        if name not in hoisted:
            used |= {str(s) for s in e.free_symbols}
    for _, rhs, _ in low.steps:
        used |= set(_TOKEN.findall(rhs))
    for _, e in low.outputs:
        used |= set(_TOKEN.findall(e)) if isinstance(e, str) else {str(s) for s in e.free_symbols}
    return used


HOISTED_KERNELS = ("accel",)
"""A kernel whose name contains one of these gets a hoisted twin (the kernels the
integrator calls at every stage: accel, accel_jac, accel_and_jac)."""


def _hoist(lowered, kernels) -> dict:
    """The plan of a module's hoisting: for each kernel named in :data:`HOISTED_KERNELS`,
    its parameter-only temporaries (a temporary is one when every operand is a parameter or
    another such temporary; the shared ``sin_slope``, ``cos_slope`` among them), each given
    the index of its value in the module's constants.  A temporary spelled like an earlier
    one (the same C text over operands of the same values) shares its index, so
    ``wk_<cname>_constants`` computes each value once.

    Returns ``{"plans": {kernel name: {"index": {name: k}, "new": [(name, text, refs)]}},
    "count": number of constants}``; ``refs`` are the operands' ``(name, source)``, source
    ``("p", i)`` or ``("c", k)``.
    """
    printer = _CPrinter()
    plans, keys, count = {}, {}, 0
    for kernel, low in zip(kernels, lowered, strict=True):
        if not any(tag in kernel.name for tag in HOISTED_KERNELS):
            continue
        params = {printer.doprint(s): i for s, name, i in low.loads if name == "p"}
        source = {name: ("p", i) for name, i in params.items()}
        index, new = {}, []
        for sym, e in low.assigns:
            name = sym if isinstance(sym, str) else printer.doprint(sym)
            operands = sorted(str(s) for s in getattr(e, "free_symbols", ()))
            if not operands or not all(o in source for o in operands):
                continue
            text = printer.doprint(e)
            refs = tuple((o, source[o]) for o in operands)
            key = (text, refs)
            if key not in keys:
                keys[key] = count
                new.append((name, text, refs, count))
                count += 1
            index[name] = keys[key]
            source[name] = ("c", keys[key])
        plans[kernel.name] = {"index": index, "new": new}
    return {"plans": plans, "count": count}


def _render_constants(cname: str, plan: dict, fast_trig: bool = False) -> str:
    """``wk_<cname>_constants(p, out)``: every hoisted constant of the module into
    out[0 .. WK_<CNAME>_N_CONSTANTS), each spelled as the kernel spells it (the same C text
    over the same values: bit for bit the kernel's temporary)."""
    lines = [
        f"/* The parameter-only terms of the hoisted kernels (wk_{cname}_*_hoisted), each",
        " * computed as the kernel computes it: once per parameter vector p, into out. */",
        f"void wk_{cname}_constants(const double *p, double *out)",
        "{",
    ]
    for kname, kplan in plan["plans"].items():
        if not kplan["new"]:
            continue
        lines.append(f"    {{ /* {kname} */")
        made = {name for name, _, _, _ in kplan["new"]}
        needed = {}
        for _, _, refs, _ in kplan["new"]:
            for o, src in refs:
                if o not in made:
                    needed[o] = src
        for o, (kind, i) in sorted(needed.items(), key=lambda item: item[1]):
            lines.append(f"        const double {o} = {'p' if kind == 'p' else 'out'}[{i}];")
        for name, text, _, k in kplan["new"]:
            if fast_trig and re.fullmatch(rf"(sin|cos)\({name[4:]}\)", text):
                text = f"wk_{text}"
            lines.append(f"        const double {name} = {text};")
            lines.append(f"        out[{k}] = {name};")
        lines.append("    }")
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
    hoist: bool = False,
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
    hoist : bool
        also print, for each kernel named in :data:`HOISTED_KERNELS`, its hoisted twin
        ``wk_<cname>_<kernel>_hoisted`` (the same arguments; ``p`` extended by the module's
        constants at ``p[WK_<CNAME>_CONSTANTS_AT + k]``, k < ``WK_<CNAME>_N_CONSTANTS``) and
        ``wk_<cname>_constants(p, out)``, which computes those constants once per parameter
        vector.  The twin computes the kernel's numbers bit for bit: each constant is the
        kernel's own temporary, spelled the same.  Every kernel of the module then takes its
        shared sines and cosines from walker/_core/wk_sincos.h (within 1 ulp for angles up
        to pi/4, libm's beyond).
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
    plan = _hoist(lowered, kernels) if hoist else None
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
    if plan is not None:
        n_p = {len(values) for k in kernels for name, values in k.args if name == "p"}
        if len(n_p) != 1:
            raise ValueError(f"{cname}: the kernels' parameter vectors differ in length {n_p}")
        header += [
            "",
            "/* Hoisted kernels: p is the parameter vector (WK_<CNAME>_CONSTANTS_AT entries)",
            f" * followed by the constants wk_{cname}_constants computes from it. */",
            f"#define WK_{cname.upper()}_CONSTANTS_AT {n_p.pop()}",
            f"#define WK_{cname.upper()}_N_CONSTANTS {plan['count']}",
            f"void wk_{cname}_constants(const double *p, double *out);",
        ]
        for k in kernels:
            if k.name in plan["plans"]:
                proto = _c_prototype(cname, k).replace(f"_{k.name}(", f"_{k.name}_hoisted(")
                header.append(proto + ";")
    header += ["", "#endif", ""]
    fast = plan is not None
    includes = (
        ["#include <math.h>", "", '#include "wk_sincos.h"'] if fast else ["#include <math.h>"]
    )
    source = [*stamp, *includes, "", f'#include "{cname}.h"', ""]
    body = "\n".join(
        _render_c(cname, k, low, check=rewrite is None, fast_trig=fast)
        for k, low in zip(kernels, lowered, strict=True)
    )
    if plan is not None:
        body += "\n" + _render_constants(cname, plan, fast_trig=True)
        for k, low in zip(kernels, lowered, strict=True):
            if k.name in plan["plans"]:
                body += "\n" + _render_c(cname, k, low, False, plan["plans"][k.name], True)
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
