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


def _limbs_of(x: int):
    import numpy as np

    return [np.array([(x >> (32 * k)) & 0xFFFFFFFF], dtype=np.uint64) for k in range(4)]


def _int_of(limbs) -> int:
    assert all(v.dtype.name == "uint64" and int(v[0]) <= 0xFFFFFFFF for v in limbs)
    return sum(int(v[0]) << (32 * k) for k, v in enumerate(limbs))


def test_mul128_and_add128_are_pythons_exact_integers_mod_2_128():
    """The 32-bit-limb product and sum of rng.uniform_table against Python's exact integers taken
    modulo 2**128, on random numbers and on edge limbs: all ones (every column at its largest
    sum, carries through every limb), zeros in any limb of either operand, single limbs."""
    import itertools
    import random

    from fire_uav_common.rng import _add128, _mul128

    m = 1 << 128
    ones = 0xFFFFFFFF
    edges = [0, 1, m - 1, 1 << 32, 1 << 64, 1 << 96, ones, ones << 96, (ones << 64) | ones]
    edges += [
        sum(v << (32 * k) for k, v in enumerate(pat)) for pat in itertools.product((0, ones, 7), repeat=4)
    ]
    r = random.Random(128)
    rand = [r.getrandbits(128) for _ in range(60)] + [
        r.getrandbits(32) << (32 * r.randrange(4)) for _ in range(20)
    ]
    for a, c in itertools.chain(
        itertools.product(edges[:9], edges),
        ((r.choice(edges + rand), r.choice(edges + rand)) for _ in range(400)),
    ):
        c_limbs = tuple(int(v[0]) for v in _limbs_of(c))
        assert _int_of(_mul128(_limbs_of(a), c_limbs)) == (a * c) % m, (hex(a), hex(c))
        assert _int_of(_add128(_limbs_of(a), _limbs_of(c))) == (a + c) % m, (hex(a), hex(c))


def test_mul128_works_on_whole_arrays_and_keeps_their_shape():
    """Limbs are arrays of any shape (uniform_table's are steps x senders): each entry's product
    is its own, the same as Python's integers."""
    import random

    import numpy as np
    from fire_uav_common.rng import _add128, _mul128

    r = random.Random(3)
    xs = [[r.getrandbits(128) for _ in range(5)] for _ in range(3)]
    ys = [[r.getrandbits(128) for _ in range(5)] for _ in range(3)]
    c = r.getrandbits(128)

    def limbs(rows):
        return [
            np.array([[(x >> (32 * k)) & 0xFFFFFFFF for x in row] for row in rows], dtype=np.uint64)
            for k in range(4)
        ]

    prod = _mul128(limbs(xs), tuple((c >> (32 * k)) & 0xFFFFFFFF for k in range(4)))
    tot = _add128(limbs(xs), limbs(ys))
    for i in range(3):
        for j in range(5):
            assert sum(int(prod[k][i, j]) << (32 * k) for k in range(4)) == xs[i][j] * c % (1 << 128)
            assert sum(int(tot[k][i, j]) << (32 * k) for k in range(4)) == (xs[i][j] + ys[i][j]) % (1 << 128)
            assert all(v.shape == (3, 5) for v in prod + tot)


def test_limbs_split_128_bit_numbers_least_significant_first():
    """rng._limbs against Python's integers, and the two limb constants of uniform_table against
    numpy's PCG64 multiplier (pcg64.h, PCG_DEFAULT_MULTIPLIER_128): M^2 and M + 1 mod 2**128."""
    import random

    from fire_uav_common.rng import _M1_LIMBS, _M2_LIMBS, _limbs

    r = random.Random(32)
    for x in [0, 1, (1 << 128) - 1, 0xFFFFFFFF, 1 << 32, 1 << 64, 1 << 96] + [
        r.getrandbits(128) for _ in range(50)
    ]:
        got = _limbs(x)
        assert len(got) == 4 and all(0 <= v <= 0xFFFFFFFF for v in got)
        assert sum(v << (32 * k) for k, v in enumerate(got)) == x
    mult = 0x2360ED051FC65DA44385DF649FCCF645
    for limbs, want in [(_M2_LIMBS, mult * mult % (1 << 128)), (_M1_LIMBS, mult + 1)]:
        assert sum(v << (32 * k) for k, v in enumerate(limbs)) == want


def test_uniform_table_refuses_each_word_numpy_would_not_take_as_one():
    """Every word position on its own: a negative word (numpy's SeedSequence refuses it) and a word
    of 2**32 or more (numpy splits it into two words, so no 32-bit arithmetic gives its draw)
    raise ArgumentError with the docstring's reason; an empty range holds no word at all, so
    its bounds are not checked and the table is empty along it."""
    import numpy as np
    from fire_uav_common.errors import ArgumentError
    from fire_uav_common.rng import uniform_table

    with pytest.raises(ValueError, match="non-negative"):
        np.random.SeedSequence([1, -1])
    big = 2**32
    ok = dict(seed=1, purpose="loss", firsts=range(3), second=0, thirds=range(2), fourth=0)
    for name, neg, over in [
        ("seed", -1, big),
        ("second", -1, big),
        ("fourth", -1, big),
        ("firsts", range(-1, 2), range(big - 1, big + 1)),
        ("thirds", range(-2, 1), range(big - 2, big + 1)),
    ]:
        with pytest.raises(ArgumentError, match=r"^seed and ids must be >= 0, got seed="):
            uniform_table(**{**ok, name: neg})
        with pytest.raises(ArgumentError, match=r"^uniform_table: every word must fit in 32 bits$"):
            uniform_table(**{**ok, name: over})
    with pytest.raises(ArgumentError, match=r"^uniform_table takes ranges of step 1$"):
        uniform_table(**{**ok, "thirds": range(0, 6, 3)})
    assert uniform_table(**{**ok, "firsts": range(big + 5, big + 5)}).shape == (2, 0)
    assert uniform_table(**{**ok, "thirds": range(big + 5, big + 5)}).shape == (0, 3)


def test_uniform_takes_a_numpy_integer_step_as_numpy_does():
    """stream() takes numpy integer ids as SeedSequence does; uniform()'s plain-integer port
    mixed an np.int64 past the head into its 32-bit words and raised OverflowError (session 25,
    every step 0-399 of this case) instead of returning stream()'s first draw. A float is refused
    by both."""
    import numpy as np
    from fire_uav_common.rng import stream, uniform

    for k in range(20):
        assert uniform(5, "loss", 0, 1, np.int64(k), 0) == stream(5, "loss", 0, 1, k, 0).random()
        assert (
            uniform(np.int64(5), "loss", np.uint32(0), 1, k, np.int32(0))
            == stream(5, "loss", 0, 1, k, 0).random()
        )
    with pytest.raises(TypeError):
        uniform(5, "loss", 0, 1, 2.0, 0)
    with pytest.raises(TypeError):
        np.random.SeedSequence([5, 0, 1, 2.0])
