#!/usr/bin/env python3
"""Reference powers for crates/supergrain/tests/pow_reference.rs, computed by mpmath at 60
significant digits from the exact binary values of x and e.

    pip install mpmath && python3 scripts/pow-reference.py > crates/supergrain/tests/data/pow-reference.txt

Each line: the bits of x and of e (hexadecimal u64) and x^e to 30 significant digits."""
import random
import struct

import mpmath

mpmath.mp.dps = 60


def bits(v):
    return struct.unpack("<Q", struct.pack("<d", v))[0]


def main():
    rng = random.Random(19)
    cases = []
    # Bases: the scaled coordinates the enclosures see (mostly in (0, 1]), near 1, near the
    # mantissa's sqrt(2) cut, powers of two, and the whole normal range.
    def base():
        r = rng.random()
        if r < 0.4:
            return rng.uniform(0.0, 1.0) or 0.5
        if r < 0.55:
            return 1.0 + rng.uniform(-1e-6, 1e-6) * 10 ** -rng.randint(0, 9)
        if r < 0.65:
            return 2.0 ** rng.randint(-60, 60) * (1.4142135623730951 + rng.uniform(-1e-15, 1e-15))
        if r < 0.7:
            return 2.0 ** rng.randint(-1000, 1000)
        return 10.0 ** rng.uniform(-300, 300)

    # Exponents: shapes' (0.1-400), their 1/e, e - 1 and 1/e - 1 (negative ones among them).
    def exponent():
        e = rng.choice([rng.uniform(0.1, 1.0), rng.uniform(1.0, 8.0), rng.uniform(8.0, 400.0)])
        return rng.choice([e, 1.0 / e, e - 1.0, 1.0 / e - 1.0]) or 0.75

    while len(cases) < 4000:
        x, e = base(), exponent()
        if x <= 0.0:
            continue
        v = mpmath.power(mpmath.mpf(x), mpmath.mpf(e))
        # Only results well inside the normal range: the code under test leaves the others to
        # powf, which another test covers.
        if not (mpmath.mpf(2) ** -1000 < v < mpmath.mpf(2) ** 1000):
            continue
        cases.append((x, e, v))
    for x, e, v in cases:
        print(f"{bits(x):016x} {bits(e):016x} {mpmath.nstr(v, 30, min_fixed=1, max_fixed=0)}")


main()
