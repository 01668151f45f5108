"""Damaged and hostile files (issue 17, storage half), read in this process: checksums on
every dataset and on each checkpoint chunk, HDF5 features walker never writes refused,
declared sizes capped, every provenance field and dataclass shape validated.  Reads in a
child process and the fuzz suite are in ``tests/test_storage_isolated_read.py``; writers in
``tests/test_storage_writer.py``.

Each test's docstring says what happened before these changes.  Files are crafted with
h5py in ``tests/_hostile_files.py``; the small sweep and basin checkpoints come from
``tests/_checkpoints.py``.
"""

from __future__ import annotations

import re

import h5py
import numpy as np
import pytest
from _checkpoints import COLUMNS, basin_kw, chunk_values, half_done_sweep, sweep_points, sweep_store
from _hostile_files import (
    chunk_offset,
    flip,
    link,
    one_line,
    poke,
    replace_dataset,
    set_attr,
    sweep_v1,
    unchecked,
    write_v1,
)
from test_storage import PROVENANCE, RESULTS, assert_same

from walker import storage
from walker.storage import BasinStore, CheckpointMismatch, StorageError, read, write

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
    half_done_sweep(tmp_path / "s.h5")
    store = BasinStore.create_or_open(tmp_path / "b.h5", **basin_kw())
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
    offset, _ = chunk_offset(path, dataset)
    flip(path, path, offset + 1, 3)
    with pytest.raises(StorageError, match=f"dataset '/{dataset}' fails its Fletcher-32") as info:
        read(path)
    one_line(info)


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
    poke(path, at + len('"rtol": 1e-1'), b"3")
    with pytest.raises(StorageError, match="checksum"):
        read(path)


def test_checksum_mismatch_names_the_file(tmp_path):
    """Before: the edited ``n_strides`` (99) read back as if written."""
    path = write(tmp_path / "b.h5", RESULTS["basin"](), provenance={})
    set_attr(path, "result", "n_strides", np.int64(99))
    with pytest.raises(StorageError, match=r"cannot read '.*b\.h5': corrupted.*checksum") as info:
        read(path)
    one_line(info)


def test_sweep_row_flip_is_recomputed_on_resume(tmp_path):
    """Before: 12 of 150 bit-flipped half-done sweeps resumed to exit 0 with wrong rows (e.g.
    ``status = 33554432``).  Now a done chunk whose rows fail their checksum is refused by
    ``read`` and pending again on resume, and recomputing it repairs the file."""
    path = tmp_path / "s.h5"
    half_done_sweep(path)
    offset, _ = chunk_offset(path, "result/columns/status", 2)
    poke(path, offset + 3, b"\x02")  # row 6: status 6 -> 33554438
    with pytest.raises(StorageError, match="checkpoint chunk 2 fails its checksum"):
        read(path)
    store = sweep_store(path)
    assert store.pending_chunks() == [1, 2, 3]
    assert storage.checkpoint_progress(path) == (1, 4)
    for i in store.pending_chunks():
        store.write_chunk(i, chunk_values(store.points, store.chunk_slice(i)))
    table, _ = read(path)
    np.testing.assert_array_equal(table.columns["status"], np.arange(10))


@pytest.mark.parametrize("what", ["done", "chunk_sha256"])
def test_sweep_flag_flip_is_pending(tmp_path, what):
    """Before: a flipped done byte (1 -> 3) still read as done, whatever its rows held.
    Now a damaged done flag or chunk checksum makes ``read`` refuse the file and its chunk
    pending on resume (its rows are recomputed), never done with rows that were not
    checked."""
    path = tmp_path / "s.h5"
    half_done_sweep(path)
    offset, size = chunk_offset(path, f"checkpoint/{what}", 2)
    flip(path, path, offset, 1)
    with pytest.raises(StorageError, match="checkpoint chunk 2 fails its checksum"):
        read(path)
    store = sweep_store(path)
    assert store.pending_chunks() == [1, 2, 3]
    store.write_chunk(2, chunk_values(store.points, store.chunk_slice(2)))
    table, _ = read(path)
    np.testing.assert_array_equal(table.columns["status"][6:9], [6, 7, 8])


def test_sweep_static_damage_refuses_resume(tmp_path):
    """Damage outside the chunk rows (the points) refuses the file, naming the checksum.
    Before: the resume was refused as "a different sweep (1 of the points differ)", a wrong
    cause that sends the user to look for another command line."""
    path = tmp_path / "s.h5"
    half_done_sweep(path)
    offset, _ = chunk_offset(path, "result/points")
    flip(path, path, offset + 7, 0)
    with pytest.raises(CheckpointMismatch, match="cannot resume .*Fletcher-32"):
        sweep_store(path)


@pytest.mark.slow  # old-file resume: the integration tier
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
        points=sweep_points(),
        columns=COLUMNS,
        chunk_size=3,
        provenance={"model": "compass"},
    )
    store = sweep_store(path)
    assert store.pending_chunks() == [0, 1, 2, 3]
    store.write_chunk(1, chunk_values(store.points, store.chunk_slice(1)))
    assert sweep_store(path).pending_chunks() == [0, 2, 3]
    table, prov = read(path)
    assert prov["schema_version"] == 1
    np.testing.assert_array_equal(table.columns["status"][3:6], [3, 4, 5])
    assert (table.columns["status"][np.r_[0:3, 6:10]] == -1).all()
    np.testing.assert_array_equal(
        table.columns["mult"][3:6], chunk_values(sweep_points(), slice(3, 6))["mult"]
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
    one_line(e)
    with pytest.raises(StorageError, match=HOSTILE[kind]):
        read(path, isolate=False)


def test_external_storage_in_a_checkpoint_is_refused_on_resume(tmp_path, secret):
    path = tmp_path / "s.h5"
    sweep_store(path)
    unchecked(path)
    replace_dataset(
        path, "result/points", shape=(10, 2), dtype="f8", external=[(str(secret), 0, 160)]
    )
    with pytest.raises(CheckpointMismatch, match="external file"):
        sweep_store(path)


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
    assert re.search(message, one_line(info)), str(info.value)


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
    one_line(info)


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
