"""Shared pieces of the benchmark scripts (scripts/bench_*.py).

* atomic output (temp file in the same directory, then ``os.replace``);
* interleaved timing: contenders run round-robin, the order rotated every round, and each
  contender's per-call times kept so that min and median can be reported;
* results/bench/README.md, regenerated from the markdown files the scripts write.

The contenders' models (the hand-written kneed walker, solve_ivp and heyoka strides) are in
scripts/_contenders.py.
"""

from __future__ import annotations

import argparse
import csv
import gc
import io
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "results" / "bench"
GAITS = ROOT / "gaits"


# ------------------------------------------------------------------------------ output
def write_atomic(path: Path, data: str | bytes) -> None:
    """Write ``data`` to ``path`` through a temp file in the same directory + os.replace."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=path.name + ".tmp-")
    try:
        with os.fdopen(fd, mode, **({} if mode == "wb" else {"encoding": "utf-8"})) as f:
            f.write(data)
        os.chmod(tmp, 0o644)  # mkstemp makes it private; results are for everyone to read
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_csv_atomic(path: Path, header, rows) -> None:
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for r in rows:
        w.writerow(r)
    write_atomic(path, buf.getvalue())


def savefig_atomic(fig, path: Path, **kw) -> None:
    buf = io.BytesIO()
    fig.savefig(buf, format=Path(path).suffix.lstrip("."), **kw)
    write_atomic(path, buf.getvalue())


def machine_line() -> str:
    import numba
    import scipy

    return (
        f"{platform.machine()}, {os.cpu_count()} logical CPUs, Python "
        f"{platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
        f"numba {numba.__version__}"
    )


def fmt_time(seconds: float) -> str:
    """Seconds with a unit that keeps 3 significant digits readable."""
    if not np.isfinite(seconds):
        return "n/a"
    if seconds < 1e-3:
        return f"{seconds * 1e6:.3g} µs"
    if seconds < 1.0:
        return f"{seconds * 1e3:.3g} ms"
    return f"{seconds:.3g} s"


def speed_ratio(f: float) -> str:
    """``"2.0x faster than"`` for ``f = t_other / t_walker >= 1``, else ``"2.0x slower than"``."""
    return f"{f:.1f}x faster than" if f >= 1 else f"{1 / f:.1f}x slower than"


# ------------------------------------------------------------------------------ timing
def _batch(fn, inner: int) -> float:
    """Seconds per call of ``fn`` over ``inner`` back-to-back calls (GC off, as timeit)."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        t = time.perf_counter()
        for _ in range(inner):
            fn()
        return (time.perf_counter() - t) / inner
    finally:
        if enabled:
            gc.enable()


def calibrate(fns: dict, batch_seconds: float) -> dict:
    """Calls per timed batch for each contender so that a batch lasts ~``batch_seconds``
    (each is called once first: warm-up, JIT)."""
    inner = {}
    for name, fn in fns.items():
        fn()
        t1 = _batch(fn, 1)
        t1 = min(t1, _batch(fn, 1))
        inner[name] = max(1, int(batch_seconds / max(t1, 1e-7)))
    return inner


def round_robin(fns: dict, reps: int, batch_seconds: float = 0.01, inner: dict | None = None):
    """Time the contenders interleaved: ``reps`` rounds, each round one batch of every
    contender, the starting contender rotated each round.

    Returns ``{name: ndarray of seconds per call, one entry per round}``.
    """
    names = list(fns)
    if inner is None:
        inner = calibrate(fns, batch_seconds)
    out = {n: [] for n in names}
    for r in range(reps):
        k = r % len(names)
        for n in names[k:] + names[:k]:
            out[n].append(_batch(fns[n], inner[n]))
    return {n: np.array(v) for n, v in out.items()}


# ------------------------------------------------------------------- README of results
README_SECTIONS = (
    (
        "stride.md",
        "One stride at equal error (work-precision)",
        "python scripts/bench_stride.py",
        ["stride.csv", "work_precision.png"],
    ),
    (
        "search.md",
        "Fixed-point search with multipliers",
        "python scripts/bench_search.py",
        ["search.csv"],
    ),
    ("basin.md", "Basin of attraction", "python scripts/bench_basin.py", ["basin.csv"]),
    (
        "coldstart.md",
        "Cold start of the CLI (new process, empty numba cache) vs warm",
        "python scripts/bench_coldstart.py",
        ["coldstart.csv"],
    ),
    (
        "sweep.md",
        "Sweep overhead per point",
        "python scripts/bench_sweep.py --overhead",
        ["sweep.csv"],
    ),
    (
        "longrun.md",
        "Long runs: memory and time against strides",
        "python scripts/bench_longrun.py",
        ["longrun.csv"],
    ),
    (
        "friction.md",
        "Cost of the dry-friction layer",
        "python scripts/bench_friction.py",
        ["friction.csv"],
    ),
    (
        "terrain.md",
        "Walks on per-step terrain (Monte-Carlo batch)",
        "python scripts/bench_terrain.py",
        ["terrain.csv"],
    ),
    (
        "mfpt.md",
        "Mean first-passage time, Monte Carlo on random slopes",
        "python scripts/bench_mfpt.py",
        ["mfpt.csv"],
    ),
)


def summary_of(md_text: str) -> str | None:
    for line in md_text.splitlines():
        if line.startswith("<!-- summary:"):
            return line[len("<!-- summary:") :].rstrip("->").strip()
    return None


def how_of(md_text: str) -> str | None:
    """The table's "How measured" paragraph (its ``<!-- how: ... -->`` line), if any."""
    for line in md_text.splitlines():
        if line.startswith("<!-- how:"):
            return line[len("<!-- how:") :].rstrip("->").strip()
    return None


def load_line() -> str:
    """The 1-, 5- and 15-minute load averages, for the tables' "How measured" paragraphs."""
    one, five, fifteen = os.getloadavg()
    return f"load average {one:.1f}, {five:.1f}, {fifteen:.1f} on {os.cpu_count()} logical CPUs"


def mode_of(md_text: str) -> str | None:
    for line in md_text.splitlines():
        if line.startswith("<!-- command:"):
            return line[len("<!-- command:") :].rstrip("->").strip()
    return None


def update_readme() -> None:
    """Regenerate results/bench/README.md from the markdown files present."""
    lines = [
        "# Benchmarks",
        "",
        "Regenerated by each `scripts/bench_*.py` run (scripts/_bench.py `update_readme`) from "
        "the tables present in this directory. Policy: speed is quoted as ratios measured side "
        "by side in one process, the contenders interleaved (round-robin repetitions, min and "
        "median reported per contender), against the strongest alternative a user would pick, "
        "named next to the ratio. Absolute times depend on the machine; the ratios are the "
        "result. A table whose command line carries `--quick` is a smoke run (fewer "
        "tolerances and repetitions, measured on a busy shared machine): re-run without "
        "`--quick` on a quiet machine before quoting it.",
        "",
    ]
    for md, title, command, extra in README_SECTIONS:
        path = OUT / md
        if not path.exists():
            continue
        text = path.read_text(encoding="utf-8")
        made = mode_of(text) or command
        lines += [f"## {title}", "", f"[{md}]({md}) — made by `{made}`."]
        files = [f for f in extra if (OUT / f).exists()]
        if files:
            lines.append("Data: " + ", ".join(f"[{f}]({f})" for f in files) + ".")
        s = summary_of(text)
        if s:
            lines += ["", s]
        h = how_of(text)
        if h:
            lines += ["", f"How measured: {h}"]
        if "work_precision.png" in files:
            lines += ["", "![work-precision](work_precision.png)"]
        lines.append("")
    write_atomic(OUT / "README.md", "\n".join(lines))


def publish(name: str, lines) -> None:
    """Write the markdown ``lines`` to results/bench/``name``, regenerate results/bench/README.md
    and print them."""
    text = "\n".join(lines)
    write_atomic(OUT / name, text)
    update_readme()
    print(text)


def command_line(script: str, argv) -> str:
    args = " ".join(argv if argv is not None else sys.argv[1:])
    return f"python scripts/{script}" + (f" {args}" if args else "")


def quick_options(script: str, doc: str, quick_help: str, argv) -> tuple[bool, str]:
    """Parse the command line of a benchmark whose one option is ``--quick`` (described by
    ``quick_help``; ``doc`` the script's docstring); return whether it is quick and the
    command line (:func:`command_line`)."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help=quick_help)
    return parser.parse_args(argv).quick, command_line(script, argv)
