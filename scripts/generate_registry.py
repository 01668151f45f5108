"""Print the C files that restate walker's Python declarations (walker.symbolic.codegen_registry):
``walker/_core/status.h`` from walker/status.py, the registry of compiled models
``walker/_core/model_table.c`` and its names ``walker/_core/wk_registry.h``, and the binding's
size table ``walker/_core/_hybridsizes.h``, from the model registry, the parameter classes and
the model modules.  Run it after adding a status, a model, a variant, a phase or a guard, then
rebuild the extension; tests/test_declared_once.py fails until you do.

Usage: python scripts/generate_registry.py [--check]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from generate_kernels import write  # noqa: E402  (scripts/ is on sys.path when run)

from walker.symbolic.codegen_registry import render_all  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument(
        "--check", action="store_true", help="write nothing; exit 1 if a file is out of date"
    )
    args = parser.parse_args(argv)
    stale = []
    for path, text in render_all().items():
        target = ROOT / path
        if target.exists() and target.read_text(encoding="utf-8") == text:
            continue
        stale.append(path)
        if not args.check:
            write(target, text)
    verb = "out of date" if args.check else "written"
    print(f"{verb}: {', '.join(stale)}" if stale else "all current")
    if stale and not args.check:
        print("rebuild the extension: python setup.py build_ext --inplace (or pip install -e .)")
    return 1 if (stale and args.check) else 0


if __name__ == "__main__":
    sys.exit(main())
