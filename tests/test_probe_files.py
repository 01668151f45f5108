"""Probe reproductions of issue 33 about files walker reads (items 2, 7 and 9): decompression
bombs, forged fields that size work, version downgrades, the isolated reader's imports.

Each test names what happened before these changes.  Memory is measured with
``resource.getrusage`` in a subprocess (the reading process and its reading child); no test
asserts on wall-clock time.  The hostile-file corpus over every file kind is in
``tests/test_probe_corpus.py``.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import h5py
import numpy as np
import pytest
from _hostile_files import _tree, bomb, resign, unchecked
from test_storage import RESULTS

from walker.storage import MAX_DECOMPRESSED_BYTES, StorageError, read, write
from walker.storage import checksums as checksums_module
from walker.storage import loader as loader_module

REPO = Path(__file__).resolve().parents[1]
MiB = 1 << 20
RESIDENT_CAP = 200 * MiB  # issue 33: the bomb is refused within 200 MiB resident


def _python(
    code: str, cwd: Path | None = None, timeout: float = 120
) -> subprocess.CompletedProcess:
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in (str(REPO), env.get("PYTHONPATH")) if p)
    return subprocess.run(
        [sys.executable, "-c", textwrap.dedent(code)],
        cwd=cwd or REPO,
        env=env,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


# --------------------------------------------------------------------------------------------
# Item 2: decompression bounded


@pytest.fixture(scope="module")
def orbit_file(tmp_path_factory):
    d = tmp_path_factory.mktemp("bomb")
    return write(d / "orbit.h5", RESULTS["orbit_diagram"](), provenance={})


@pytest.mark.slow  # storage fuzzing: the integration tier
@pytest.mark.parametrize("signed", [False, True], ids=["stale-checksum", "re-signed"])
def test_decompression_bomb_is_refused_in_bounded_memory(tmp_path, orbit_file, signed):
    """Before: a 1.1 MB file whose deflated dataset declares 2 GiB was refused after 52 s
    and 2.2 GB resident with a stale checksum, and read (and plotted) in 92 s at 2.2 GB when
    re-signed.  Now the expansion (about 1000:1) is refused before anything is
    decompressed; the reading process and its child each stay under 200 MiB."""
    path = bomb(orbit_file, tmp_path / "bomb.h5", declared=2 << 30, signed=signed)
    assert path.stat().st_size < 3 * MiB
    with h5py.File(path, "r") as f:
        assert f["result/values"].nbytes >= (2 << 30) - (1 << 27)
    code = f"""
        import json, resource
        from walker.storage import StorageError, read
        out = {{}}
        for isolate in (True, False):
            try:
                read({str(path)!r}, isolate=isolate)
                out[str(isolate)] = "read"
            except StorageError as exc:
                out[str(isolate)] = str(exc)
        try:  # this process's own peak: VmHWM belongs to the address space exec made
            hwm = next(l for l in open("/proc/self/status") if l.startswith("VmHWM:"))
            out["self"] = int(hwm.split()[1]) * 1024
        except (OSError, StopIteration):  # no /proc: ru_maxrss, which exec keeps
            out["self"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
        out["children"] = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss * 1024
        print(json.dumps(out))
    """
    done = _python(code)
    assert done.returncode == 0, done.stderr
    out = json.loads(done.stdout)
    for isolate in ("True", "False"):
        assert "expansion above the cap of 64:1" in out[isolate], out[isolate]
        assert "'/result/values'" in out[isolate]
    # ru_maxrss survives fork + exec (a process started from a large pytest worker began
    # with the worker's peak), so the process's own peak is read from VmHWM.
    assert out["self"] < RESIDENT_CAP, out
    assert out["children"] < RESIDENT_CAP, out


def test_bomb_plot_is_exit_2(tmp_path, orbit_file):
    """Before: ``walker plot`` rendered the re-signed bomb after 92 s at 2.2 GB."""
    path = bomb(orbit_file, tmp_path / "bomb.h5", declared=1 << 30, signed=False)
    done = subprocess.run(
        [sys.executable, "-m", "walker", "plot", str(path), "--out", str(tmp_path / "fig")],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and "decompression bomb" in done.stderr
    assert not (tmp_path / "fig").exists()


def test_signed_bomb_is_a_valid_file_refused_only_by_the_cap(tmp_path, orbit_file, monkeypatch):
    """The forged checksum is right: with the expansion cap lifted, a small re-signed bomb
    (about 8 MiB declared) reads back as zeros of the declared shape, so the refusal above comes
    from the cap and not from a checksum."""
    path = bomb(orbit_file, tmp_path / "small.h5", declared=8 * MiB, signed=True)
    with pytest.raises(StorageError, match="expansion above the cap"):
        read(path, isolate=False)
    monkeypatch.setattr(loader_module, "MAX_COMPRESSION_RATIO", 2000)
    result, _ = read(path, isolate=False)
    with h5py.File(path, "r") as f:
        assert result.values.shape == f["result/values"].shape
    assert result.values.nbytes > 4 * MiB
    assert not result.values.any()


def test_compressed_total_is_capped(tmp_path, orbit_file, monkeypatch):
    """A file repacked with gzip (walker never compresses) still reads back equal; the total
    its compressed datasets declare is capped by ``MAX_DECOMPRESSED_BYTES``."""
    original = RESULTS["orbit_diagram"]()
    path = tmp_path / "gz.h5"
    path.write_bytes(Path(orbit_file).read_bytes())
    with h5py.File(path, "r+") as f:
        data = f["result/values"][...]
        del f["result/values"]
        f.create_dataset("result/values", data=data, compression="gzip", fletcher32=True)
    resign(path, _tree(path))
    result, _ = read(path, isolate=False)
    np.testing.assert_array_equal(result.values, original.values)
    assert MAX_DECOMPRESSED_BYTES == 32 * MiB
    monkeypatch.setattr(loader_module, "MAX_DECOMPRESSED_BYTES", data.nbytes - 1)
    with pytest.raises(StorageError, match=f"above the cap of {data.nbytes - 1} bytes"):
        read(path, isolate=False)


def test_chunk_larger_than_the_dataset_is_refused(tmp_path, orbit_file):
    """HDF5 decompresses whole chunks: a (5, 3) dataset stored in one chunk of 2**22 rows
    (a resizable dataset allows it) allocates 96 MiB to read 120 bytes; 2**26 rows would
    be 1.5 GiB.  walker's chunks never exceed the dataset."""
    import zlib

    path = tmp_path / "c.h5"
    path.write_bytes(Path(orbit_file).read_bytes())
    unchecked(path)
    rows = 1 << 22
    packer = zlib.compressobj(9)
    zipped = b"".join(packer.compress(bytes(MiB)) for _ in range(rows * 3 * 8 // MiB))
    zipped += packer.flush()
    with h5py.File(path, "r+") as f:
        shape = f["result/values"].shape
        del f["result/values"]
        ds = f.create_dataset(
            "result/values",
            shape=(shape[0], 3),
            dtype="f8",
            maxshape=(None, 3),
            chunks=(rows, 3),
            compression="gzip",
        )
        ds.id.write_direct_chunk((0, 0), zipped)
    with pytest.raises(StorageError, match=r"in chunks of \(4194304, 3\), larger than the dataset"):
        read(path, isolate=False)


def _one_chunk_stream(path, orbit_file, *, cols, mib_of_zeros):
    """``orbit_file`` with ``result/values`` of shape (1, cols) in one deflated chunk whose
    stream inflates to ``mib_of_zeros`` MiB of zeros, written raw."""
    import zlib

    path.write_bytes(Path(orbit_file).read_bytes())
    packer = zlib.compressobj(9)
    stream = b"".join(packer.compress(bytes(MiB)) for _ in range(mib_of_zeros))
    stream += packer.flush()
    with h5py.File(path, "r+") as f:
        del f["result/values"]
        ds = f.create_dataset(
            "result/values", shape=(1, cols), dtype="f8", chunks=(1, cols), compression="gzip"
        )
        ds.id.write_direct_chunk((0, 0), stream)
    return path


@pytest.mark.parametrize("cols", [40, 1 << 17], ids=["chunk-320-B", "chunk-1-MiB"])
def test_chunk_stream_larger_than_its_chunk_is_refused(tmp_path, orbit_file, cols):
    """HDF5's deflate filter grows its output buffer until the stream ends: a 1 MB stream
    in one chunk of 320 bytes was read after allocating 1 GiB (10.8 s), the dataset's
    declared size (320 bytes) bounding nothing.  Now each chunk is inflated here first, at
    most one byte beyond its size: a stream longer than a chunk can be (320 B) or one
    expanding beyond it (1 MiB chunk) is refused.  (The streams here inflate to 64 MiB:
    the mechanism is the same at any size, and making a 1 GiB one takes 10 s.)"""
    path = _one_chunk_stream(tmp_path / "c.h5", orbit_file, cols=cols, mib_of_zeros=64)
    with pytest.raises(StorageError) as info:
        read(path, isolate=False)
    text = str(info.value)
    if cols == 40:
        assert re.search(r"stores \d+ bytes for a chunk of 320, more than deflate", text), text
    else:
        assert "expands beyond the chunk's 1048576 bytes" in text, text


@pytest.mark.parametrize(
    "arr",
    [
        np.ones(()),
        np.arange(300.0),
        np.arange(280.0).reshape(5, 7, 8),
        np.arange(240, dtype=">f4").reshape(3, 40, 2),
        np.arange(150) % 3 == 0,
        (np.arange(120) + 1j).astype(np.complex64).reshape(30, 4),
        np.zeros((0, 5)),
        np.arange(240.0).reshape(40, 6)[:, ::2],
        np.broadcast_to(np.int64(7), (9, 100)),
    ],
    ids=["0d", "1d", "3d", "big-endian", "bool", "complex64", "empty", "strided", "broadcast"],
)
def test_streamed_checksum_hashes_the_bytes_of_tobytes(arr, monkeypatch):
    """The content checksum now hashes arrays in blocks, without a copy; the reference is
    SHA-256 over the length-prefixed ``arr.tobytes()`` (the format of ``docs/storage.md``),
    with blocks of 64 bytes so that every array is cut."""
    monkeypatch.setattr(checksums_module, "_HASH_BLOCK", 64)
    raw = arr.tobytes()
    want = hashlib.sha256(b"D")
    for item in (b"/p", f"{arr.dtype.str}{arr.shape}".encode(), raw):
        want.update(len(item).to_bytes(8, "little"))
        want.update(item)
    got = hashlib.sha256()
    checksums_module._feed_array(got, b"D", "/p", arr)
    assert got.hexdigest() == want.hexdigest()


# --------------------------------------------------------------------------------------------
# Item 7: decoding bounded (forged files with a valid checksum)


def _forged(tmp_path, kind, edit, name="forged.h5"):
    """A file of ``kind`` edited by ``edit(h5file)`` and re-signed: its checksum is valid,
    so only the reader's range checks can refuse it."""
    path = write(tmp_path / name, RESULTS[kind](), provenance={"rtol": 1e-10})
    with h5py.File(path, "r+") as f:
        edit(f)
    return resign(path, _tree(path))


FORGED_INTS = {
    # case: (kind, group, attribute, value, before)
    "branch-period-2e6": ("branch", "result", "period", 2_000_000, "plot allocated 3.3 GB"),
    "branch-period-1e9": ("branch", "result", "period", 10**9, "exit 3"),
    "branch-period--3": ("branch", "result", "period", -3, "exit 3"),
    "fixed-point-period-0": ("fixed_point", "result", "period", 0, "read"),
    "orbit-coordinate--100": ("orbit_diagram", "result", "coordinate", -100, "exit 3"),
    "orbit-coordinate--1": ("orbit_diagram", "result", "coordinate", -1, "mislabelled axis"),
    "orbit-coordinate-10**6": ("orbit_diagram", "result", "coordinate", 10**6, "read"),
    "solution-n-steps--1": ("solution", "result", "n_steps", -1, "read"),
}


@pytest.mark.parametrize("case", sorted(FORGED_INTS))
def test_forged_integer_is_refused(tmp_path, case):
    """Before: the values after each case's name were read as they were (see ``before``);
    now every integer field is checked against the range walker writes, before use."""
    kind, group, name, value, _ = FORGED_INTS[case]

    def edit(f):
        f[group].attrs[name] = np.int64(value)

    path = _forged(tmp_path, kind, edit)
    with pytest.raises(
        StorageError, match=rf"attribute '{name}' of '/{group}' is {value}, outside"
    ):
        read(path)


def test_forged_branch_period_plot_is_exit_2(tmp_path):
    """Before: ``walker plot`` of a 39 KB branch file with ``period = 2e6`` allocated 3.3 GB
    (hours of strides).  Now it is one line and exit 2, before any figure."""

    def edit(f):
        f["result"].attrs["period"] = np.int64(2_000_000)

    path = _forged(tmp_path, "branch", edit)
    done = subprocess.run(
        [sys.executable, "-m", "walker", "plot", str(path), "--out", str(tmp_path / "fig")],
        cwd=REPO,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 2, done.stderr
    assert done.stderr.count("\n") == 1 and "'period'" in done.stderr, done.stderr


def test_write_refuses_an_integer_read_would_refuse(tmp_path):
    import dataclasses

    bad = dataclasses.replace(RESULTS["orbit_diagram"](), coordinate=-1)
    with pytest.raises(ValueError, match=r"`OrbitDiagram.coordinate` must be in \[0, 255\]"):
        write(tmp_path / "x.h5", bad, provenance={})
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("key", ["rtol", "parameters"])
def test_provenance_integer_beyond_float_is_refused(tmp_path, key):
    """Before: a provenance ``rtol`` written as a 400-digit integer ended in exit 3
    (OverflowError converting it).  Now a real number must fit a float."""

    def edit(f):
        prov = json.loads(f.attrs["provenance"])
        big = 10**400
        if key == "rtol":
            prov["rtol"] = big
        else:
            prov["parameters"] = {"slope": {"value": big, "unit": "rad"}}
        f.attrs["provenance"] = json.dumps(prov)

    path = _forged(tmp_path, "fixed_point", edit)
    with pytest.raises(StorageError, match=f"provenance key '{key}'"):
        read(path)


def test_version_downgrade_is_refused(tmp_path):
    """Before: setting ``schema_version = 1`` switched off the SHA-256 check even with the
    ``checksum`` attribute present, so an edited provenance was read.  Now a version-1 file
    carrying version-2 features (the ``checksum`` attribute, Fletcher-32 datasets, chunk
    SHA-256) is refused."""

    def downgrade(f, drop_checksum):
        f.attrs["schema_version"] = np.int64(1)
        f.attrs["provenance"] = json.dumps({"rtol": 1.0, "model": "edited"})
        if drop_checksum:
            del f.attrs["checksum"]

    for drop in (False, True):
        path = write(tmp_path / f"d{drop}.h5", RESULTS["fixed_point"](), provenance={})
        with h5py.File(path, "r+") as f:
            downgrade(f, drop)
        feature = "the checksums of dataset" if drop else "the root attribute 'checksum'"
        with pytest.raises(StorageError, match=f"schema_version 1 but carries {feature}"):
            read(path)
    # a genuine version-1 file (contiguous, no checksums) is still read
    path = unchecked(write(tmp_path / "v1.h5", RESULTS["fixed_point"](), provenance={}))
    result, prov = read(path)
    assert prov["schema_version"] == 1
    np.testing.assert_array_equal(result.section, RESULTS["fixed_point"]().section)


# --------------------------------------------------------------------------------------------
# The isolated reader's imports


def test_spawned_reader_does_not_import_from_the_current_directory(tmp_path, orbit_file):
    """Before: with more than one thread (a notebook, Dask) the reading child started as
    ``python -c`` with the current directory first on ``sys.path``, so a planted ``json.py``
    ran in it.  Now the child runs in isolated mode (``-I``) and loads walker by path."""
    planted = tmp_path / "cwd"
    planted.mkdir()
    marker = tmp_path / "planted-code-ran"
    for name in ("json", "numpy", "h5py"):
        (planted / f"{name}.py").write_text(
            f"open({str(marker)!r}, 'a').write({name!r})\nraise SystemExit(99)\n"
        )
    # The parent imports what it needs first, then moves into the planted directory: the
    # child starts there.
    code = f"""
        import os, threading
        from walker.storage import isolated, read
        stop = threading.Event()
        threading.Thread(target=stop.wait, daemon=True).start()  # no fork: a new interpreter
        assert not isolated._can_fork()
        os.chdir({str(planted)!r})
        result, prov = read({str(orbit_file)!r})
        stop.set()
        print(prov["kind"], result.values.shape)
    """
    done = _python(code)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split()[0] == "orbit_diagram"
    assert not marker.exists(), marker.read_text()


# --------------------------------------------------------------------------------------------
# The interrupt message reads the bookkeeping only


def test_progress_without_verifying_reads_only_the_bookkeeping(tmp_path, monkeypatch):
    """Before: Ctrl-C on a 1e6-point checkpoint took 28-55 s, because the one-line message
    re-read and re-verified the whole file.  Now the message counts the done flags of
    ``/checkpoint`` alone: the same count as the full check on an intact file, and no row
    is read (the full loader is replaced by one that fails)."""
    from _checkpoints import basin_kw, half_done_sweep

    from walker.storage import BasinStore, checkpoint_progress
    from walker.storage import checkpoint as checkpoint_module

    sweep = tmp_path / "s.h5"
    half_done_sweep(sweep)
    basin = tmp_path / "b.h5"
    store = BasinStore.create_or_open(basin, **basin_kw())
    sl = store.chunk_slice(1)
    rows = np.ones((sl.stop - sl.start, 3), dtype=np.int64)
    store.write_chunk(1, rows, rows)
    full = {p: checkpoint_progress(p) for p in (sweep, basin)}
    assert full[sweep] == (2, 4) and full[basin] == (1, 3)

    def no_full_read(*args, **kw):
        raise AssertionError("the whole file was read")

    monkeypatch.setattr(checkpoint_module, "_load_checked", no_full_read)
    for p in (sweep, basin):
        assert checkpoint_progress(p, verify=False) == full[p]
    not_a_checkpoint = write(tmp_path / "o.h5", RESULTS["orbit_diagram"](), provenance={})
    monkeypatch.undo()
    assert checkpoint_progress(not_a_checkpoint, verify=False) is None
    assert checkpoint_progress(tmp_path / "missing.h5", verify=False) is None


# --------------------------------------------------------------------------------------------
# A branch file names its companion: only a file beside it


@pytest.mark.parametrize("companion", ["../outside.h5", "/etc/hostname", "sub/dir.h5", ".."])
def test_switched_branch_outside_the_directory_is_refused(tmp_path, companion, capsys):
    """A branch file's provenance names the period-doubled branch written beside it
    (``switched_branch``, a bare file name); ``walker plot`` read whatever path it named,
    inside or outside the directory.  Now a name with a directory part is refused (the file
    is forged with a valid checksum)."""
    from walker.cli import main
    from walker.scene import load_scene
    from walker.storage import scene_provenance

    scene = load_scene(REPO / "gaits" / "compass_goswami.toml")
    prov = scene_provenance(scene, switched_branch="fine.h5")
    d = tmp_path / "results"
    d.mkdir()
    path = write(d / "branch.h5", RESULTS["branch"](), provenance=prov)
    with h5py.File(path, "r+") as f:
        stored = json.loads(f.attrs["provenance"])
        stored["switched_branch"] = companion
        f.attrs["provenance"] = json.dumps(stored)
    resign(path, _tree(path))
    assert main(["plot", str(path), "--out", str(tmp_path / "figs")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "provenance key 'switched_branch' must name a file in the same directory" in err
