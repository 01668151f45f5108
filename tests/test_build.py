"""The compiled extension is built from the sources in this tree (no stale build)."""

from pathlib import Path

from walker import _build, _hybrid

ROOT = Path(__file__).resolve().parents[1]


def test_extension_is_built_from_these_sources():
    expected = _build.source_hash(ROOT)
    assert _hybrid.SOURCE_HASH == expected, (
        "walker._hybrid was built from other C sources than those in walker/_core and "
        "walker/_generated: rebuild it with `python -m pip install -e .`"
    )


def test_source_hash_sees_every_compiled_file(tmp_path):
    files = [f.relative_to(ROOT).as_posix() for f in _build.source_files(ROOT)]
    assert "walker/_core/hybrid.c" in files
    assert "walker/_core/wk_system.h" in files
    assert "walker/_generated/kneed_plain.c" in files
    for rel in files:
        (tmp_path / rel).parent.mkdir(parents=True, exist_ok=True)
        (tmp_path / rel).write_bytes((ROOT / rel).read_bytes())
    assert _build.source_hash(tmp_path) == _build.source_hash(ROOT)
    # one changed byte in one header changes the fingerprint
    header = tmp_path / "walker/_core/wk_system.h"
    data = bytearray(header.read_bytes())
    data[-2] ^= 1
    header.write_bytes(bytes(data))
    assert _build.source_hash(tmp_path) != _build.source_hash(ROOT)
