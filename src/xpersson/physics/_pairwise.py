"""numpy's pairwise summation order as a plain loop (private): shared by the compiled kernels of
:mod:`._compiled` and :mod:`._spline_sums` (compiled with them; plain Python without numba)."""

from __future__ import annotations

from typing import Any


def _pairwise(a: Any, n: int) -> float:
    """``a[:n].sum()`` in numpy's order for a contiguous axis of ``n <= PAIRWISE`` elements
    (8 accumulators): bit for bit ``np.sum``."""
    if n < 8:
        r = 0.0
        for i in range(n):
            r += a[i]
        return r
    r0, r1, r2, r3, r4, r5, r6, r7 = a[0], a[1], a[2], a[3], a[4], a[5], a[6], a[7]
    i = 8
    while i < n - n % 8:
        r0 += a[i]
        r1 += a[i + 1]
        r2 += a[i + 2]
        r3 += a[i + 3]
        r4 += a[i + 4]
        r5 += a[i + 5]
        r6 += a[i + 6]
        r7 += a[i + 7]
        i += 8
    res = ((r0 + r1) + (r2 + r3)) + ((r4 + r5) + (r6 + r7))
    while i < n:
        res += a[i]
        i += 1
    return res
