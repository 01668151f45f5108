"""Regenerate walker/_generated/ from the symbolic models (run after changing them): the C
kernels ``<module>.c``/``.h`` compiled into walker._hybrid, their structural variants
``<module>_<variant>.c``/``.h`` and the registry ``kernel_table.c`` (with each kernel's
argument lengths and output shape, which walker.models checks calls against); and the named
indices of every model, ``indices.py`` and
``indices.h`` (:mod:`walker.symbolic.indices`; ``--indices`` writes only these, in a second).

Usage: python scripts/generate_kernels.py [--indices] [MODULE ...]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

from walker.symbolic.codegen import share_trig, symbolic_hash, variant_hash
from walker.symbolic.codegen_c import render_c_module, render_kernel_table
from walker.symbolic.indices import render_indices_h, render_indices_py
from walker.symbolic.kernels import (
    C_MODULES,
    C_VARIANTS,
    GENERATED_MODULES,
    VARIANT_SIMPLIFICATION,
    kernels_for,
    variant_kernels,
)

OUT = Path(__file__).resolve().parents[1] / "walker" / "_generated"


def write(target: Path, text: str) -> Path:
    """Write ``text`` to ``target`` atomically (a temporary file, then a rename)."""
    fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=f".{target.name}.", suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write(text)
    os.chmod(tmp, 0o644)
    os.replace(tmp, target)
    return target


def variant_notes(name: str, variant: str) -> list[str]:
    zeros = C_VARIANTS[name][variant]
    return [
        f"structural variant `{variant}` of `{name}`: these parameters are exactly 0 and",
        "never read (the arguments are those of the general kernels):",
        "  " + ", ".join(zeros) + ";",
        f"entries simplified ({VARIANT_SIMPLIFICATION});",
        "sin and cos of each angle (coordinates, slope) are computed once per call",
        "(wk_sincos, walker/_core/wk_sincos.h: within 1 ulp up to pi/4, libm beyond) and",
        "sines and cosines of their sums are expanded by the angle-sum identities;",
        "accel and accel_jac solve with the mass matrix in closed form, adj(D) / det(D)",
        "from its cofactors (one division), not by Cholesky; accel_and_jac is accel_jac",
        "with the accelerations its solve computes as one more column.",
        "the accel kernels' parameter-only terms are hoisted into <module>_constants,",
        "computed once per parameter vector, which the *_hoisted twins read.",
    ]


def c_modules(name: str, kernels, simplify: bool = True) -> list[tuple[str, str, list]]:
    """``(C module name, registry prefix, kernels)`` of module ``name`` and its variants
    (``simplify=False``: the variants' kernels unsimplified, enough for names and
    signatures)."""
    out = [(name, name, kernels)]
    for variant in C_VARIANTS.get(name, {}):
        ks = variant_kernels(name, variant, kernels, simplify=simplify)
        out.append((f"{name}_{variant}", f"{name}/{variant}", ks))
    return out


def render_c(name: str, kernels) -> list[tuple[str, str, str]]:
    """``(C module name, source, header)`` of module ``name`` (from its ``kernels``) and of
    each of its structural variants."""
    digest = symbolic_hash(kernels)
    out = []
    for cname, _, ks in c_modules(name, kernels):
        if cname == name:
            c, h = render_c_module(cname, ks, doc=GENERATED_MODULES[name], digest=digest)
        else:
            variant = cname[len(name) + 1 :]
            c, h = render_c_module(
                cname,
                ks,
                doc=GENERATED_MODULES[name],
                digest=variant_hash(
                    digest,
                    variant,
                    C_VARIANTS[name][variant],
                    [k.name for k in ks],
                    VARIANT_SIMPLIFICATION,
                ),
                rewrite=share_trig,
                notes=variant_notes(name, variant),
                hoist=True,
            )
        out.append((cname, c, h))
    return out


def generate(name: str) -> list[Path]:
    """Write one generated module's C forms atomically; return the paths."""
    paths = []
    if name in C_MODULES:
        for cname, c, h in render_c(name, kernels_for(name)):
            # the header first: a source never sees an older header of its own
            paths.append(write(OUT / f"{cname}.h", h))
            paths.append(write(OUT / f"{cname}.c", c))
    return paths


def generate_table() -> Path:
    """Write ``kernel_table.c``, the registry of every C kernel of every C module."""
    modules = [m for name in C_MODULES for m in c_modules(name, kernels_for(name), False)]
    return write(OUT / "kernel_table.c", render_kernel_table(modules))


def generate_indices() -> list[Path]:
    """Write ``indices.h`` and ``indices.py``, the models' named indices."""
    return [
        write(OUT / "indices.h", render_indices_h()),
        write(OUT / "indices.py", render_indices_py()),
    ]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("modules", nargs="*", default=sorted(GENERATED_MODULES))
    parser.add_argument(
        "--indices", action="store_true", help="write only indices.py and indices.h"
    )
    args = parser.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    init = OUT / "__init__.py"
    if not init.exists():
        init.write_text('"""Generated kernels: do not edit; see scripts/generate_kernels.py."""\n')
    root = OUT.parents[1]
    print(", ".join(str(p.relative_to(root)) for p in generate_indices()))
    if args.indices:
        print("rebuild the extension: python setup.py build_ext --inplace (or pip install -e .)")
        return
    for name in args.modules:
        t = time.perf_counter()
        paths = generate(name)
        print(
            f"{', '.join(str(p.relative_to(root)) for p in paths)}: {time.perf_counter() - t:.1f} s"
        )
    print(f"{generate_table().relative_to(root)}")
    print("rebuild the extension: python setup.py build_ext --inplace (or pip install -e .)")


if __name__ == "__main__":
    main()
