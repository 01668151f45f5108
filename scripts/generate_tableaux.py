"""Print walker/_core/tableaux.h, the C copy of the Runge–Kutta coefficients in
walker/simulation/_tableaux.py that the compiled integrator (walker/_core/hybrid.c) uses.

Every float is printed with ``repr``, the shortest decimal string that reads back as the
same double, so the C constants are bit-for-bit the Python ones.  Run after changing
walker/simulation/_tableaux.py, then rebuild the extension::

    python scripts/generate_tableaux.py
    python setup.py build_ext --inplace

``--check`` exits with status 1 when the header on disk differs from what would be printed.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from walker.simulation import _tableaux as tab  # noqa: E402

HEADER = ROOT / "walker" / "_core" / "tableaux.h"

# (method, classical order, order of the embedded error estimate: 0 = none).  The error
# order sets the step-size controller's exponent -1 / (order + 1); the classical order
# Hairer's starting-step rule.  These are properties of the methods, not of the tables.
ORDERS = (("DOP853", 8, 7), ("RK45", 5, 4), ("RK4", 4, 3), ("EULER", 1, 0))

# Arrays copied, by their name in walker/simulation/_tableaux.py (the C name is WK_<name>).
ARRAYS = (
    "DOP853_C",
    "DOP853_A",
    "DOP853_B",
    "DOP853_E3",
    "DOP853_E5",
    "DOP853_D",
    "RK45_C",
    "RK45_A",
    "RK45_B",
    "RK45_E",
    "RK45_P",
    "RK4_C",
    "RK4_A",
    "RK4_B",
    "EULER_C",
    "EULER_A",
    "EULER_B",
)


def _float(v: float) -> str:
    text = repr(float(v))
    if not np.isfinite(v) or float(text) != v:  # pragma: no cover - repr round-trips
        raise ValueError(f"cannot print {v!r} exactly")
    return text


def _values(row, indent: str, per_line: int = 4) -> list[str]:
    """The numbers of ``row``, ``per_line`` to a line, each line ending in a comma."""
    text = [_float(v) for v in row]
    return [indent + ", ".join(text[i : i + per_line]) + "," for i in range(0, len(text), per_line)]


def _array(name: str, a: np.ndarray) -> list[str]:
    a = np.asarray(a, dtype=np.float64)
    cname = f"WK_{name}"
    if a.ndim == 1:
        dims = f"[{a.shape[0]}]"
        body = _values(a, "    ")
    elif a.ndim == 2:
        dims = f"[{a.shape[0]}][{a.shape[1]}]"
        body = []
        for r, row in enumerate(a):
            body.append(f"    {{ /* row {r} */")
            body += _values(row, "        ")
            body.append("    },")
    else:  # pragma: no cover - the tables are vectors and matrices
        raise ValueError(f"{name}: unexpected shape {a.shape}")
    lines = [f"#define {cname}_ROWS {a.shape[0]}"]
    if a.ndim == 2:
        lines.append(f"#define {cname}_COLS {a.shape[1]}")
    lines.append(f"static const double {cname}{dims} = {{")
    lines += body
    lines.append("};")
    return lines


def render() -> str:
    out = [
        "/* generated, do not edit: Runge-Kutta coefficients of walker/simulation/_tableaux.py",
        " * for the compiled integrator (walker/_core/hybrid.c); every number is printed with",
        " * Python's repr, which reads back as the same double.",
        " * Regenerate with `python scripts/generate_tableaux.py`. */",
        "#ifndef WK_TABLEAUX_H",
        "#define WK_TABLEAUX_H",
        "",
        "/* Stages of the step (the FSAL stage f(t + h, y_new) follows them). */",
    ]
    for method in ("DOP853", "RK45", "RK4", "EULER"):
        out.append(f"#define WK_{method}_N_STAGES {int(getattr(tab, f'{method}_N_STAGES'))}")
    out += ["", "/* Classical order and order of the embedded error estimate (0: none). */"]
    for method, order, err_order in ORDERS:
        out.append(f"#define WK_{method}_ORDER {order}")
        out.append(f"#define WK_{method}_ERR_ORDER {err_order}")
    for name in ARRAYS:
        out.append("")
        out += _array(name, getattr(tab, name))
    out += ["", "#endif", ""]
    return "\n".join(out)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare, do not write")
    args = parser.parse_args(argv)
    text = render()
    if args.check:
        current = HEADER.read_text() if HEADER.exists() else ""
        if current != text:
            print(f"{HEADER.relative_to(ROOT)} is out of date", file=sys.stderr)
            return 1
        return 0
    HEADER.write_text(text)
    print(f"wrote {HEADER.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
