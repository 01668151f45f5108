"""The fingerprint of the C sources compiled into ``walker._hybrid``.

``setup.py`` compiles the hash of the sources into the extension (``_hybrid.SOURCE_HASH``);
``tests/test_build.py`` recomputes it from the files, so running the tests against an
extension built from older sources (an edited .c file without ``pip install -e .``) fails
with a message that says so, instead of silently testing the old code.  Imports nothing from
walker: ``setup.py`` loads this file by path before the package is installed.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

SOURCE_DIRS = ("walker/_core", "walker/_generated")


def source_files(root: Path) -> list[Path]:
    """The C sources and headers compiled into the extension, in a fixed order."""
    root = Path(root)
    files = []
    for d in SOURCE_DIRS:
        files += [f for f in (root / d).iterdir() if f.suffix in (".c", ".h")]
    return sorted(files, key=lambda f: f.relative_to(root).as_posix())


def source_hash(root: Path) -> str:
    """sha256 over the relative paths and bytes of :func:`source_files`."""
    root = Path(root)
    h = hashlib.sha256()
    for f in source_files(root):
        h.update(f.relative_to(root).as_posix().encode())
        h.update(b"\0")
        h.update(f.read_bytes())
        h.update(b"\0")
    return h.hexdigest()
