"""Regenerate walker/_generated/*.py from the symbolic models (run after changing them).

Usage: python scripts/generate_kernels.py [MODULE ...]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

from walker.symbolic.codegen import render_module
from walker.symbolic.kernels import GENERATED_MODULES, kernels_for, module_extra

OUT = Path(__file__).resolve().parents[1] / "walker" / "_generated"


def generate(name: str) -> Path:
    """Write one generated module atomically and return its path."""
    source = render_module(
        name, kernels_for(name), doc=GENERATED_MODULES[name], extra=module_extra(name)
    )
    target = OUT / f"{name}.py"
    fd, tmp = tempfile.mkstemp(dir=OUT, prefix=f".{name}.", suffix=".tmp")
    with os.fdopen(fd, "w") as f:
        f.write(source)
    os.replace(tmp, target)
    return target


def clear_numba_cache() -> int:
    """Delete numba's cache files under walker/.

    numba keys a cached function on its own source file only, so a model function that
    calls a regenerated kernel would keep running the old kernel from its cache.
    """
    n = 0
    for path in OUT.parent.rglob("__pycache__/*.nb[ic]"):
        path.unlink()
        n += 1
    return n


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("modules", nargs="*", default=sorted(GENERATED_MODULES))
    args = parser.parse_args(argv)
    OUT.mkdir(parents=True, exist_ok=True)
    init = OUT / "__init__.py"
    if not init.exists():
        init.write_text('"""Generated kernels: do not edit; see scripts/generate_kernels.py."""\n')
    for name in args.modules:
        t = time.perf_counter()
        path = generate(name)
        print(f"{path.relative_to(OUT.parents[1])}: {time.perf_counter() - t:.1f} s")
    print(f"cleared {clear_numba_cache()} numba cache files (callers cache stale kernels)")


if __name__ == "__main__":
    main()
