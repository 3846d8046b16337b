"""fire_bench.envelope: the share of airborne truth beyond a bank limit, against the
coordinated-turn relation omega = g tan(phi) / v (Beard & McLain Eq. 9.14)."""

from __future__ import annotations

import math

import pytest
from fire_bench.envelope import envelope_share, needed_bank_deg
from fire_bench.errors import BenchError
from fire_uav_common.constants import VehicleStatus
from fire_uav_common.scenario.airframes import G_MPS2

AIR, GROUND = int(VehicleStatus.AIRBORNE), int(VehicleStatus.ON_GROUND)


def test_a_sample_just_inside_and_just_beyond_the_bank_limit() -> None:
    v = 20.0
    at_60 = G_MPS2 * math.tan(math.radians(60)) / v
    e = envelope_share([(AIR, v, 0.999 * at_60), (AIR, v, -1.001 * at_60), (GROUND, 0.0, 99.0)], 60.0)
    assert (e.airborne, e.beyond) == (2, 1) and e.share == 0.5
    assert e.max_bank_deg == pytest.approx(60.0, abs=0.05)


def test_ff_limits_need_a_bank_near_ninety_degrees() -> None:
    # FF: 10 rad/s at 44.7 m/s is a 4.5 m radius, about 46 g
    assert needed_bank_deg(44.7, 10.0) == pytest.approx(math.degrees(math.atan(447 / G_MPS2)))
    assert needed_bank_deg(44.7, 10.0) > 88.0


def test_no_airborne_sample_is_no_share_and_a_bad_limit_is_refused() -> None:
    assert envelope_share([(GROUND, 0.0, 0.0)], 45.0).share == 0.0
    with pytest.raises(BenchError, match="bank_max_deg"):
        envelope_share([], 90.0)


def _script():
    """scripts/envelope_share.py as a module (a script, not a package)."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).resolve().parents[1] / "scripts" / "envelope_share.py"
    spec = importlib.util.spec_from_file_location("envelope_share_script", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_the_raster_line_gives_the_burned_area_in_hectares_and_the_containment() -> None:
    line = _script().raster_line
    s = {"burned_area_m2": 31_900.0, "contained_at_s": 257.04, "mission_time_s": 316.4, "refills": 35}
    assert line(s, "flank") == (
        "raster fire, tactic flank: burned area 3.19 ha at 316.4 s, contained at 257.0 s, refills 35"
    )
    s.update(contained_at_s=None, burned_area_m2=None)
    assert "burned area n/a at 316.4 s, not contained" in line(s, "head")
