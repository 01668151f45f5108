"""Build walker's compiled core (the extension module ``walker._hybrid``).

Every C file in ``walker/_core`` (the hybrid integrator, the model glue, the Python
binding) and ``walker/_generated`` (kernels printed by ``scripts/generate_kernels.py``)
is compiled into one extension when the package is installed (``pip install .`` or
``pip install -e .``).  Nothing is compiled at run time.  The metadata lives in
pyproject.toml.
"""

import importlib.util
import os
from glob import glob
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

SOURCES = sorted(glob("walker/_core/*.c")) + sorted(glob("walker/_generated/*.c"))


def _source_hash() -> str:
    """walker/_build.py's fingerprint of the C sources, compiled into the extension."""
    spec = importlib.util.spec_from_file_location("walker_build", Path("walker/_build.py"))
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.source_hash(Path("."))


# IEEE arithmetic exactly as written: no fused multiply-add contraction, no fast-math, so
# results do not depend on the compiler's choices (the reference digits are held to 1e-13).
UNIX_FLAGS = ["-O2", "-std=c99", "-ffp-contract=off", "-fno-fast-math", "-fno-strict-aliasing"]
MSVC_FLAGS = ["/O2", "/fp:precise"]
# Warnings (they change no code): -Wall -Wextra clean but for one warning switched off, by
# design: the registry entries (the model files) and wk_functions initializers
# list their leading fields only and leave the trailing optional ones (rhs_jac, lift,
# lift_jacobian) NULL, as wk_system.h and wk_models.h document.
UNIX_WARNINGS = ["-Wall", "-Wextra", "-Wno-missing-field-initializers"]
# WALKER_SANITIZE=1: the sanitizer test tier's build (scripts/sanitize_tests.sh) with
# AddressSanitizer and UndefinedBehaviorSanitizer, into a separate build directory.
SANITIZE_FLAGS = ["-fsanitize=address,undefined", "-fno-omit-frame-pointer", "-g"]
SANITIZE = os.environ.get("WALKER_SANITIZE", "") == "1"


def _c_string(text: str) -> str:
    """``text`` as a C string literal for a ``-D`` macro."""
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


class BuildExt(build_ext):
    def build_extensions(self):
        msvc = self.compiler.compiler_type == "msvc"
        flags = MSVC_FLAGS if msvc else UNIX_FLAGS + UNIX_WARNINGS
        if SANITIZE and not msvc:
            flags = flags + SANITIZE_FLAGS
        # The compiler command with its own and walker's flags, compiled into the extension
        # (_hybrid.COMPILE_FLAGS) so that every result file can record it.
        command = [*getattr(self.compiler, "compiler_so", [self.compiler.compiler_type]), *flags]
        for ext in self.extensions:
            ext.extra_compile_args = list(flags)
            ext.extra_link_args = list(SANITIZE_FLAGS) if SANITIZE and not msvc else []
            ext.define_macros = [
                *(m for m in ext.define_macros if m[0] != "WK_COMPILE_FLAGS"),
                ("WK_COMPILE_FLAGS", _c_string(" ".join(command))),
            ]
        super().build_extensions()


setup(
    ext_modules=[
        Extension(
            "walker._hybrid",
            sources=SOURCES,
            include_dirs=["walker/_core", "walker/_generated"],
            define_macros=[("WK_SOURCE_HASH", f'"{_source_hash()}"')],
            depends=sorted(glob("walker/_core/*.h")) + sorted(glob("walker/_generated/*.h")),
        )
    ],
    cmdclass={"build_ext": BuildExt},
)
