"""The examples in walker's docstrings run, one test per docstring, in the default suite.

Every module of the package is imported and searched (``doctest.DocTestFinder``), so a new
module's examples run without being listed here.  Examples run from the repository root
(they load ``gaits/...`` by relative path) with ``tempfile`` pointed at a fresh directory:
an example that writes a file must write it under ``tempfile.mkdtemp()`` (or
``gettempdir()``), and one that writes into the repository instead fails here.
"""

import doctest
import importlib
import pkgutil
import tempfile
from pathlib import Path

import pytest

import walker

ROOT = Path(__file__).resolve().parents[1]
FLAGS = doctest.ELLIPSIS  # as pytest's --doctest-modules


def _modules():
    names = ["walker"] + [m.name for m in pkgutil.walk_packages(walker.__path__, "walker.")]
    return [importlib.import_module(name) for name in sorted(names)]


def _docstring_tests():
    finder = doctest.DocTestFinder(exclude_empty=True)
    found = []
    for module in _modules():
        found += [t for t in finder.find(module, module.__name__) if t.examples]
    return sorted(found, key=lambda t: t.name)


DOCTESTS = _docstring_tests()


def test_every_module_with_examples_is_searched():
    """Each source file whose docstrings hold ``>>>`` examples has its examples collected
    (a module that cannot be imported, or whose examples sit where the finder does not look,
    would otherwise drop out silently)."""
    files = {Path(t.filename).resolve() for t in DOCTESTS}
    with_examples = {
        path.resolve()
        for path in Path(walker.__file__).parent.rglob("*.py")
        if "_generated" not in path.parts and ">>> " in path.read_text(encoding="utf-8")
    }
    assert with_examples, "no examples found in walker/"
    assert with_examples <= files, sorted(str(p) for p in with_examples - files)


@pytest.mark.parametrize("test", DOCTESTS, ids=[t.name for t in DOCTESTS])
def test_docstring_examples(test, tmp_path, monkeypatch):
    monkeypatch.chdir(ROOT)
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    before = sorted(p.name for p in ROOT.iterdir())
    report = []
    runner = doctest.DocTestRunner(optionflags=FLAGS)
    try:
        result = runner.run(test, out=report.append, clear_globs=True)
    finally:
        after = sorted(p.name for p in ROOT.iterdir())
    assert result.attempted == len(test.examples)
    assert result.failed == 0, "".join(report)
    assert after == before, f"the examples wrote into {ROOT}: {sorted(set(after) - set(before))}"
