"""Known-fires briefing (fire_world_sim.dispatch): noisy, seeded, only in known mode."""

import numpy as np
from fire_uav_common.scenario import load_scenario
from fire_world_sim.dispatch import prior_fire_estimates

from .conftest import SCENARIOS


def _ff(_unused=None, **ov):
    return load_scenario(SCENARIOS / "ff_two_fires.yaml", overrides=ov)


def test_unknown_mode_briefs_nothing_and_known_mode_briefs_every_fire():
    assert prior_fire_estimates(_ff()) == []
    b = prior_fire_estimates(_ff(**{"mission.prior_fires": "known"}), seed=1)
    assert len(b) == 2
    assert b == prior_fire_estimates(_ff(**{"mission.prior_fires": "known"}), seed=1)
    assert b != prior_fire_estimates(_ff(**{"mission.prior_fires": "known"}), seed=2)


def test_the_briefing_noise_has_the_configured_spread():
    sc = _ff(**{"mission.prior_fires": "known", "mission.prior_position_sigma_m": 10.0})
    err = np.array([np.subtract(prior_fire_estimates(sc, seed=s)[0][:2], (300.0, 400.0)) for s in range(400)])
    assert abs(err.std() - 10.0) < 1.0 and np.all(np.abs(err.mean(axis=0)) < 1.5)
    ext = np.array([prior_fire_estimates(sc, seed=s)[0][2] for s in range(400)])
    assert np.all((ext >= 25.0) & (ext <= 75.0)) and abs(ext.mean() - 50.0) < 2.0
