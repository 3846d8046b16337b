"""rng.bernoulli: the loss draw depends only on its arguments and has the asked-for rate."""

from __future__ import annotations

import math

import pytest
from fire_uav_common.rng import bernoulli


def test_rate_is_p_within_binomial_bounds():
    n = 20000
    for p in (0.05, 0.2, 0.5):
        hits = sum(bernoulli(p, 7, "loss", j % 5, 1, j // 5, 0) for j in range(n))
        sd = math.sqrt(n * p * (1 - p))
        assert abs(hits - n * p) < 5 * sd, (p, hits)


def test_same_arguments_same_draw_in_any_order():
    args = [(3, "loss", j, i, s, t) for j in range(3) for i in range(3) for s in range(50) for t in range(3)]
    first = [bernoulli(0.3, *a) for a in args]
    again = [bernoulli(0.3, *a) for a in reversed(args)][::-1]
    assert first == again


def test_draws_differ_between_seeds_and_purposes():
    a = [bernoulli(0.5, 1, "loss", 0, 1, s, 0) for s in range(400)]
    b = [bernoulli(0.5, 2, "loss", 0, 1, s, 0) for s in range(400)]
    c = [bernoulli(0.5, 1, "other", 0, 1, s, 0) for s in range(400)]
    assert a != b and a != c
    assert 0.4 < sum(x == y for x, y in zip(a, b, strict=True)) / 400 < 0.6  # independent: ~half agree


def test_edges_and_errors():
    assert not any(bernoulli(0.0, 1, "loss", 0, 1, s, 0) for s in range(100))
    assert all(bernoulli(1.0, 1, "loss", 0, 1, s, 0) for s in range(100))
    with pytest.raises(ValueError, match=r"probability must be in \[0, 1\], got 1.5"):
        bernoulli(1.5, 1, "loss", 0)
    with pytest.raises(ValueError, match="seed and ids must be >= 0"):
        bernoulli(0.5, 1, "loss", -1)


def test_uniform_is_numpys_first_draw_bit_for_bit():
    """rng.uniform re-implements SeedSequence + PCG64 in integers: numpy is the reference.

    Word lists of 0 to 9 ids (fewer than the pool's 4 words, exactly 4, more), with 0, 1,
    2**32 - 1 and ids above 32 bits (the fallback), in every position.
    """
    import random

    import numpy as np
    from fire_uav_common.rng import _key, stream, uniform

    r = random.Random(20261203)
    pick = [
        lambda: 0,
        lambda: 1,
        lambda: 2**32 - 1,
        lambda: r.randint(0, 2**32 - 1),
        lambda: r.randint(0, 200),
    ]
    for n in range(3000):
        seed = r.choice(pick)()
        ids = [r.choice(pick)() for _ in range(r.randint(0, 9))]
        if n % 100 == 0:
            ids.append(2**40 + n)  # split into two words by SeedSequence: the numpy path
        purpose = r.choice(["loss", "gps", "x" * (n % 7)])
        ref = np.random.default_rng(np.random.SeedSequence([seed, _key(purpose), *ids])).random()
        assert uniform(seed, purpose, *ids) == ref == stream(seed, purpose, *ids).random(), (
            seed,
            purpose,
            ids,
        )


def test_bernoulli_is_the_first_draw_of_the_stream_below_p():
    from fire_uav_common.rng import stream

    for s in range(300):
        for p in (0.1, 0.5, 0.93):
            assert bernoulli(p, 11, "loss", s % 7, 3, s, s % 2) == (
                stream(11, "loss", s % 7, 3, s, s % 2).random() < p
            )


def test_a_draw_equal_to_p_is_not_a_loss_and_stream_checks_its_ids():
    """P(u < p) = p for u uniform on [0, 1): a draw exactly p is kept, as numpy's own test reads."""
    from fire_uav_common.rng import stream, uniform

    u = uniform(5, "loss", 1, 2, 3, 0)
    assert not bernoulli(u, 5, "loss", 1, 2, 3, 0)
    assert bernoulli(math.nextafter(u, 1.0), 5, "loss", 1, 2, 3, 0)
    for bad in ((-1, "loss", 0), (1, "loss", 0, -2)):
        with pytest.raises(ValueError, match=r"^seed and ids must be >= 0, got seed="):
            stream(*bad)
        with pytest.raises(ValueError, match=r"^seed and ids must be >= 0, got seed="):
            uniform(*bad)


def test_the_tabled_hash_constants_are_numpys_at_every_position():
    """The tables replace SeedSequence's running hash constant: it is the same whatever the words
    (checked after the pool's first phases for random heads), and word lists around and beyond
    the tables' 16 extra words (the loop that carries the constant on) still match numpy."""
    import random

    import numpy as np
    from fire_uav_common.rng import _HA, _TAIL_WORDS, _first_double, _pool_head

    r = random.Random(7)
    for _ in range(200):
        head = tuple(r.randint(0, 2**32 - 1) for _ in range(r.randint(0, 4)))
        assert _pool_head(head)[1] == _HA[16]
    for n in [4 + _TAIL_WORDS - 1, 4 + _TAIL_WORDS, 4 + _TAIL_WORDS + 1, 4 + _TAIL_WORDS + 7]:
        for _ in range(20):
            words = [r.randint(0, 2**32 - 1) for _ in range(n)]
            assert _first_double(words) == np.random.default_rng(np.random.SeedSequence(words)).random(), n


def test_tables_built_afresh_give_numpys_draws(monkeypatch):
    """The tables are built at import; this builds them again through ``_h_table`` and draws
    with those: the same floats as numpy's SeedSequence + PCG64 (so a wrong table fails here
    even where the import-time tables are the right ones)."""
    import random

    import numpy as np
    from fire_uav_common import rng

    fresh_a = rng._h_table(rng._INIT_A, rng._MULT_A, 16 + 4 * rng._TAIL_WORDS)
    fresh_b = rng._h_table(rng._INIT_B, rng._MULT_B, 8)
    assert len(fresh_a) == 17 + 4 * rng._TAIL_WORDS and len(fresh_b) == 9
    monkeypatch.setattr(rng, "_HA", fresh_a)
    monkeypatch.setattr(rng, "_HB", fresh_b)
    r = random.Random(11)
    for n in [1, 4, 5, 6, 9, 20, 23]:
        for _ in range(10):
            words = [r.randint(0, 2**32 - 1) for _ in range(n)]
            assert rng._first_double(words) == np.random.default_rng(np.random.SeedSequence(words)).random()


def test_uniform_table_is_numpys_first_draw_bit_for_bit():
    """rng.uniform_table (numpy uint64 arithmetic, 128-bit PCG64 state on 32-bit limbs) against
    numpy's own SeedSequence + PCG64 for every entry: seeds, receivers, steps and topics at 0, 1,
    2**32 - 1 and random 32-bit values, tables at the top of the 32-bit range, empty ones."""
    import random

    import numpy as np
    from fire_uav_common.rng import _key, uniform_table

    r = random.Random(20261207)
    edge = [0, 1, 2**32 - 1]
    for n in range(60):
        seed = r.choice([*edge, r.randint(0, 2**32 - 1), r.randint(0, 50)])
        second = r.choice([*edge, r.randint(0, 2**32 - 1), r.randint(0, 30)])
        fourth = r.choice([*edge, r.randint(0, 2**32 - 1), r.randint(0, 6)])
        a0 = r.choice([0, r.randint(0, 2**32 - 1 - 40), 2**32 - 40])
        firsts = range(a0, a0 + r.randint(0, 40) * (n % 10 != 0))
        c0 = r.choice([0, r.randint(0, 2**32 - 1 - 70), 2**32 - 70])
        thirds = range(c0, c0 + r.choice([0, 1, 7, 64, 70]))
        purpose = r.choice(["loss", "gps"])
        got = uniform_table(seed, purpose, firsts, second, thirds, fourth)
        assert got.shape == (len(thirds), len(firsts)) and got.dtype == np.float64
        k = _key(purpose)
        picks = [(i, j) for i in range(len(thirds)) for j in range(len(firsts))]
        for i, j in r.sample(picks, min(len(picks), 40)) + picks[-1:]:
            ss = np.random.SeedSequence([seed, k, firsts[j], second, thirds[i], fourth])
            want = np.random.default_rng(ss).random()
            assert got[i, j] == want, (seed, purpose, firsts[j], second, thirds[i], fourth)


def test_uniform_table_refuses_what_it_cannot_draw():
    from fire_uav_common.errors import ArgumentError
    from fire_uav_common.rng import uniform_table

    for args in [
        (-1, "loss", range(3), 0, range(3), 0),
        (1, "loss", range(3), 2**32, range(3), 0),
        (1, "loss", range(3), 0, range(2**32 - 1, 2**32 + 1), 0),
        (1, "loss", range(0, 6, 2), 0, range(3), 0),
    ]:
        with pytest.raises(ArgumentError):
            uniform_table(*args)
