"""The documentation in docs/ and the README: its examples load and run, its tables match the
code, and it points only inside the repository."""

import dataclasses
import re
from pathlib import Path

import pytest

from walker import scene as scene_module
from walker.cli import main
from walker.models import MODEL_NAMES, get_model
from walker.scene import ComputeSettings, load_scene

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"
SCENES = (DOCS / "scenes.md").read_text(encoding="utf-8")
CONVENTIONS = (DOCS / "conventions.md").read_text(encoding="utf-8")
README = (ROOT / "README.md").read_text(encoding="utf-8")


def _blocks(text: str, language: str) -> list[str]:
    return re.findall(rf"^```{language}\n(.*?)^```$", text, flags=re.MULTILINE | re.DOTALL)


TOML_BLOCKS = _blocks(SCENES, "toml")


def _scene_file(tmp_path, text: str) -> Path:
    path = tmp_path / "example.toml"
    path.write_text(text, encoding="utf-8")
    return path


def test_scenes_md_has_one_example_per_model(tmp_path):
    models = [load_scene(_scene_file(tmp_path, block)).model for block in TOML_BLOCKS]
    assert sorted(models) == sorted(MODEL_NAMES)


@pytest.mark.parametrize("block", TOML_BLOCKS, ids=lambda b: re.search(r'model = "(\w+)"', b)[1])
def test_scenes_md_example_loads_and_runs(tmp_path, capsys, block):
    path = _scene_file(tmp_path, block)
    scene = load_scene(path)
    command = "find" if scene.compute.task == "fixed_point" else "run"
    code = main([command, str(path)])
    out, err = capsys.readouterr()
    assert code == 0, (out, err)
    assert "COMPLETED" in out


def _table_rows(text: str, heading: str) -> dict[str, list[str]]:
    """The rows of the first table under ``heading``: key -> its cells."""
    section = text.split(heading, 1)[1].split("\n## ", 1)[0]
    rows = {}
    for line in section.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        match = re.fullmatch(r"`(\w+)`", cells[0]) if line.startswith("|") else None
        if match:
            rows[match[1]] = cells
    return rows


def test_scenes_md_documents_every_table_and_key():
    for table in scene_module._TABLES:
        assert f"## `[{table}]`" in SCENES, table
    expected = {
        "## `[scene]`": scene_module._SCENE_KEYS,
        "## `[model]`": ("swing_scuff",),
        "## `[parameters]`": ("preset",),
        "## `[initial]`": scene_module._INITIAL_KEYS,
        "## `[compute]`": tuple(f.name for f in dataclasses.fields(ComputeSettings)),
        "## `[reference]`": scene_module._REFERENCE_KEYS,
        "## `[terrain]`": ("kind", "slopes", "heights", "slope_mean", "slope_std", "height_std"),
    }
    for heading, keys in expected.items():
        rows = _table_rows(SCENES, heading)
        assert set(keys) <= set(rows), (heading, set(keys) - set(rows))
        for key in keys:
            assert len(rows[key]) == 5 and all(rows[key][i] for i in (1, 3, 4)), rows[key]


def test_scenes_md_compute_defaults_are_the_code_s():
    rows = _table_rows(SCENES, "## `[compute]`")
    for f in dataclasses.fields(ComputeSettings):
        default = rows[f.name][3]
        if f.default is None:
            assert "chosen by the integrator" in default
        elif isinstance(f.default, str):
            assert default.startswith(f'`"{f.default}"`'), (f.name, default)
        else:
            assert default.startswith(f"`{f.default!r}`"), (f.name, default)
    for method in scene_module.METHODS:
        assert f'`"{method}"`' in rows["method"][4]
    for task in scene_module.TASKS:
        assert f'`"{task}"`' in rows["task"][4]


def _row_of(section: str, model: str) -> str:
    """The table row of ``section`` whose first cell names ``model``."""
    return next(
        line
        for line in section.splitlines()
        if line.startswith("|") and f"`{model}`" in line.split("|")[1]
    )


def test_conventions_md_lists_every_section_coordinate_with_its_index():
    section = CONVENTIONS.split("## Section coordinates", 1)[1].split("\n## ", 1)[0]
    for name in MODEL_NAMES:
        row = _row_of(section, name)
        names = get_model(name).section_names
        if names:
            listed = ", ".join(f"{i} `{n}`" for i, n in enumerate(names))
            assert f"| {listed} |" in row, (name, row)
        else:
            assert "none" in row


def test_conventions_md_gives_every_state_in_order():
    section = CONVENTIONS.split("## State vectors", 1)[1].split("\n## ", 1)[0]
    for name in MODEL_NAMES:
        listed = ", ".join(f"`{n}`" for n in get_model(name).state_names)
        assert f"| {listed} |" in _row_of(section, name), name


@pytest.mark.parametrize("doc", ["scenes.md", "conventions.md", "architecture.md"])
def test_docs_point_only_inside_the_repository(doc):
    text = (DOCS / doc).read_text(encoding="utf-8")
    assert "../" not in text and "http" not in text and "/work" not in text
    assert "the course" not in text
    for target in re.findall(r"\]\(([^)]+)\)", text):
        assert (DOCS / target).is_file(), target


def test_readme_keeps_its_first_two_commands():
    blocks = _blocks(README, "bash")
    assert (
        blocks[0] == "python -m pip install -e '.[test,dask]' && walker find gaits/kneed_hsu.toml\n"
    )
    assert blocks[1] == 'python -m pytest -q -m "not slow" -n auto\n'


def test_readme_finding_your_way_lists_the_commands_and_docs():
    section = README.split("## Finding your way", 1)[1].split("\n## ", 1)[0]
    for command in ("walker models", "walker params", "walker scene new"):
        assert command in section
    for doc in ("docs/scenes.md", "docs/conventions.md", "docs/storage.md"):
        assert doc in section and (ROOT / doc).is_file()


def test_architecture_md_names_only_paths_that_exist():
    """docs/architecture.md tells a contributor where each change goes: every repository path
    it names (``walker/...``, ``scripts/...``, ``tests/...``, ``gaits/...``, ``docs/...``)
    exists."""
    text = (DOCS / "architecture.md").read_text(encoding="utf-8")
    root = DOCS.parent
    named = set(re.findall(r"`((?:walker|scripts|tests|gaits|docs)/[^`*<> ]*)`", text))
    assert len(named) > 20
    for path in sorted(named):
        assert (root / path.rstrip("/")).exists(), path


def test_storage_md_codes_and_h5py_example(tmp_path, monkeypatch):
    """docs/storage.md lists every status value, and its h5py-only reading example runs on
    a sweep file walker wrote."""
    from walker.cli.sweep import run_sweep_command
    from walker.status import Status

    text = (DOCS / "storage.md").read_text(encoding="utf-8")
    for status in Status:
        assert f"| {int(status)} | `{status.name}` |" in text, status
    section = text.split("**Reading without walker**", 1)[1]
    code = section.split("```python\n", 1)[1].split("```", 1)[0]
    run_sweep_command(
        ROOT / "gaits/compass_goswami.toml",
        ["slope=0.04:0.05:2"],
        kind="outcome",
        jobs=1,
        scheduler=None,
        out=tmp_path / "sweep.h5",
        quiet=True,
        strides=1,
    )
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    exec(compile(code, "storage.md", "exec"), namespace)  # noqa: S102 - the doc's own example
    assert namespace["names"] == ["slope"]
    assert namespace["points"].shape == (2, 1)
    assert namespace["status"].tolist() == [0, 0]
