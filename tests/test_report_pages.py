"""The report writes every figure and its page (matplotlib: slow, ~20-50 s under load; kept out of
test_report_metrics.py so that the mutation run of fire_report.metrics does not pay for it)."""

from __future__ import annotations

import pytest
from fire_report import write_report
from fire_report.synthetic import write_synthetic_mission


@pytest.fixture(scope="module")
def synthetic(tmp_path_factory):
    path = tmp_path_factory.mktemp("bags") / "mission"
    spec = write_synthetic_mission(path)
    return path, spec


@pytest.fixture
def label_check(monkeypatch) -> list[str]:
    """Every figure drawn meanwhile is checked before it is saved: no label written on a plot
    (annotation) covers a title or an axis label (a crash label drawn at 90 % of the height once
    ran over the title of the faults figure). Returns the names of the figures checked."""
    from fire_report import figures
    from matplotlib.text import Text

    checked: list[str] = []
    real_save = figures._save

    def save(fig, out, name, caption):
        fig.tight_layout()
        renderer = fig.canvas.get_renderer()
        for ax in fig.axes:
            fixed = [t for t in (ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label)
                     if t.get_text()]  # fmt: skip
            for note in ax.texts:
                if not isinstance(note, Text) or not note.get_visible() or not note.get_text():
                    continue
                nb = note.get_window_extent(renderer)
                for t in fixed:
                    assert not nb.overlaps(t.get_window_extent(renderer)), (
                        f"{name}: '{note.get_text()}' covers '{t.get_text()}'"
                    )
        checked.append(name)
        return real_save(fig, out, name, caption)

    monkeypatch.setattr(figures, "_save", save)
    return checked


def test_report_writes_every_figure_and_page(synthetic, tmp_path, label_check):
    path, _ = synthetic
    metrics = write_report(path, tmp_path / "out")
    assert {"voronoi_phases.png", "faults.png", "drops.png"} <= set(label_check)
    out = tmp_path / "out"
    html = (out / "index.html").read_text()
    assert (out / "metrics.json").is_file()
    names = set(metrics["figures"])
    assert {
        "voronoi_phases.png",
        "ekf_error.png",
        "covariance_trace.png",
        "tracks.png",
        "drops.png",
        "fire_0_estimates.png",
        "fire_1_estimates.png",
        "perimeter.png",
        "faults.png",
    } <= names
    for name in names:
        assert (out / name).stat().st_size > 1000
        assert f'src="{name}"' in html
