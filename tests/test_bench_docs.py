"""docs/benchmarks.md is generated: the committed page is the render of the committed results and
notes, and a benchmark run changes the committed docs only when told to (``--update-docs``)."""

from __future__ import annotations

import json
import shutil
import subprocess
from pathlib import Path

import pytest
from fire_bench import bench, markdown
from fire_bench.markdown import render

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"


def test_committed_page_is_the_render_byte_for_byte() -> None:
    results = json.loads((DOCS / "bench/results.json").read_text())
    page = render(results, DOCS / "bench/notes", plot_dir=DOCS / "bench")
    committed = (DOCS / "benchmarks.md").read_text()
    if page != committed:
        diff = [
            f"line {i + 1}: page {a!r} / render {b!r}"
            for i, (a, b) in enumerate(zip(committed.splitlines(), page.splitlines(), strict=False))
            if a != b
        ]
        pytest.fail(
            "docs/benchmarks.md is not the render of docs/bench/results.json and docs/bench/notes "
            f"(run scripts/bench --render; edit the notes, not the page): {diff[:3]}"
        )


def test_every_note_is_on_the_page() -> None:
    """A notes file whose name is no section would be left out silently."""
    sections = {"intro"} | set(bench.BENCHES)
    for f in (DOCS / "bench/notes").glob("*.md"):
        assert f.name.removesuffix(".md").removesuffix(".before") in sections, f


@pytest.fixture
def docs(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    """A copy of the committed docs (results, notes, plots, page) for the run to touch."""
    d = tmp_path / "docs"
    shutil.copytree(DOCS / "bench", d / "bench")
    shutil.copyfile(DOCS / "benchmarks.md", d / "benchmarks.md")
    monkeypatch.setattr(markdown, "DOCS", d)
    monkeypatch.setattr(markdown, "RUNS", tmp_path / "runs")
    monkeypatch.setitem(bench.BENCHES, "dummy", (lambda quick: {"figure": 3.5}, 0.1, 0.1, "a stand-in"))
    return d


def _snapshot(d: Path) -> dict[str, bytes]:
    return {str(p.relative_to(d)): p.read_bytes() for p in sorted(d.rglob("*")) if p.is_file()}


def test_a_run_writes_a_run_folder_and_leaves_the_docs_alone(docs: Path, tmp_path: Path) -> None:
    before = _snapshot(docs)
    assert bench.main(["--quick", "--only", "dummy"]) == 0
    assert _snapshot(docs) == before
    (run,) = (tmp_path / "runs").iterdir()
    assert run.name.startswith("bench-")
    got = json.loads((run / "results.json").read_text())
    assert got["dummy"]["figure"] == 3.5 and got["dummy"]["command"] == "scripts/bench --quick --only dummy"
    assert "## " not in (run / "benchmarks.md").read_text().split("Machine:")[1]  # no committed notes


def test_out_writes_there_and_leaves_the_docs_alone(docs: Path, tmp_path: Path) -> None:
    before = _snapshot(docs)
    assert bench.main(["--only", "dummy", "--out", str(tmp_path / "mine")]) == 0
    assert _snapshot(docs) == before
    assert json.loads((tmp_path / "mine/results.json").read_text())["dummy"]["figure"] == 3.5
    assert not (tmp_path / "runs").exists()


def test_update_docs_replaces_only_the_sections_run_and_renders(docs: Path) -> None:
    old = json.loads((docs / "bench/results.json").read_text())
    assert bench.main(["--only", "dummy", "--update-docs"]) == 0
    new = json.loads((docs / "bench/results.json").read_text())
    assert new.pop("dummy")["figure"] == 3.5
    assert new == old  # every committed section kept as it was
    assert (docs / "benchmarks.md").read_text() == render(
        json.loads((docs / "bench/results.json").read_text()), docs / "bench/notes", plot_dir=docs / "bench"
    )


def test_update_docs_with_out_is_refused(docs: Path, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as e:
        bench.main(["--only", "dummy", "--update-docs", "--out", "/tmp/x"])
    assert e.value.code == 2
    assert (
        capsys.readouterr()
        .err.strip()
        .splitlines()[-1]
        .startswith("bench: error: --update-docs writes into docs/bench; leave out --out")
    )


def test_render_rewrites_the_page_from_results_and_notes(docs: Path) -> None:
    committed = (docs / "benchmarks.md").read_text()
    (docs / "benchmarks.md").write_text(committed.replace("## Crashes and packet loss", "## edited by hand"))
    (docs / "bench/notes/faults.md").write_text("A note on the faults.\n")
    assert bench.main(["--render"]) == 0
    page = (docs / "benchmarks.md").read_text()
    assert "edited by hand" not in page
    assert "## Crashes and packet loss" in page
    faults = page.split("## Crashes and packet loss")[1].split("\n## ")[0]
    assert faults.rstrip().endswith("A note on the faults.")


def test_the_time_estimate_comes_from_measured_runs() -> None:
    measured = {"world": {"quick": True, "wall_s": 120.0}, "ekf": {"quick": False, "wall_s": 600.0}}
    est, guessed = bench.estimate_minutes(["world", "ekf"], True, measured)
    assert est == pytest.approx(2.0 + bench.BENCHES["ekf"][1])  # ekf's measurement was a full run
    assert guessed == ["ekf"]


def test_the_recorded_command_keeps_the_sweeps_executor() -> None:
    a = bench.argparse.Namespace(quick=False, scale_sizes=None, scale_duration=None, scheduler=None, jobs=2)
    assert bench.run_command(a, "ff_known", sweep=True) == "scripts/bench --only ff_known --jobs 2"
    assert bench.run_command(a, "ekf", sweep=False) == "scripts/bench --only ekf"


def test_suppression_from_runs_goes_to_a_run_folder(docs: Path, tmp_path: Path) -> None:
    from fire_bench.suppression import main

    runs = tmp_path / "suppression_runs.jsonl"
    run = {
        "scenario": "grass_brush_hill",
        "uavs": 0,
        "seed": 1,
        "tactic": "none",
        "duration_s": 900.0,
        "burned_area_m2": 235600.0,
        "hit_rate": None,
        "drops": 0,
        "water_on_burning_kg": 0.0,
        "contained_at_s": None,
        "crashes": 0,
        "area_t_s": [0.0, 900.0],
        "area_m2": [1.0, 235600.0],
        "wall_s": 1.0,
    }
    runs.write_text(json.dumps(run) + "\n")
    before = _snapshot(docs)
    assert main(["--from-runs", str(runs)]) == 0
    assert _snapshot(docs) == before
    (out,) = (tmp_path / "runs").iterdir()
    assert out.name.startswith("suppression-") and (out / "suppression.json").is_file()
    assert main(["--from-runs", str(runs), "--out", str(tmp_path / "s"), "--update-docs"]) == 0
    got = json.loads((docs / "bench/results.json").read_text())["suppression"]
    assert got["scenarios"]["grass_brush_hill"]["baseline_burned_area_m2"] == 235600.0
    assert "| 0 | 53.16 |" not in (docs / "benchmarks.md").read_text()  # the new summary, rendered


@pytest.mark.slow
def test_a_quick_benchmark_leaves_git_status_clean(tmp_path: Path) -> None:
    """scripts/bench --quick as a user runs it (the cheapest sub-benchmark: the world's step cost)."""

    def status() -> str:
        return subprocess.run(
            ["git", "status", "--porcelain", "--untracked-files=all"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
        ).stdout

    before = status()
    r = subprocess.run(
        [str(ROOT / "scripts/bench"), "--quick", "--only", "world"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=600,
        check=False,
    )
    assert r.returncode == 0, r.stderr[-2000:]
    assert status() == before
    page = Path(r.stderr.split("page: ")[-1].split()[0])
    assert page.parent.parent == ROOT / "runs" and page.is_file(), r.stderr[-500:]
    shutil.rmtree(page.parent)
