"""Hostile and damaged files (issue 17, storage half): checksums on every dataset and on
each checkpoint chunk, HDF5 features walker never writes refused, declared sizes capped,
every provenance field and dataclass shape validated, reads in a child process with a time
and memory budget, readers beside a running writer, writes that survive a full or read-only
disk, stale temporary files removed; and a fuzz suite.

Each test's docstring says what happened before these changes.  Files are crafted with
h5py in ``tests/_hostile_files.py``.
"""

from __future__ import annotations

import errno
import os
import re
import shutil
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import h5py
import numpy as np
import pytest
from _hostile_files import (
    basin_v1,
    flip,
    link,
    replace_dataset,
    set_attr,
    sweep_v1,
    truncate,
    unchecked,
    write_v1,
)
from test_storage import PROVENANCE, RESULTS, assert_same

from walker import storage
from walker.storage import (
    BasinStore,
    CheckpointMismatch,
    StorageError,
    SweepStore,
    read,
    write,
)

REPO = Path(__file__).resolve().parents[1]
COMPASS = REPO / "gaits" / "compass_goswami.toml"
HANG_TIMEOUT = 20.0  # generous: a read that has not ended by then is a hang

COLUMNS = {"value": ("f8", ()), "status": ("i8", ()), "mult": ("c16", (2,)), "ok": ("?", ())}


def _points(n=10):
    return np.stack([np.linspace(0.001, 0.010, n), np.full(n, 2.0)], axis=1)


def _values(points, sl):
    p = points[sl, 0]
    return {
        "value": 1000 * p,
        "status": np.arange(sl.start, sl.stop),
        "mult": np.stack([p + 1j * p, p - 1j * p], axis=1),
        "ok": np.ones(len(p), bool),
    }


def _store(path, **changes):
    kw = dict(
        parameter_names=("slope", "mass_ratio"),
        points=_points(),
        columns=COLUMNS,
        chunk_size=3,
        provenance={"model": "compass"},
    )
    kw.update(changes)
    return SweepStore.create_or_open(path, **kw)


def _half_done(path):
    """A sweep checkpoint with chunks 0 and 2 of 4 done."""
    store = _store(path)
    for i in (0, 2):
        store.write_chunk(i, _values(store.points, store.chunk_slice(i)))
    return store


def _chunk_offset(path, dataset, index=0):
    """Byte offset and size of HDF5 chunk ``index`` of ``dataset`` (of row ``index`` when
    the dataset is contiguous, as in files written before checksums)."""
    with h5py.File(path, "r") as f:
        ds = f[dataset]
        if ds.chunks is None:
            row = ds.dtype.itemsize * int(np.prod(ds.shape[1:]))
            return ds.id.get_offset() + index * row, row
        infos = []
        ds.id.chunk_iter(infos.append)
    info = sorted(infos, key=lambda x: x.chunk_offset)[index]
    return info.byte_offset, info.size


def _poke(path, offset, new: bytes):
    data = bytearray(Path(path).read_bytes())
    data[offset : offset + len(new)] = new
    Path(path).write_bytes(bytes(data))


def _one_line(exc_info):
    text = str(exc_info.value)
    assert "\n" not in text and text.startswith("cannot ")
    return text


# --------------------------------------------------------------------------------------------
# 1. Checksums


def test_fletcher32_matches_hdf5():
    """The checkpoint writer computes HDF5's Fletcher-32 itself (it writes chunks with
    os.pwrite); it must equal what HDF5 stores, for odd and even lengths, blocks of 360
    words, and all-0xFF data (where HDF5's uint32 sums wrap)."""
    rng = np.random.default_rng(0)
    with h5py.File("fl.h5", "w", driver="core", backing_store=False) as f:
        for k, n in enumerate([1, 2, 3, 719, 720, 721, 4097, 100_001]):
            for data in (rng.integers(0, 256, n, dtype=np.uint8), np.full(n, 255, np.uint8)):
                name = f"d{k}_{int(data[0])}"
                ds = f.create_dataset(name, data=data, chunks=(n,), fletcher32=True)
                _, raw = ds.id.read_direct_chunk((0,))
                assert raw[:-4] == data.tobytes()
                assert storage._fletcher32(data.tobytes()).to_bytes(4, "little") == raw[-4:]


@pytest.mark.parametrize("name", sorted(RESULTS))
def test_every_dataset_has_a_checksum(tmp_path, name):
    """Before: datasets were contiguous with no checksum (233 of 1,206 mutated files read
    back with changed numbers).  Now every non-empty, non-scalar dataset has Fletcher-32
    and the root has the SHA-256 ``checksum`` of the content."""
    path = write(tmp_path / "f.h5", RESULTS[name](), provenance=PROVENANCE)
    with h5py.File(path) as f:
        assert f.attrs["checksum"].startswith("sha256:")
        assert int(f.attrs["schema_version"]) == storage.SCHEMA_VERSION == 2
        seen = []

        def check(name, obj):
            if isinstance(obj, h5py.Dataset) and obj.size and obj.ndim:
                assert obj.fletcher32, name
                seen.append(name)

        f.visititems(check)
    assert seen


def test_checkpoints_have_chunk_checksums(tmp_path):
    """Before: a checkpoint had only its done flags; nothing checked a done chunk's rows."""
    _half_done(tmp_path / "s.h5")
    store = BasinStore.create_or_open(tmp_path / "b.h5", **_basin_kw())
    store.write_chunk(0, np.full((2, 3), -1), np.full((2, 3), 4))
    for path, n_chunks in ((tmp_path / "s.h5", 4), (tmp_path / "b.h5", 3)):
        with h5py.File(path) as f:
            sha = f["checkpoint/chunk_sha256"]
            assert sha.shape == (n_chunks, 32) and sha.fletcher32
            assert f["checkpoint/done"].fletcher32
            for ds in [f[f"checkpoint/{n}"] for n in ("done", "chunk_sha256")]:
                assert ds.chunks[0] == 1  # one flag per HDF5 chunk: one small write
            assert sha[0].any()  # chunk 0 is done
            assert not sha[1].any()


@pytest.mark.parametrize("name", ["solution", "fixed_point", "branch", "basin", "sweep"])
def test_flipped_data_byte_is_refused(tmp_path, name):
    """Before: a flipped bit in a dataset's raw data read back as a changed number."""
    path = write(tmp_path / "f.h5", RESULTS[name](), provenance=PROVENANCE)
    with h5py.File(path) as f:
        datasets = []
        f.visititems(
            lambda n, o: datasets.append(n) if isinstance(o, h5py.Dataset) and o.nbytes else None
        )
    dataset = sorted(datasets)[0]
    offset, _ = _chunk_offset(path, dataset)
    flip(path, path, offset + 1, 3)
    with pytest.raises(StorageError, match=f"dataset '/{dataset}' fails its Fletcher-32") as info:
        read(path)
    _one_line(info)


def test_edited_attribute_is_refused(tmp_path):
    """Before: an attribute (a number of the result, or the provenance) changed on disk read
    back changed; attributes have no HDF5 checksum.  The root ``checksum`` covers them."""
    path = write(tmp_path / "fp.h5", RESULTS["fixed_point"](), provenance=PROVENANCE)
    set_attr(path, "result", "step_time", 3.9)
    with pytest.raises(StorageError, match="does not match the root 'checksum'"):
        read(path)
    path = write(tmp_path / "fp2.h5", RESULTS["fixed_point"](), provenance=PROVENANCE)
    data = path.read_bytes()
    at = data.index(b'"rtol": 1e-12')  # inside the provenance JSON (global heap, unchecked)
    _poke(path, at + len('"rtol": 1e-1'), b"3")
    with pytest.raises(StorageError, match="checksum"):
        read(path)


def test_checksum_mismatch_names_the_file(tmp_path):
    """Before: the edited ``n_strides`` (99) read back as if written."""
    path = write(tmp_path / "b.h5", RESULTS["basin"](), provenance={})
    set_attr(path, "result", "n_strides", np.int64(99))
    with pytest.raises(StorageError, match=r"cannot read '.*b\.h5': corrupted.*checksum") as info:
        read(path)
    _one_line(info)


def test_sweep_row_flip_is_recomputed_on_resume(tmp_path):
    """Before: 12 of 150 bit-flipped half-done sweeps resumed to exit 0 with wrong rows (e.g.
    ``status = 33554432``).  Now a done chunk whose rows fail their checksum is refused by
    ``read`` and pending again on resume, and recomputing it repairs the file."""
    path = tmp_path / "s.h5"
    _half_done(path)
    offset, _ = _chunk_offset(path, "result/columns/status", 2)
    _poke(path, offset + 3, b"\x02")  # row 6: status 6 -> 33554438
    with pytest.raises(StorageError, match="checkpoint chunk 2 fails its checksum"):
        read(path)
    store = _store(path)
    assert store.pending_chunks() == [1, 2, 3]
    assert storage.checkpoint_progress(path) == (1, 4)
    for i in store.pending_chunks():
        store.write_chunk(i, _values(store.points, store.chunk_slice(i)))
    table, _ = read(path)
    np.testing.assert_array_equal(table.columns["status"], np.arange(10))


@pytest.mark.parametrize("what", ["done", "chunk_sha256"])
def test_sweep_flag_flip_is_pending(tmp_path, what):
    """Before: a flipped done byte (1 -> 3) still read as done, whatever its rows held.
    Now a damaged done flag or chunk checksum makes ``read`` refuse the file and its chunk
    pending on resume (its rows are recomputed), never done with rows that were not
    checked."""
    path = tmp_path / "s.h5"
    _half_done(path)
    offset, size = _chunk_offset(path, f"checkpoint/{what}", 2)
    flip(path, path, offset, 1)
    with pytest.raises(StorageError, match="checkpoint chunk 2 fails its checksum"):
        read(path)
    store = _store(path)
    assert store.pending_chunks() == [1, 2, 3]
    store.write_chunk(2, _values(store.points, store.chunk_slice(2)))
    table, _ = read(path)
    np.testing.assert_array_equal(table.columns["status"][6:9], [6, 7, 8])


def test_sweep_static_damage_refuses_resume(tmp_path):
    """Damage outside the chunk rows (the points) refuses the file, naming the checksum.
    Before: the resume was refused as "a different sweep (1 of the points differ)", a wrong
    cause that sends the user to look for another command line."""
    path = tmp_path / "s.h5"
    _half_done(path)
    offset, _ = _chunk_offset(path, "result/points")
    flip(path, path, offset + 7, 0)
    with pytest.raises(CheckpointMismatch, match="cannot resume .*Fletcher-32"):
        _store(path)


def test_version_1_files_are_read_and_resumed(tmp_path):
    """Files of schema version 1 (no checksums) still read, and a version-1 sweep
    checkpoint is resumed in place.  (Compatibility: this passed before too; it fails if
    the new reader or the os.pwrite chunk writer mishandles the old layout.)"""
    for name in sorted(RESULTS):
        path = write_v1(tmp_path / f"{name}.h5", RESULTS[name](), PROVENANCE)
        back, prov = read(path)
        assert_same(back, RESULTS[name]())
        assert prov["schema_version"] == 1
    path = sweep_v1(
        tmp_path / "s1.h5",
        parameter_names=("slope", "mass_ratio"),
        points=_points(),
        columns=COLUMNS,
        chunk_size=3,
        provenance={"model": "compass"},
    )
    store = _store(path)
    assert store.pending_chunks() == [0, 1, 2, 3]
    store.write_chunk(1, _values(store.points, store.chunk_slice(1)))
    assert _store(path).pending_chunks() == [0, 2, 3]
    table, prov = read(path)
    assert prov["schema_version"] == 1
    np.testing.assert_array_equal(table.columns["status"][3:6], [3, 4, 5])
    assert (table.columns["status"][np.r_[0:3, 6:10]] == -1).all()
    np.testing.assert_array_equal(
        table.columns["mult"][3:6], _values(_points(), slice(3, 6))["mult"]
    )


# --------------------------------------------------------------------------------------------
# 2. HDF5 features walker never writes


@pytest.fixture
def secret(tmp_path):
    path = tmp_path / "secret.txt"
    path.write_bytes(b"password=hunter2" * 4)
    return path


def _hostile(tmp_path, kind, secret):
    path = unchecked(write(tmp_path / f"{kind}.h5", RESULTS["orbit_diagram"](), provenance={}))
    other = write(tmp_path / "other.h5", RESULTS["orbit_diagram"](), provenance={})
    if kind == "external_storage":
        replace_dataset(
            path, "result/parameter", shape=(8,), dtype="f8", external=[(str(secret), 0, 64)]
        )
    elif kind == "external_link":
        link(path, "result/values", h5py.ExternalLink(str(other), "/result/values"))
    elif kind == "soft_link":
        link(path, "result/values", h5py.SoftLink("/result/parameter"))
    elif kind == "virtual":
        layout = h5py.VirtualLayout(shape=(5, 8), dtype="f8")
        layout[:] = h5py.VirtualSource(str(other), "result/values", shape=(5, 8))
        with h5py.File(path, "r+") as f:
            del f["result/values"]
            f["result"].create_virtual_dataset("values", layout, fillvalue=0)
    elif kind == "hard_link_loop":
        with h5py.File(path, "r+") as f:
            f["result/loop"] = f["result"]
    elif kind == "foreign_filter":
        replace_dataset(path, "result/values", data=np.zeros((5, 8)), compression="lzf")
    elif kind == "named_type":
        with h5py.File(path, "r+") as f:
            f["result/kind_of_type"] = np.dtype("f8")
    return path


HOSTILE = {
    "external_storage": r"dataset '/result/parameter' keeps its data in an external file",
    "external_link": r"'/result/values' is an external link \(to '.*other.h5:/result/values'\)",
    "soft_link": r"'/result/values' is a soft link \(to '/result/parameter'\)",
    "virtual": r"dataset '/result/values' is a virtual dataset",
    "hard_link_loop": r"'/result/loop' is a second link to an object already read",
    "foreign_filter": r"dataset '/result/values' uses the HDF5 filter 32000",
    "named_type": r"'/result/kind_of_type' is a Datatype",
}


@pytest.mark.parametrize("kind", sorted(HOSTILE))
def test_hdf5_features_walker_never_writes_are_refused(tmp_path, secret, kind):
    """Before: external raw storage made walker read the bytes of another local file into a
    result, and external links were followed.  Now each is refused before any data is read,
    on read and on resume, naming the object."""
    path = _hostile(tmp_path, kind, secret)
    with pytest.raises(StorageError, match=HOSTILE[kind] + ".*which walker never writes") as e:
        read(path)
    _one_line(e)
    with pytest.raises(StorageError, match=HOSTILE[kind]):
        read(path, isolate=False)


def test_external_storage_in_a_checkpoint_is_refused_on_resume(tmp_path, secret):
    path = tmp_path / "s.h5"
    _store(path)
    unchecked(path)
    replace_dataset(
        path, "result/points", shape=(10, 2), dtype="f8", external=[(str(secret), 0, 160)]
    )
    with pytest.raises(CheckpointMismatch, match="external file"):
        _store(path)


# --------------------------------------------------------------------------------------------
# 3. Declared sizes


def test_huge_gzip_dataset_is_refused_before_reading(tmp_path):
    """Before: a gzip dataset declared 1e10 x 4 in a 20 KB file ended in MemoryError
    (298 GiB).  Now its declared size is compared with what its storage can hold."""
    path = unchecked(write(tmp_path / "o.h5", RESULTS["orbit_diagram"](), provenance={}))
    with h5py.File(path, "r+") as f:
        del f["result/values"]
        ds = f["result"].create_dataset(
            "values", shape=(10**10, 4), dtype="f8", chunks=(1024, 4), compression="gzip"
        )
        ds[:1024] = 1.0  # one stored chunk: a few hundred bytes
    assert path.stat().st_size < 30_000
    # refused from the declared size: reading it would be a MemoryError in this process
    with pytest.raises(StorageError, match=r"dataset '/result/values' declares 320000000000 "):
        read(path)
    with pytest.raises(StorageError, match="declares 320000000000 bytes"):
        read(path, isolate=False)


def test_dataset_without_storage_is_refused(tmp_path):
    path = unchecked(write(tmp_path / "o.h5", RESULTS["orbit_diagram"](), provenance={}))
    replace_dataset(path, "result/values", shape=(10**9, 8), dtype="f8")  # contiguous, empty
    with pytest.raises(StorageError, match=r"'/result/values' declares 64000000000 bytes but"):
        read(path)


def test_memory_budget(tmp_path):
    path = write(tmp_path / "s.h5", RESULTS["solution"](), provenance={})
    with pytest.raises(StorageError, match="more than the read budget of 1000 bytes"):
        read(path, memory=1000)


# --------------------------------------------------------------------------------------------
# 4. Provenance and field validation


def _provenance_text(path, text):
    set_attr(path, "/", "provenance", text)


BAD_PROVENANCE = {
    "list": ("[1,2]", "the provenance must be a JSON object, got list"),
    "complex": ('{"z": {"__complex__": [1]}}', r"`provenance\['z'\]`: '__complex__' must hold"),
    "status": ('{"s": {"__status__": "WALKING"}}', "unknown status 'WALKING'"),
    "tag": ('{"s": {"__pickle__": 1}}', "unknown tag '__pickle__'"),
    "ndarray": (
        '{"a": {"__ndarray__": {"dtype": "<f8", "shape": [3], "data": [1]}}}',
        "data does not match its shape",
    ),
    "ndarray_dtype": (
        '{"a": {"__ndarray__": {"dtype": "|O", "shape": [1], "data": [1]}}}',
        "invalid dtype",
    ),
    "parameters_list": ('{"parameters": [1, 2]}', "provenance key 'parameters' must be a dict"),
    "parameter_entry": (
        '{"parameters": {"slope": {"value": "x", "unit": "rad"}}}',
        "provenance key 'parameters' entry 'slope' must be a dict with exactly the keys",
    ),
    "model": ('{"model": 3}', "provenance key 'model' must be a str"),
    "rtol": ('{"rtol": "tight"}', "provenance key 'rtol' must be a real number"),
    "not_json": ("{'a': 1}", "attribute 'provenance' of '/' is not valid JSON"),
    "deep": ("[" * 100_000 + "]" * 100_000, "nested too deeply"),
}


@pytest.mark.parametrize("case", sorted(BAD_PROVENANCE))
def test_bad_provenance_is_a_storage_error(tmp_path, case):
    """Before: ``'[1,2]'`` raised AttributeError, ``{"__complex__":[1]}`` IndexError,
    ``parameters`` as a list an error in gallery.  Now each is a one-line StorageError
    naming the file and the key (checked even without the checksum: schema 1)."""
    text, message = BAD_PROVENANCE[case]
    path = unchecked(write(tmp_path / "fp.h5", RESULTS["fixed_point"](), provenance={}))
    _provenance_text(path, text)
    with pytest.raises(StorageError, match=r"cannot read '.*fp\.h5': corrupted") as info:
        read(path)
    assert re.search(message, _one_line(info)), str(info.value)


def test_missing_model_reads(tmp_path):
    """Provenance is the caller's: a file without ``model`` reads; a tool that needs the
    model (walker plot of a run) must say so itself.  (Passed before too: it fails if the
    provenance checks start requiring keys.)"""
    path = write(tmp_path / "fp.h5", RESULTS["fixed_point"](), provenance={"scene": "x"})
    _, prov = read(path)
    assert "model" not in prov


BAD_FIELDS = {
    "scalar_section": (
        "fixed_point",
        lambda p: replace_dataset(p, "result/section", data=np.float64(0.2)),
        r"'/result/section' must be 1-D, got shape \(\)",
    ),
    "record_x_1d": (
        "solution",
        lambda p: replace_dataset(p, "result/record/x", data=np.zeros(50)),
        r"'/result/record/x' must be 2-D with 50 rows, got shape \(50,\)",
    ),
    "record_x_columns": (
        "solution",
        lambda p: replace_dataset(p, "result/record/x", data=np.zeros((50, 3))),
        r"'/result/record/x' must have n_x = 4 columns \(as `x`\)",
    ),
    "points_1d": (
        "sweep",
        lambda p: replace_dataset(p, "result/points", data=np.zeros(3)),
        r"'/result/points' must have shape \(n, 2\)",
    ),
    "column_rows": (
        "sweep",
        lambda p: replace_dataset(p, "result/columns/status", data=np.zeros(4, dtype=int)),
        r"'/result/columns/status' must have 3 rows",
    ),
    "outcome_float": (
        "basin",
        lambda p: replace_dataset(p, "result/outcome", data=np.zeros((2, 3))),
        r"'/result/outcome' must be integers of shape \(ny, nx\) = \(2, 3\)",
    ),
    "string_dataset": (
        "basin",
        lambda p: replace_dataset(p, "result/x", data=np.array([b"a", b"b", b"c"])),
        "dataset '/result/x' has the type |S1",
    ),
    "attr_type": (
        "fixed_point",
        lambda p: set_attr(p, "result", "n_iter", "four"),
        "attribute 'n_iter' of '/result' must be an int",
    ),
    "status_name": (
        "fixed_point",
        lambda p: set_attr(p, "result", "status", "WALKING"),
        "unknown status 'WALKING'",
    ),
    "group_list_length": (
        "branch",
        lambda p: set_attr(p, "result/bifurcations", "length", np.int64(5)),
        "says length 5 but holds 2",
    ),
    "kind_type": (
        "basin",
        lambda p: set_attr(p, "/", "kind", np.int64(3)),
        "unknown result kind",
    ),
}


@pytest.mark.parametrize("case", sorted(BAD_FIELDS))
def test_bad_fields_are_a_storage_error(tmp_path, case):
    """Before: a scalar ``section`` or a 1-D ``record/x`` or ``points`` read fine and raised
    IndexError later (in gallery/plotting).  Now each field's type and shape are checked
    against its class on read."""
    kind, damage, message = BAD_FIELDS[case]
    path = unchecked(write(tmp_path / "f.h5", RESULTS[kind](), provenance={}))
    damage(path)
    with pytest.raises(StorageError, match=message) as info:
        read(path)
    _one_line(info)


def test_write_refuses_what_read_would_refuse(tmp_path):
    import dataclasses

    bad = dataclasses.replace(RESULTS["fixed_point"](), section=np.array(0.2))
    with pytest.raises(ValueError, match=r"`FixedPoint.section` must be 1-D"):
        write(tmp_path / "x.h5", bad, provenance={})
    with pytest.raises(ValueError, match=r"'value' and 'unit' \(a real number and a str\)"):
        write(tmp_path / "x.h5", bad, provenance={"parameters": {"a": {"value": "1", "unit": ""}}})
    with pytest.raises(ValueError, match="provenance key 'rtol' must be a real number"):
        write(tmp_path / "x.h5", RESULTS["basin"](), provenance={"rtol": "tight"})
    with pytest.raises(TypeError, match="`path` must be a str or os.PathLike, got int"):
        read(123)
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------------------------
# 5. Reading under a time and memory budget


@pytest.fixture(scope="module")
def issue_files(tmp_path_factory):
    """The two files of the issue, in the layout walker wrote then (schema 1): a ``find
    --out`` file and an 8x8 ``basin`` file of the compass scene."""
    from walker.cli import main

    tmp = tmp_path_factory.mktemp("issue")
    assert main(["find", str(COMPASS), "--out", str(tmp / "find.h5")]) == 0
    assert main(["basin", str(COMPASS), "--n", "8", "--out", str(tmp / "basin.h5")]) == 0
    fp, prov = read(tmp / "find.h5")
    prov = {k: v for k, v in prov.items() if k not in storage.AUTOMATIC_KEYS}
    prov["scene"] = "gaits/compass_goswami.toml"
    find_v1 = write_v1(tmp / "find_v1.h5", fp, prov)
    basin, bprov = read(tmp / "basin.h5")
    bprov = {k: v for k, v in bprov.items() if k not in storage.AUTOMATIC_KEYS}
    bprov["scene"] = "gaits/compass_goswami.toml"  # the same bytes from any checkout
    with h5py.File(tmp / "basin.h5") as f:
        k = f["checkpoint"].attrs
        tol, period, cs = float(k["tol"]), int(k["period"]), int(k["chunk_size"])
    basin_v1_path = basin_v1(
        tmp / "basin_v1.h5",
        basin,
        tol=tol,
        period=period,
        chunk_size=cs,
        provenance=bprov,
        done=range(8),
    )
    return {
        "find": find_v1,
        "basin": basin_v1_path,
        "find_v2": tmp / "find.h5",
        "basin_v2": tmp / "basin.h5",
    }


def test_segfaulting_flip_is_a_storage_error(tmp_path, issue_files):
    """Before: byte 857, bit 1 of a ``find --out`` file of the compass scene made
    ``storage.read`` (and ``walker plot``) die of SIGSEGV.  Now the read runs in a child
    process and its death is a StorageError naming the signal."""
    path = flip(issue_files["find"], tmp_path / "f.h5", 857, 1)
    with pytest.raises(StorageError, match=r"cannot read '.*f\.h5'") as info:
        read(path, timeout=HANG_TIMEOUT)
    _one_line(info)


def test_hanging_flip_is_a_storage_error(tmp_path, issue_files):
    """Before: a one-bit flip of an 8x8 basin file (byte 3545 bit 2 in the issue's file;
    byte 3457 bit 1 of this one, whose provenance is the same bytes from any checkout) made
    ``storage.read`` never return.  Now the reading child is stopped at the timeout and the
    read ends in a StorageError that says so."""
    path = flip(issue_files["basin"], tmp_path / "b.h5", 3457, 1)
    with pytest.raises(StorageError, match=r"cannot read '.*b\.h5'") as info:
        read(path, timeout=3)
    assert "did not finish within 3 s" in str(info.value)
    _one_line(info)


def test_child_crash_is_reported_by_signal(tmp_path, monkeypatch):
    path = write(tmp_path / "m.h5", RESULTS["map_result"](), provenance={})

    def crash(*args):
        os.kill(os.getpid(), signal.SIGSEGV)

    monkeypatch.setattr(storage.isolated, "_load_here", crash)  # the forked child inherits it
    # the forked child inherits the patch: fork even when an earlier test left a thread
    monkeypatch.setattr(storage.isolated, "_can_fork", lambda: True)
    with pytest.raises(StorageError, match=r"crashed reading it .*killed by SIGSEGV") as info:
        read(path)
    _one_line(info)


def test_child_hang_is_reported_after_timeout(tmp_path, monkeypatch):
    path = write(tmp_path / "m.h5", RESULTS["map_result"](), provenance={})
    monkeypatch.setattr(storage.isolated, "_load_here", lambda *args: time.sleep(600))
    # the forked child inherits the patch: fork even when an earlier test left a thread
    monkeypatch.setattr(storage.isolated, "_can_fork", lambda: True)
    with pytest.raises(StorageError, match=r"did not finish within 1 s"):
        read(path, timeout=1)  # the child sleeps 600 s: the timeout stopped it


def test_child_memory_is_limited(tmp_path, monkeypatch):
    path = write(tmp_path / "m.h5", RESULTS["map_result"](), provenance={})

    def greedy(path, file_size, budget):
        return {"x": np.ones(budget + (3 << 30), dtype=np.uint8)}

    monkeypatch.setattr(storage.isolated, "_load_here", greedy)
    # the forked child inherits the patch: fork even when an earlier test left a thread
    monkeypatch.setattr(storage.isolated, "_can_fork", lambda: True)
    with pytest.raises(StorageError, match="more than the memory budget of 100000000 bytes"):
        read(path, memory=100_000_000)


def test_isolated_read_with_threads_uses_a_new_interpreter(tmp_path):
    """With other threads running, fork is unsafe: the child is a new interpreter."""
    path = write(tmp_path / "b.h5", RESULTS["branch"](), provenance=PROVENANCE)
    stop = threading.Event()
    thread = threading.Thread(target=stop.wait)
    thread.start()
    try:
        assert not storage._can_fork()
        back, prov = read(path)
    finally:
        stop.set()
        thread.join()
    assert_same(back, RESULTS["branch"]())
    assert prov["model"] == "simplest"


def test_walker_plot_of_a_crashing_file_exits_2(tmp_path, issue_files, capsys):
    """Before: ``walker plot`` died of SIGSEGV on the flipped find file."""
    from walker.cli import main

    path = flip(issue_files["find"], tmp_path / "f.h5", 857, 1)
    assert main(["plot", str(path), "--out", str(tmp_path / "figs")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("walker: error: cannot read") and "\n" not in err


# --------------------------------------------------------------------------------------------
# 6. Readers beside the running writer

_WRITER = textwrap.dedent(
    """
    import sys, time
    import numpy as np
    from walker.storage import SweepStore
    n, chunk = 60, 3
    points = np.linspace(0.0, 1.0, n)[:, None]
    store = SweepStore.create_or_open(
        {path!r}, parameter_names=("p",), points=points,
        columns={{"a": ("f8", (50,)), "b": ("i8", ())}}, chunk_size=chunk,
        provenance={{"model": "test"}})
    print("created", flush=True)
    for i in store.pending_chunks():
        sl = store.chunk_slice(i)
        store.write_chunk(i, {{"a": np.repeat(points[sl], 50, axis=1) + 1.0,
                               "b": np.arange(sl.start, sl.stop)}})
        if i < 3:  # the first chunks wait for a reader's turn: reads mid-run on any machine
            print("wrote", flush=True)
            sys.stdin.readline()
        time.sleep(0.02)
    print("finished", flush=True)
    """
)


@pytest.mark.parametrize("isolate", [True, False])
def test_readers_and_a_running_writer_coexist(tmp_path, isolate):
    """Before: ``walker plot`` of a sweep's file while the sweep ran killed the sweep
    (``cannot write chunk ... unable to lock file``) and the plot said "truncated/
    corrupted".  Now chunks are written with os.pwrite (no HDF5, no lock), and a reader
    sees a consistent snapshot: the chunks marked done, complete, the others pending."""
    path = tmp_path / "s.h5"
    proc = subprocess.Popen(
        [sys.executable, "-c", _WRITER.format(path=str(path))],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )

    def check_snapshot() -> None:
        table, _ = read(path) if isolate else read(path, isolate=False)
        b = table.columns["b"]
        done = b >= 0
        np.testing.assert_array_equal(b[done], np.arange(60)[done])
        expected = np.repeat(table.points, 50, axis=1) + 1.0
        np.testing.assert_array_equal(table.columns["a"][done], expected[done])
        assert np.isnan(table.columns["a"][~done]).all()

    try:
        assert proc.stdout.readline().strip() == "created"
        # A reader holding the file open with HDF5's own lock does not stop the writer.
        with h5py.File(path, "r") as held:
            n_reads = 0
            for _ in range(3):  # the writer waits after each of its first three chunks
                assert proc.stdout.readline().strip() == "wrote"
                check_snapshot()
                n_reads += 1
                proc.stdin.write("go\n")
                proc.stdin.flush()
            while proc.poll() is None:  # then reads run beside writes
                check_snapshot()
                n_reads += 1
            assert held["checkpoint/done"].shape == (20,)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, err
    assert out.strip() == "finished"
    assert n_reads >= 3
    assert storage.checkpoint_progress(path) == (20, 20)


def test_failed_chunk_write_is_retried(tmp_path, monkeypatch):
    """Before: one failed chunk write ended the sweep.  Now a transient error (EIO, EAGAIN,
    ...) is retried with backoff; a persistent one is a StorageError, the chunk stays
    pending and the chunks done before stay intact."""
    store = _half_done(tmp_path / "s.h5")
    real = storage.checkpoint._write_all
    failures = [errno.EIO, errno.EAGAIN]
    sleeps = []

    def flaky(fd, data, offset=None):
        if failures:
            raise OSError(failures.pop(0), "simulated")
        return real(fd, data, offset)

    monkeypatch.setattr(storage.checkpoint, "_write_all", flaky)
    monkeypatch.setattr(storage.checkpoint.time, "sleep", sleeps.append)
    store.write_chunk(1, _values(store.points, store.chunk_slice(1)))
    assert sleeps == [0.05, 0.2]
    assert store.pending_chunks() == [3]

    def broken(fd, data, offset=None):
        raise OSError(errno.EIO, "simulated")

    monkeypatch.setattr(storage.checkpoint, "_write_all", broken)
    with pytest.raises(StorageError, match=r"cannot write chunk 3 to '.*s\.h5'.*\(EIO\)") as info:
        store.write_chunk(3, _values(store.points, store.chunk_slice(3)))
    _one_line(info)
    monkeypatch.setattr(storage.checkpoint, "_write_all", real)
    assert store.pending_chunks() == [3]
    table, _ = read(tmp_path / "s.h5")
    np.testing.assert_array_equal(table.columns["status"][:9], np.arange(9))


def test_replaced_file_is_not_written(tmp_path):
    store = _half_done(tmp_path / "s.h5")
    write(tmp_path / "s.h5", RESULTS["basin"](), provenance={}, overwrite=True)
    with pytest.raises(StorageError, match="the file was replaced"):
        store.write_chunk(1, _values(store.points, store.chunk_slice(1)))


# --------------------------------------------------------------------------------------------
# 7. Writing survives the disk

_FULL_DISK = textwrap.dedent(
    """
    import resource, signal, sys
    signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
    resource.setrlimit(resource.RLIMIT_FSIZE, ({limit}, {limit}))
    from walker.cli import main
    sys.exit(main(sys.argv[1:]))
    """
)


@pytest.mark.parametrize("limit", [2000, 40_000])
def test_sweep_on_a_full_disk_exits_2(tmp_path, limit):
    """Before: ``walker sweep ... --out SMALL/sw.h5`` on a full 1 MiB tmpfs died of
    SIGSEGV (exit 139) in h5py's flush under ``_atomic_create`` and left ``.sw.h5.tmp-*``.
    A full disk is simulated with RLIMIT_FSIZE (SIGXFSZ ignored: writes beyond the limit
    fail with EFBIG, as they fail with ENOSPC on a full disk); the same segfault was seen
    so before this change.  Now: exit 2, one line, no file, no temporary file."""
    out = tmp_path / "sw.h5"
    proc = subprocess.run(
        [
            sys.executable,
            "-c",
            _FULL_DISK.format(limit=limit),
            "sweep",
            str(COMPASS),
            "--param",
            "slope=0.04:0.06:500",
            "--jobs",
            "1",
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 2, proc.stderr
    lines = proc.stderr.strip().splitlines()
    assert lines == [
        f"walker: error: cannot write '{out}': file too large for the file "
        "system or the process limit (EFBIG)"
    ]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("code", [errno.ENOSPC, errno.EDQUOT, errno.EROFS])
def test_disk_errors_while_writing_are_storage_errors(tmp_path, monkeypatch, code):
    """ENOSPC, EDQUOT and EROFS while a file is written: a one-line StorageError, no file,
    no temporary file; an existing target is kept."""
    old = write(tmp_path / "b.h5", RESULTS["basin"](), provenance={"model": "old"})

    def failing(fd, data, offset=None):
        raise OSError(code, os.strerror(code))

    monkeypatch.setattr(storage.disk, "_write_all", failing)
    name = errno.errorcode[code]
    for target in (tmp_path / "new.h5", old):
        with pytest.raises(StorageError, match=rf"cannot write '.*'.*\({name}\)$") as info:
            write(target, RESULTS["basin"](), provenance={"model": "new"}, overwrite=True)
        _one_line(info)
    with pytest.raises(StorageError, match=name):
        _store(tmp_path / "s.h5")
    monkeypatch.undo()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.h5"]
    assert read(old)[1]["model"] == "old"


def test_chunk_write_on_a_full_disk_keeps_the_checkpoint(tmp_path, monkeypatch):
    store = _half_done(tmp_path / "s.h5")

    def full(fd, data, offset=None):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(storage.checkpoint, "_write_all", full)
    with pytest.raises(StorageError, match=r"cannot write chunk 1 to '.*s\.h5'.*\(ENOSPC\)"):
        store.write_chunk(1, _values(store.points, store.chunk_slice(1)))
    monkeypatch.undo()
    assert store.pending_chunks() == [1, 3]
    table, _ = read(tmp_path / "s.h5")
    np.testing.assert_array_equal(table.columns["status"][6:9], [6, 7, 8])


def test_free_space_is_checked_before_creating(tmp_path, monkeypatch):
    real = shutil.disk_usage
    monkeypatch.setattr(storage.disk.shutil, "disk_usage", lambda p: real(p)._replace(free=10_000))
    with pytest.raises(StorageError, match=r"needs about \d+ bytes, only 10000 are free"):
        write(tmp_path / "s.h5", RESULTS["solution"](), provenance={})
    with pytest.raises(StorageError, match="only 10000 are free"):
        storage.check_writable(tmp_path / "x.h5", 1_000_000)
    assert list(tmp_path.iterdir()) == []


def test_read_only_file_system_is_reported(tmp_path, monkeypatch):
    real = os.statvfs

    class ReadOnly:
        def __init__(self, st):
            self.st = st

        def __getattr__(self, name):
            return os.ST_RDONLY if name == "f_flag" else getattr(self.st, name)

    monkeypatch.setattr(storage.disk.os, "statvfs", lambda p: ReadOnly(real(p)))
    with pytest.raises(StorageError, match=r"cannot write '.*': read-only file system"):
        write(tmp_path / "s.h5", RESULTS["basin"](), provenance={})
    with pytest.raises(StorageError, match="read-only"):
        storage.check_writable(tmp_path / "x.h5")


def test_write_under_a_file_size_limit(tmp_path):
    """write() itself (as ``find``/``run``/``basin`` use it) under RLIMIT_FSIZE."""
    code = textwrap.dedent(
        f"""
        import resource, signal, sys
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (3000, 3000))
        sys.path.insert(0, {str(REPO / "tests")!r})
        from test_storage import RESULTS
        from walker.storage import StorageError, write
        try:
            write({str(tmp_path / "s.h5")!r}, RESULTS["solution"](), provenance={{}})
        except StorageError as exc:
            print(exc)
        """
    )
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr
    assert "(EFBIG)" in proc.stdout
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------------------------
# 8. Stale temporary files


def test_stale_temporary_files_are_removed(tmp_path):
    """Before: temporary files of a killed or crashed create were never removed (one was
    192 MB).  Now a create removes those of the same target whose writer is gone."""
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    alive = os.getppid()
    stale = tmp_path / f".b.h5.tmp-{dead.pid}-0123abcd"
    live = tmp_path / f".b.h5.tmp-{alive}-0123abcd"
    other = tmp_path / f".c.h5.tmp-{dead.pid}-0123abcd"
    fresh = tmp_path / f".b.h5.tmp-{dead.pid}-fedc4321"
    for p in (stale, live, other, fresh):
        p.write_bytes(b"x" * 1000)
    old = time.time() - 3600
    for p in (stale, live, other):
        os.utime(p, (old, old))
    write(tmp_path / "b.h5", RESULTS["basin"](), provenance={})
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == sorted(["b.h5", live.name, other.name, fresh.name])


def test_killed_create_leaves_a_temp_that_the_next_create_removes(tmp_path):
    path = tmp_path / "s.h5"
    code = textwrap.dedent(
        f"""
        import os, signal
        from walker.storage import disk
        real = disk._write_all
        def killed(fd, data, offset=None):
            real(fd, memoryview(data)[:100])
            os.kill(os.getpid(), signal.SIGKILL)
        disk._write_all = killed
        from walker.storage import SweepStore
        import numpy as np
        SweepStore.create_or_open({str(path)!r}, parameter_names=("p",),
            points=np.zeros((4, 1)), columns={{"a": ("f8", ())}}, chunk_size=2,
            provenance={{}})
        """
    )
    proc = subprocess.run([sys.executable, "-c", code], timeout=120)
    assert proc.returncode == -signal.SIGKILL
    (temp,) = tmp_path.iterdir()
    assert temp.name.startswith(".s.h5.tmp-")
    os.utime(temp, (time.time() - 60, time.time() - 60))
    store = SweepStore.create_or_open(
        path,
        parameter_names=("p",),
        points=np.zeros((4, 1)),
        columns={"a": ("f8", ())},
        chunk_size=2,
        provenance={},
    )
    assert store.pending_chunks() == [0, 1]
    assert [p.name for p in tmp_path.iterdir()] == ["s.h5"]


# --------------------------------------------------------------------------------------------
# 9. Fuzz: deterministic damage of every file kind (the slow suite below: random)


def _basin_kw():
    return dict(
        axis_names=("a", "b"),
        x=np.linspace(0, 1, 3),
        y=np.linspace(0, 1, 5),
        fixed_point=np.zeros(2),
        base=np.zeros(2),
        n_strides=10,
        tol=1e-6,
        period=1,
        provenance={"model": "toy"},
        chunk_size=2,
    )


@pytest.fixture(scope="module")
def file_kinds(tmp_path_factory):
    """One file of each kind walker writes: every result of ``write`` and a half-done sweep
    and basin checkpoint."""
    tmp = tmp_path_factory.mktemp("kinds")
    files = {
        name: write(tmp / f"{name}.h5", make(), provenance=PROVENANCE)
        for name, make in RESULTS.items()
    }
    _half_done(tmp / "sweep_checkpoint.h5")
    files["sweep_checkpoint"] = tmp / "sweep_checkpoint.h5"
    store = BasinStore.create_or_open(tmp / "basin_checkpoint.h5", **_basin_kw())
    store.write_chunk(1, np.full((2, 3), -1), np.full((2, 3), 7))
    files["basin_checkpoint"] = tmp / "basin_checkpoint.h5"
    return files


def _mutate(data: bytes, rng, how: str) -> bytes:
    data = bytearray(data)
    if how == "flip":
        data[int(rng.integers(len(data)))] ^= 1 << int(rng.integers(8))
    elif how == "byte":
        data[int(rng.integers(len(data)))] = int(rng.integers(256))
    else:
        data = data[: int(rng.integers(len(data)))]
    return bytes(data)


def _check_mutant(path, reference, timeout):
    """A mutated file either is refused with a one-line StorageError, or reads back exactly
    the reference."""
    try:
        got = read(path, timeout=timeout)
    except StorageError as exc:
        text = str(exc)
        assert "\n" not in text and text.startswith("cannot read"), text
        return "refused"
    assert_same(got[0], reference[0])
    assert_same(got[1], reference[1])
    return "same"


@pytest.mark.parametrize("how", ["flip", "byte", "truncate"])
def test_deterministic_damage_of_every_kind(tmp_path, file_kinds, how):
    """A handful of fixed bit flips, byte overwrites and truncations of each file kind:
    each ends in a StorageError or reads back unchanged, within the time limit."""
    rng = np.random.default_rng({"flip": 1, "byte": 2, "truncate": 3}[how])
    outcomes = []
    for name, path in sorted(file_kinds.items()):
        reference = read(path)
        original = path.read_bytes()
        for k in range(4):
            mutant = tmp_path / f"{name}-{k}.h5"
            mutant.write_bytes(_mutate(original, rng, how))
            outcomes.append(_check_mutant(mutant, reference, timeout=HANG_TIMEOUT))
    assert "refused" in outcomes


@pytest.mark.parametrize("keep", [0.0, 0.1, 0.5, 0.99])
def test_truncated_checkpoints_are_refused_on_resume(tmp_path, keep):
    """(Passed before too: it guards the new resume path, which reads in a child.)"""
    path = tmp_path / "s.h5"
    _half_done(path)
    truncate(path, path, keep)
    with pytest.raises(CheckpointMismatch, match=r"cannot resume '.*s\.h5'"):
        _store(path)


# --------------------------------------------------------------------------------------------
# Slow: random damage


@pytest.mark.slow
def test_fuzz_read_many_mutated_files(tmp_path, file_kinds):
    """Before: of 1,206 mutated files 233 read back with changed numbers and no error, and
    some crashed or hung the reader.  Now 1,200 random bit flips, byte overwrites and
    truncations over every file kind each end in a StorageError or read back unchanged;
    none crashes or hangs the test process."""
    rng = np.random.default_rng(17)
    counts = {"refused": 0, "same": 0}
    kinds = sorted(file_kinds.items())
    for k in range(1200):
        name, path = kinds[k % len(kinds)]
        how = ("flip", "byte", "truncate")[(k // len(kinds)) % 3]
        mutant = tmp_path / "mutant.h5"
        mutant.write_bytes(_mutate(path.read_bytes(), rng, how))
        counts[_check_mutant(mutant, read(path), timeout=10)] += 1
    assert counts["refused"] > 300 and sum(counts.values()) == 1200


@pytest.mark.slow
def test_fuzz_resume_bit_flipped_half_done_sweeps(tmp_path):
    """Before: 12 of 150 bit-flipped half-done sweep files resumed to exit 0 with a wrong
    row.  Now, over 300 single bit flips of a half-done sweep, a resume either is refused
    (CheckpointMismatch, exit 2 in the CLI) or finishes with every row right."""
    clean = tmp_path / "clean.h5"
    _half_done(clean)
    data = clean.read_bytes()
    expected = {name: v for name, v in _values(_points(), slice(0, 10)).items()}
    rng = np.random.default_rng(150)
    counts = {"refused": 0, "resumed": 0}
    for k in range(300):
        path = tmp_path / f"flip-{k}.h5"
        byte = int(rng.integers(len(data)))
        flip(clean, path, byte, int(rng.integers(8)))
        try:
            store = _store(path)
            for i in store.pending_chunks():
                store.write_chunk(i, _values(store.points, store.chunk_slice(i)))
            table = store.table()
        except StorageError:
            counts["refused"] += 1
            path.unlink()
            continue
        counts["resumed"] += 1
        for name, col in table.columns.items():
            np.testing.assert_array_equal(col, expected[name], err_msg=f"flip at {byte}")
        path.unlink()
    assert counts["resumed"] > 0 and counts["refused"] > 0
