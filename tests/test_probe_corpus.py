"""The hostile-file corpus of issue 33 (item 9) over every file kind the command line writes:
``find``, ``run``, ``sweep``, ``basin``, ``continue`` and ``orbit-diagram``.

Each file is made by the command line itself (in this process), then
:func:`_hostile_files.corpus` makes its hostile twins: bit flips, truncations, crafted
headers, soft/external/second hard links, external storage, virtual datasets, foreign filters
and decompression bombs (one re-signed with a valid checksum).  Every twin must end in one
of two ways, with no crash, no hang, no traceback: refused (a one-line ``StorageError``;
``walker plot`` exit 2 with one line; a resumed sweep or basin exit 2), or read back exactly
as the original (``test_storage.assert_same``, field by field: no read that silently
differs).  The default tier checks a sample; the slow tier the whole corpus, through
``read``, ``walker plot`` and, for the checkpoints, a resume.
"""

from __future__ import annotations

import shutil
import zlib
from pathlib import Path

import pytest
from _hostile_files import corpus
from test_storage import assert_same

from walker.cli import main
from walker.storage import StorageError, read

REPO = Path(__file__).resolve().parents[1]
SCENE = str(REPO / "gaits" / "compass_goswami.toml")
HANG_TIMEOUT = 20.0  # a read not finished by then is a hang (the reader's own budget)
MiB = 1 << 20

# The command of each file kind, small: about 3 s for all six.
COMMANDS = {
    "find": ["find", SCENE],
    "run": ["run", SCENE, "--strides", "2"],
    "sweep": ["sweep", SCENE, "--param", "slope=0.01:0.02:3", "--chunk-size", "2"]
    + ["--quiet", "--jobs", "1"],
    "basin": ["basin", SCENE, "--n", "4", "--strides", "5", "--quiet", "--jobs", "1"],
    "continue": ["continue", SCENE, "--param", "slope", "--range", "0.052:0.053"]
    + ["--max-points", "4"],
    "orbit-diagram": ["orbit-diagram", SCENE, "--range", "0.052:0.053", "--n", "3"]
    + ["--transient", "2", "--strides", "3"],
}
CATEGORIES = (
    "flip",
    "truncate",
    "header",
    "link",
    "external-storage",
    "virtual",
    "filter",
    "bomb",
)


@pytest.fixture(scope="module")
def kinds(tmp_path_factory):
    """kind -> (path, what read() gives) of a file each command wrote, made on first use."""
    tmp = tmp_path_factory.mktemp("kinds")
    made: dict[str, tuple] = {}

    def get(kind: str) -> tuple:
        if kind not in made:
            path = tmp / f"{kind}.h5"
            code = main([*COMMANDS[kind], "--out", str(path)])
            assert code in (0, 1) and path.exists(), kind  # continue may stop at its range
            _stop_tqdm_monitor()
            made[kind] = (path, read(path))
        return made[kind]

    return get


def _stop_tqdm_monitor() -> None:
    """The progress bars leave tqdm's monitor thread running; with a second thread alive,
    each read would start a new interpreter (0.6 s) instead of forking (10 ms)."""
    import tqdm
    import tqdm.auto

    for cls in {tqdm.tqdm, tqdm.auto.tqdm}:
        monitor = cls.__dict__.get("monitor")
        if monitor is not None:
            monitor.exit()
            cls.monitor = None


def _check_read(path: Path, reference) -> str:
    """``path`` is refused in one line or reads back as ``reference``."""
    try:
        got = read(path, timeout=HANG_TIMEOUT)
    except StorageError as exc:
        text = str(exc)
        assert "\n" not in text and text.startswith("cannot read"), text
        return "refused"
    assert_same(got[0], reference[0])
    assert_same(got[1], reference[1])
    return "same"


def _check_plot(path: Path, out: Path, capsys) -> int:
    """``walker plot`` of ``path``: exit 0, or 2 with one ``walker: error`` line."""
    code = main(["plot", str(path), "--out", str(out)])
    err = capsys.readouterr().err
    assert code in (0, 2), err
    if code == 2:
        assert err.count("\n") == 1 and err.startswith("walker: error: "), err
    assert "Traceback" not in err and "internal error" not in err, err
    return code


SAMPLE_KINDS = ("basin", "find", "orbit-diagram", "run", "sweep")  # continue: 1.6 s to make


def _sample(kind_index: int):
    """Two categories per kind, rotating, so that five kinds cover all eight."""
    chosen = {CATEGORIES[(2 * kind_index + j) % len(CATEGORIES)] for j in range(2)}
    return lambda name: (
        any(name.startswith(c) for c in chosen)
        and not name.startswith(("flip-1", "flip-2", "flip-3"))
    )


@pytest.mark.slow  # storage fuzzing: the integration tier
def test_corpus_sample_of_every_kind(tmp_path, kinds):
    """Default tier: five kinds with two categories of attack each (together all eight);
    bombs declare 64 MiB at about 1000:1 (the slow tier: 1 GiB, and every kind)."""
    seen = set()
    outcomes = []
    for i, kind in enumerate(SAMPLE_KINDS):
        path, reference = kinds(kind)
        files = corpus(
            path, tmp_path / kind, n_flips=4, bomb_bytes=64 * MiB, only=_sample(i), seed=i
        )
        assert files, kind
        for name, mutant in files.items():
            seen.add(next(c for c in CATEGORIES if name.startswith(c)))
            outcomes.append((kind, name, _check_read(mutant, reference)))
    assert seen == set(CATEGORIES)
    structural = [o for k, n, o in outcomes if not n.startswith(("flip", "truncate"))]
    assert set(structural) == {"refused"}, outcomes


@pytest.mark.slow
@pytest.mark.parametrize("kind", sorted(COMMANDS))
def test_whole_corpus_read_and_plot(tmp_path, kinds, kind, capsys):
    """Slow tier: the whole corpus of each kind (40 bit flips, 5 truncations, 9 crafted
    headers, 4 links, external storage, a virtual dataset, 2 foreign filters, 3 bombs: 2 of
    1 GiB, one chunk inflating to 64 MiB) through ``read`` and ``walker plot``."""
    path, reference = kinds(kind)
    files = corpus(path, tmp_path / "corpus", n_flips=40, seed=zlib.crc32(kind.encode()))
    counts = {"refused": 0, "same": 0}
    (tmp_path / "figs").mkdir()
    for name, mutant in sorted(files.items()):
        outcome = _check_read(mutant, reference)
        counts[outcome] += 1
        if not name.startswith(("flip", "truncate")):
            assert outcome == "refused", name
        if name.startswith("flip") and int(name.split("-")[1]) >= 8:
            continue  # the plot of every flip would take minutes; eight of them suffice
        code = _check_plot(mutant, tmp_path / "figs" / name, capsys)
        assert code == (2 if outcome == "refused" else 0), name
    assert counts["refused"] > 20


@pytest.mark.slow
@pytest.mark.parametrize("kind", ["sweep", "basin"])
def test_whole_corpus_resumed(tmp_path, kinds, kind, capsys):
    """Slow tier: rerunning the command on each hostile twin of a finished sweep or basin
    (a resume) either is refused (exit 2, one line) or ends with a file that reads back
    as the original (a damaged chunk is recomputed, to the same numbers)."""
    path, reference = kinds(kind)
    files = corpus(path, tmp_path / "corpus", n_flips=40, seed=7, bomb_bytes=64 * MiB)
    for name, mutant in sorted(files.items()):
        work = tmp_path / "work.h5"
        shutil.copyfile(mutant, work)
        code = main([*COMMANDS[kind], "--out", str(work)])
        err = capsys.readouterr().err
        assert code in (0, 2), (name, err)
        assert "Traceback" not in err and "internal error" not in err, (name, err)
        # the rerun first says what it resumes (`walker: resuming OUT: k of N chunks kept`)
        err = "".join(line for line in err.splitlines(True) if "walker: resuming " not in line)
        if code == 2:
            assert err.count("\n") == 1, (name, err)
        else:
            got = read(work)
            assert_same(got[0], reference[0])
        work.unlink(missing_ok=True)
