"""fire_bench.height_tracking: bad arguments give a one-line error naming the argument."""

import pytest
from fire_bench.height_tracking import main


def test_no_uavs_is_refused():
    with pytest.raises(SystemExit, match="--uavs must be >= 1, got 0"):
        main(["--uavs", "0"])


def test_non_positive_duration_is_refused():
    with pytest.raises(SystemExit, match="--duration must be > 0, got -5.0"):
        main(["--duration", "-5"])
