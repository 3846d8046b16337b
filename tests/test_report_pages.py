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


def test_report_writes_every_figure_and_page(synthetic, tmp_path):
    path, _ = synthetic
    metrics = write_report(path, tmp_path / "out")
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
