"""Half floats from float32 values: numpy's rounding, bit for bit."""

from __future__ import annotations

import numpy as np

from paintapp.canvas.half_floats import half_bits


def test_half_float_bits_are_numpys_rounding_everywhere():
    def convert(values, out):
        half_bits(np.ascontiguousarray(values, np.float32).view(np.uint32), out)

    rng = np.random.default_rng(3)
    edges = [0.0, -0.0, 1.0, 1 / 3, 65504.0, 65519.99, 65520.0, 1e9, np.inf, -np.inf]
    edges += [2.0**-24, 2.0**-25, 1.5 * 2.0**-25, 2.0**-14, 2.0**-14 * (1 - 2.0**-11)]
    patterns = rng.integers(0, 2**32, 200_000, dtype=np.uint64).astype(np.uint32)
    with np.errstate(over="ignore"):
        floats = [np.array(edges), rng.uniform(0, 1, 100_000), 10 ** rng.uniform(-12, 6, 100_000)]
        values = np.concatenate(
            [*(a.astype(np.float32) for a in floats), patterns.view(np.float32)]
        )
    values = values[~np.isnan(values)]
    out = np.empty(values.size, np.uint16)
    convert(values, out)
    with np.errstate(over="ignore", invalid="ignore"):
        expected = values.astype(np.float16).view(np.uint16)
    assert np.array_equal(out, expected)
    nan = np.empty(1, np.uint16)
    convert(np.array([np.nan], np.float32), nan)
    assert np.isnan(nan.view(np.float16)[0])
