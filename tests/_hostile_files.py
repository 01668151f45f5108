"""Damaged and hostile walker files for the ``tests/test_storage_*`` tests of damaged files.

Files are made with h5py directly: in the layout of schema version 1 (what walker wrote
before checksums: contiguous datasets, no ``checksum`` attribute, no chunk SHA-256), or by
editing a file :func:`walker.storage.write` made.
"""

from __future__ import annotations

import functools
import json
import zlib
from pathlib import Path

import h5py
import numpy as np

from walker import storage


def write_v1(path, result, provenance) -> Path:
    """``result`` in the schema-1 layout (as walker wrote it before checksums)."""
    prov_json = storage._check_provenance(provenance)
    kind = storage._KIND_OF[type(result)]
    tree = storage._encode(result, type(result), type(result).__name__)
    attrs = storage._provenance_attrs(prov_json, kind)
    attrs["schema_version"] = np.int64(1)

    def emit(node, group):
        for name, value in node["attrs"].items():
            group.attrs[name] = value
        for name, arr in node["datasets"].items():
            group.create_dataset(name, data=arr)
        for name, sub in node["groups"].items():
            emit(sub, group.create_group(name))

    with h5py.File(path, "w", libver="earliest") as f:
        f.attrs.update(attrs)
        emit(tree, f.create_group("result"))
    return Path(path)


def sweep_v1(path, *, parameter_names, points, columns, chunk_size, provenance) -> Path:
    """An empty sweep checkpoint in the schema-1 layout (contiguous columns, a bool
    ``/checkpoint/done``, no chunk checksums)."""
    attrs = storage._provenance_attrs(storage._check_provenance(provenance), "sweep")
    attrs["schema_version"] = np.int64(1)
    points = np.asarray(points, dtype=np.float64)
    n = points.shape[0]
    n_chunks = -(-n // chunk_size)
    with h5py.File(path, "w", libver="earliest") as f:
        f.attrs.update(attrs)
        g = f.create_group("result")
        g.attrs["dataclass"] = "SweepTable"
        g.attrs["parameter_names"] = json.dumps(list(parameter_names))
        g.create_dataset("points", data=points)
        cg = g.create_group("columns")
        cg.attrs["names"] = json.dumps(list(columns))
        for name, (dtype, shape) in columns.items():
            dtype = np.dtype(dtype)
            fill = storage._fill_value(dtype)
            ds = cg.create_dataset(name, shape=(n, *shape), dtype=dtype, fillvalue=fill)
            ds[...] = np.full((n, *shape), fill, dtype=dtype)
        k = f.create_group("checkpoint")
        k.attrs["chunk_size"] = np.int64(chunk_size)
        k.attrs["n_chunks"] = np.int64(n_chunks)
        k.create_dataset("done", data=np.zeros(n_chunks, dtype=bool))
    return Path(path)


def unchecked(path) -> Path:
    """Turn a file :func:`walker.storage.write` made into a schema-1 file: the same content
    rewritten in the layout of version 1 (contiguous datasets without Fletcher-32, no root
    ``checksum``, no chunk SHA-256), so that what it holds is checked by the reader's rules
    only, not by the checksums.  (Setting ``schema_version`` to 1 alone is refused: a
    downgraded file.)"""
    tree = _tree(path)

    def emit(node, group, where):
        for name, value in node["attrs"].items():
            if where == "/" and name == "checksum":
                continue
            group.attrs[name] = value
        for name, arr in node["datasets"].items():
            if where == "/checkpoint" and name == "chunk_sha256":
                continue
            ds = group.create_dataset(name, data=np.ascontiguousarray(arr))
            for attr, value in node.get("dataset_attrs", {}).get(name, {}).items():
                ds.attrs[attr] = value
        for name, sub in node["groups"].items():
            emit(sub, group.create_group(name), f"{where.rstrip('/')}/{name}")

    with h5py.File(path, "w", libver="earliest") as f:
        emit(tree, f, "/")
        f.attrs["schema_version"] = np.int64(1)
    return Path(path)


def set_attr(path, obj: str, name: str, value) -> Path:
    with h5py.File(path, "r+") as f:
        f[obj].attrs[name] = value
    return Path(path)


def replace_dataset(path, name: str, **create) -> Path:
    """Delete dataset ``name`` and create it again with ``create_dataset(**create)``."""
    with h5py.File(path, "r+") as f:
        del f[name]
        f.create_dataset(name, **create)
    return Path(path)


def link(path, name: str, target) -> Path:
    """Replace the object ``name`` by a link (h5py.SoftLink, ExternalLink or an object)."""
    with h5py.File(path, "r+") as f:
        if name in f:
            del f[name]
        f[name] = target
    return Path(path)


def flip(src, dst, byte: int, bit: int) -> Path:
    data = bytearray(Path(src).read_bytes())
    data[byte % len(data)] ^= 1 << bit
    Path(dst).write_bytes(bytes(data))
    return Path(dst)


def truncate(src, dst, keep: float) -> Path:
    data = Path(src).read_bytes()
    Path(dst).write_bytes(data[: int(len(data) * keep)])
    return Path(dst)


def basin_v1(path, basin, *, tol, period, chunk_size, provenance, done=()) -> Path:
    """A basin checkpoint in the schema-1 layout, with the rows of the chunks in ``done``
    taken from ``basin`` and marked done, the others not computed."""
    attrs = storage._provenance_attrs(storage._check_provenance(provenance), "basin")
    attrs["schema_version"] = np.int64(1)
    ny, nx = basin.outcome.shape
    n_chunks = -(-ny // chunk_size)
    with h5py.File(path, "w", libver="earliest") as f:
        f.attrs.update(attrs)
        g = f.create_group("result")
        g.attrs["dataclass"] = "BasinMap"
        g.attrs["axis_names"] = json.dumps(list(basin.axis_names))
        g.attrs["n_strides"] = np.int64(basin.n_strides)
        for name in ("x", "y", "fixed_point", "base"):
            g.create_dataset(name, data=getattr(basin, name))
        for name, fill in (("outcome", storage.BASIN_NOT_COMPUTED), ("strides", -1)):
            ds = g.create_dataset(name, shape=(ny, nx), dtype=np.int64, fillvalue=fill)
            for start in range(0, ny, chunk_size):
                stop = min(start + chunk_size, ny)
                rows = np.full((stop - start, nx), fill, dtype=np.int64)
                if start // chunk_size in done:
                    rows = getattr(basin, name)[start:stop]
                ds[start:stop] = rows
        k = f.create_group("checkpoint")
        k.attrs["chunk_size"] = np.int64(chunk_size)
        k.attrs["n_chunks"] = np.int64(n_chunks)
        k.attrs["tol"] = np.float64(tol)
        k.attrs["period"] = np.int64(period)
        flags = np.zeros(n_chunks, dtype=bool)
        flags[list(done)] = True
        k.create_dataset("done", data=flags)
    return Path(path)


def chunk_offset(path, dataset, index=0):
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


def poke(path, offset, new: bytes):
    """Overwrite the bytes of the file ``path`` from ``offset`` with ``new``."""
    data = bytearray(Path(path).read_bytes())
    data[offset : offset + len(new)] = new
    Path(path).write_bytes(bytes(data))


def one_line(exc_info):
    """The message of a refused file, checked to be one line that starts with "cannot "."""
    text = str(exc_info.value)
    assert "\n" not in text and text.startswith("cannot ")
    return text


def _tree(path):
    """The tree walker reads from ``path`` (in this process, no budget)."""
    from walker.storage.loader import _Loader

    with h5py.File(path, "r") as f:
        return _Loader(f, Path(path), None, None).run()


def resign(path, tree) -> Path:
    """Store in ``path`` the root ``checksum`` of ``tree``: what a forger with walker's
    source does to make an edited file pass the SHA-256."""
    from walker.storage.checksums import _content_digest

    with h5py.File(path, "r+") as f:
        f.attrs["checksum"] = _content_digest(tree)
    return Path(path)


def bomb(src, dst, *, declared: int, dataset: str = "result/values", signed: bool = False) -> Path:
    """A decompression bomb made from the walker file ``src``: ``dataset`` (float64) is
    replaced by one of the same rows (1-D: one row) whose columns make it ``declared``
    bytes, stored as chunks of 1 MiB of zeros deflated at level 9 (about 1 KiB each, an
    expansion near deflate's 1032:1).  The chunks are written raw (``write_direct_chunk``),
    so making the bomb takes no memory.  ``signed``: the root ``checksum`` is computed again for the
    bombed content (streamed over a broadcast zero array), so that only a size cap can
    refuse it; else the old checksum is left, stale."""
    import shutil

    shutil.copyfile(src, dst)
    chunk_cols = 1 << 17  # 1 MiB of float64
    with h5py.File(dst, "r") as f:
        one_d = f[dataset].ndim == 1
        rows = 1 if one_d else f[dataset].shape[0]
    cols = max(declared // (8 * rows * chunk_cols), 1) * chunk_cols
    zipped = zlib.compress(bytes(8 * chunk_cols), 9)
    with h5py.File(dst, "r+") as f:
        del f[dataset]
        shape, chunks = ((cols,), (chunk_cols,)) if one_d else ((rows, cols), (1, chunk_cols))
        ds = f.create_dataset(dataset, shape=shape, dtype="f8", chunks=chunks, compression="gzip")
        for r in range(rows):
            for c in range(0, cols, chunk_cols):
                ds.id.write_direct_chunk((c,) if one_d else (r, c), zipped)
    if signed:
        tree = _tree(src)
        node = tree
        *groups, name = dataset.split("/")
        for g in groups:
            node = node["groups"][g]
        node["datasets"][name] = np.broadcast_to(np.float64(0.0), shape)
        resign(dst, tree)
    return Path(dst)


# --------------------------------------------------------------------------------------------
# A corpus of hostile files made from any walker file


@functools.lru_cache(maxsize=1)
def _zeros_stream(mib: int) -> bytes:
    packer = zlib.compressobj(9)
    return b"".join(packer.compress(bytes(1 << 20)) for _ in range(mib)) + packer.flush()


def chunk_bomb(src, dst, *, dataset: str, mib: int = 64) -> Path:
    """``src`` with ``dataset`` (float64) stored in one deflated chunk of its own shape
    whose stream inflates to ``mib`` MiB of zeros: the declared size is right, the stream
    is not (HDF5's filter would inflate all of it)."""
    import shutil

    shutil.copyfile(src, dst)
    with h5py.File(dst, "r+") as f:
        shape = f[dataset].shape
        del f[dataset]
        ds = f.create_dataset(dataset, shape=shape, dtype="f8", chunks=shape, compression="gzip")
        ds.id.write_direct_chunk((0,) * len(shape), _zeros_stream(mib))
    return Path(dst)


def _datasets(path) -> list[tuple[str, tuple, str]]:
    """(path, shape, dtype kind) of every dataset of ``path``, sorted."""
    out = []
    with h5py.File(path, "r") as f:
        f.visititems(
            lambda n, o: (
                out.append((n, o.shape, o.dtype.kind)) if isinstance(o, h5py.Dataset) else None
            )
        )
    return sorted(out)


def _target(path) -> str:
    """The dataset the structural attacks replace: the largest float dataset outside
    ``/checkpoint`` that no checkpoint writes chunk by chunk (those are refused for their
    layout already)."""
    with h5py.File(path, "r") as f:
        dynamic = "checkpoint" in f
    candidates = [
        (int(np.prod(shape)), name)
        for name, shape, kind in _datasets(path)
        if kind == "f"
        and len(shape) >= 1
        and not name.startswith("checkpoint/")
        and not (
            dynamic
            and (name.startswith("result/columns/") or name in ("result/outcome", "result/strides"))
        )
    ]
    return max(candidates)[1]


def _edit(src, dst, change) -> Path:
    import shutil

    shutil.copyfile(src, dst)
    with h5py.File(dst, "r+") as f:
        change(f)
    return Path(dst)


def _replace(f, name, **create):
    data = f[name][...]
    del f[name]
    f.create_dataset(name, data=data, **create)


def _external_storage(f, name, src):
    """``name`` with its raw data in the external file ``src``, at the dataset's offset
    there when it is contiguous (the same bytes: it would read back equal)."""
    data = f[name][...]
    del f[name]
    f.create_dataset(
        name, shape=data.shape, dtype=data.dtype, external=[(str(src), 0, data.nbytes)]
    )


def _virtual(f, name, src):
    data = f[name]
    layout = h5py.VirtualLayout(shape=data.shape, dtype=data.dtype)
    layout[...] = h5py.VirtualSource(str(src), name, shape=data.shape)
    del f[name]
    f.create_virtual_dataset(name, layout)


def _header_attr(name, value):
    def change(f):
        f.attrs[name] = value

    return change


def corpus(
    src, out_dir, *, n_flips: int = 8, seed: int = 0, bomb_bytes: int = 1 << 30, only=None
) -> dict[str, Path]:
    """Hostile files made from the walker file ``src`` into ``out_dir``: name -> path.

    Categories (the name's prefix): ``flip-k`` (one random bit flipped), ``truncate-f``
    (the first fraction ``f`` kept), ``header-*`` (the superblock signature, an unknown or
    swapped kind, a newer or downgraded schema, garbage provenance, a wrong dataclass),
    ``link-*`` (soft, external, a second hard link, a group linked into itself),
    ``external-storage``, ``virtual``, ``filter-*`` (lzf, scale-offset: filters walker never
    writes), ``bomb-chunk`` (one chunk of the dataset's own size whose deflate stream
    inflates to 64 MiB), ``bomb-stale`` and ``bomb-signed`` (a deflated dataset declaring
    ``bomb_bytes`` at about 1000:1; the second with a valid checksum).  None is re-signed
    but that bomb: each must be refused or read back equal to ``src``.  ``only``: a
    predicate on the name, to make a sample."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    src = Path(src)
    data = src.read_bytes()
    target = _target(src)
    with h5py.File(src, "r") as f:
        kind = f.attrs["kind"]
    other_kind = "branch" if kind != "branch" else "fixed_point"
    out: dict[str, Path] = {}

    def put(name, make):
        if only is None or only(name):
            out[name] = make(out_dir / f"{src.stem}-{name}.h5")

    rng = np.random.default_rng(seed)
    for k in range(n_flips):
        byte, bit = int(rng.integers(len(data))), int(rng.integers(8))
        put(f"flip-{k}", lambda dst, b=byte, t=bit: flip(src, dst, b, t))
    for keep in (0.0, 0.01, 0.5, 0.9, 0.999):
        put(f"truncate-{keep}", lambda dst, k=keep: truncate(src, dst, k))

    def signature(dst):
        raw = bytearray(data)
        raw[1] ^= 0xFF  # "\x89HDF" -> not an HDF5 file
        Path(dst).write_bytes(bytes(raw))
        return Path(dst)

    put("header-signature", signature)
    headers = {
        "header-kind-unknown": _header_attr("kind", "nope"),
        "header-kind-swapped": _header_attr("kind", other_kind),
        "header-version-newer": _header_attr("schema_version", np.int64(99)),
        "header-version-downgraded": _header_attr("schema_version", np.int64(1)),
        "header-version-text": _header_attr("schema_version", "2"),
        "header-version-huge": _header_attr("schema_version", np.uint64(2**64 - 1)),
        "header-provenance-garbage": _header_attr("provenance", "{not json"),
        "header-provenance-deep": _header_attr("provenance", "[" * 100_000 + "]" * 100_000),
        "header-dataclass": lambda f: f["result"].attrs.__setitem__(
            "dataclass", "Solution" if kind != "solution" else "FixedPoint"
        ),
    }
    for name, change in headers.items():
        put(name, lambda dst, c=change: _edit(src, dst, c))
    links = {
        "link-soft": lambda f: (
            f.__delitem__(target),
            f.__setitem__(target, h5py.SoftLink("/result")),
        ),
        "link-external": lambda f: (
            f.__delitem__(target),
            f.__setitem__(target, h5py.ExternalLink(str(src), "/" + target)),
        ),
        "link-second-hard": lambda f: f.__setitem__("result/again", f[target]),
        "link-group-loop": lambda f: f.__setitem__("result/loop", f["result"]),
    }
    for name, change in links.items():
        put(name, lambda dst, c=change: _edit(src, dst, c))
    put(
        "external-storage", lambda dst: _edit(src, dst, lambda f: _external_storage(f, target, src))
    )
    put("virtual", lambda dst: _edit(src, dst, lambda f: _virtual(f, target, src)))
    put("filter-lzf", lambda dst: _edit(src, dst, lambda f: _replace(f, target, compression="lzf")))
    put(
        "filter-scaleoffset",
        lambda dst: _edit(src, dst, lambda f: _replace(f, target, scaleoffset=4)),
    )
    put("bomb-chunk", lambda dst: chunk_bomb(src, dst, dataset=target))
    put("bomb-stale", lambda dst: bomb(src, dst, declared=bomb_bytes, dataset=target))
    put(
        "bomb-signed",
        lambda dst: bomb(src, dst, declared=bomb_bytes, dataset=target, signed=True),
    )
    return out
