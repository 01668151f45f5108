"""Long runs of ``walker run``: wall time and peak memory against the number of strides.

Runs ``python -m walker run gaits/kneed_hsu.toml --strides N --out <tmp>/run.h5`` in a new
process for each N, under ``/usr/bin/time -v`` (peak resident set size of the process), and
reports wall time, time per stride, peak memory and the file's size.  Runs of more than
``walker.cli.run.BLOCK_STRIDES`` strides are integrated in blocks and streamed to the file,
so memory should stay flat and time grow linearly.  The contender is the run as it was
before blocks (one call keeping every step, budget 1,000,000 steps), at the largest N it
could finish (it ended in MAX_STEPS after about 21.7k kneed strides): its peak memory at
20,000 strides is reported beside ours.

Writes results/bench/longrun.md and results/bench/longrun.csv.

Usage::

    python scripts/bench_longrun.py            # 10k, 100k and 1M strides
    python scripts/bench_longrun.py --quick    # 10k and 100k
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _bench import GAITS, OUT, ROOT, machine_line, publish, quick_options, write_csv_atomic  # noqa: E402

ONE_PIECE = """
import sys
from walker import load_scene
from walker.simulation.stride import simulate, solver_settings
scene = load_scene(sys.argv[1]); c = scene.compute; n = int(sys.argv[2])
s = solver_settings(c); s.pop("t_max", None)
sol = simulate(scene.walker_model, scene.params, scene.state, output="full", n_strides=n,
               t_max=c.t_max * n, phase0=scene.phase, max_steps=1_000_000, **s)
print(sol.status.name, sol.n_strides)
"""


def _timed(argv: list[str]) -> tuple[float, float, str]:
    """Wall seconds, peak RSS [MiB] and stdout of ``argv`` under /usr/bin/time -v."""
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    t0 = time.perf_counter()
    proc = subprocess.run(
        ["/usr/bin/time", "-v", *argv], capture_output=True, text=True, env=env, cwd=ROOT
    )
    wall = time.perf_counter() - t0
    peak = re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr)
    return wall, (int(peak.group(1)) / 1024 if peak else float("nan")), proc.stdout


def main(argv=None) -> None:
    quick, command = quick_options("bench_longrun.py", __doc__, "10k and 100k strides", argv)
    scene = GAITS / "kneed_hsu.toml"
    counts = [10_000, 100_000] if quick else [10_000, 100_000, 1_000_000]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for n in counts:
            out = Path(tmp) / f"run{n}.h5"
            wall, peak, text = _timed(
                [
                    sys.executable,
                    "-m",
                    "walker",
                    "run",
                    str(scene),
                    "--strides",
                    str(n),
                    "--out",
                    str(out),
                ]
            )
            status = text.split(":", 1)[0].replace("status ", "").strip()
            size = out.stat().st_size / 2**20 if out.exists() else float("nan")
            rows.append(
                [
                    "walker run, blocks streamed to --out",
                    n,
                    status,
                    wall,
                    wall / n * 1e6,
                    peak,
                    size,
                ]
            )
            print(rows[-1])
            out.unlink(missing_ok=True)
        wall, peak, text = _timed([sys.executable, "-c", ONE_PIECE, str(scene), "20000"])
        rows.append(
            [
                "one piece, every step kept (before)",
                20_000,
                text.split()[0],
                wall,
                wall / 20_000 * 1e6,
                peak,
                float("nan"),
            ]
        )
        print(rows[-1])
    header = ["how", "strides", "status", "wall_s", "per_stride_us", "peak_rss_mib", "file_mib"]
    write_csv_atomic(OUT / "longrun.csv", header, rows)
    ours = [r for r in rows if r[0].startswith("walker run")]
    summary = (
        "`walker run gaits/kneed_hsu.toml --strides N --out run.h5`: peak memory "
        + ", ".join(f"{r[5]:.0f} MiB at {r[1]:,}" for r in ours)
        + " strides; time per stride "
        + ", ".join(f"{r[4]:.0f} us" for r in ours)
        + f" (1-minute load average {os.getloadavg()[0]:.2f} at the end; the time includes "
        "writing the file and its checksum pass); the former one-piece run kept every step: "
        f"{rows[-1][5]:.0f} MiB at 20,000 strides, and ended in MAX_STEPS past about 21.7k."
    )
    lines = [
        "# Long runs",
        "",
        f"<!-- command: {command} -->",
        f"<!-- summary: {summary} -->",
        "",
        f"Made by `{command}` on {machine_line()}; 1-minute load average {os.getloadavg()[0]:.2f} "
        "when done (a shared, loaded machine: the times are upper bounds).",
        "",
        __doc__.split("\n\n")[1].replace("\n", " "),
        "",
        "| how | strides | status | wall [s] | per stride [us] | peak RSS [MiB] | file [MiB] |",
        "|---|---:|---|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r[0]} | {r[1]:,} | {r[2]} | {r[3]:.1f} | {r[4]:.0f} | {r[5]:.0f} | {r[6]:.0f} |"
        )
    lines += ["", summary, ""]
    publish("longrun.md", lines)


if __name__ == "__main__":
    main()
