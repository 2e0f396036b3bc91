"""IEEE half floats from float32 values, as numpy's ``astype(np.float16)`` rounds them.

:func:`half_of` gives the half nearest a float32 (ties to even), both as their bits: subnormals,
infinities and NaN included; a kernel that writes half floats calls it per value instead of
building a float32 temporary for numpy to convert. :func:`half_bits` is the array form.
"""

from __future__ import annotations

import numpy as np

from solver import inline_kernel, kernel


@inline_kernel
def half_of(x):
    """The bits (uint16) of the half float nearest the float32 whose bits (uint32) are ``x``."""
    sign = (x >> np.uint32(16)) & np.uint32(0x8000)
    exponent = np.int64((x >> np.uint32(23)) & np.uint32(0xFF))
    mantissa = x & np.uint32(0x7FFFFF)
    if exponent == 0xFF:  # infinity or NaN (kept a NaN)
        nan = np.uint32(0x200) if mantissa != 0 else np.uint32(0)
        return np.uint16(sign | np.uint32(0x7C00) | nan)
    e = exponent - 127 + 15
    if e >= 31:  # too large: infinity
        return np.uint16(sign | np.uint32(0x7C00))
    if e <= 0:  # a half subnormal, or zero
        if e < -10:
            return np.uint16(sign)
        mantissa |= np.uint32(0x800000)
        shift = np.uint32(14 - e)
        half = mantissa >> shift
        rest = mantissa & ((np.uint32(1) << shift) - np.uint32(1))
        tie = np.uint32(1) << (shift - np.uint32(1))
        if rest > tie or (rest == tie and (half & np.uint32(1)) != 0):
            half += np.uint32(1)
        return np.uint16(sign | half)
    half = sign | (np.uint32(e) << np.uint32(10)) | (mantissa >> np.uint32(13))
    rest = mantissa & np.uint32(0x1FFF)
    if rest > np.uint32(0x1000) or (rest == np.uint32(0x1000) and (half & np.uint32(1)) != 0):
        half += np.uint32(1)  # a carry into the exponent rounds up to the next binade
    return np.uint16(half)


@kernel
def half_bits(bits: np.ndarray, out: np.ndarray) -> None:
    """:func:`half_of` of every value: ``bits`` (uint32, float32 bits) into ``out`` (uint16),
    both 1D."""
    for i in range(bits.size):
        out[i] = half_of(bits[i])
