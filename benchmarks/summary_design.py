"""The scene design of ``benchmarks/summary.py`` and its timing helpers.

``design(n, seed)`` draws ``n`` (>= 12) scenes across the documented domain: H stratified over
0.3-0.95, with and without roll-off (roll-off decade 0.5-1), 3-6 decades of q_1/q_L, q_L 1e2-1e4
1/m; the two scenes the issue named are always in (roll-off H = 0.3 over 6 decades, steep
H = 0.95 without roll-off over 6 decades). Each scene is an elastic contact (rubber,
E* = 13.3 MPa); the paths that need another boundary (``jkr``, ``plastic_scale_dependent``) put
theirs on the same spectrum.
"""

from __future__ import annotations

import time
import tracemalloc
import warnings
from collections.abc import Callable

import numpy as np

#: Magnifications of every output curve (as ``sweep_scaling.scene``): 50 points.
ZETA = [float(z) for z in np.geomspace(1.0, 1e3, 50)]


def spectrum(H: float, roll: bool, decades: float, q_L: float) -> dict:
    """A self-affine spectrum (``q_r = q_L``: no roll-off)."""
    q_L, H = float(q_L), float(H)
    q_r = q_L * (10 ** (0.5 + 0.5 * (H % 0.1) / 0.1) if roll else 1.0)
    return {
        "model": "self_affine",
        "H": round(float(H), 4),
        "q_L": f"{q_L!r} 1/m",
        "q_r": f"{q_r!r} 1/m",
        "q_1": f"{q_L * 10**decades!r} 1/m",
        "h_rms": "1 um",
    }


def design(n: int = 12, seed: int = 36) -> list[tuple[str, dict]]:
    """``n`` named spectra (seeded): the two named ones first, then a stratified draw."""
    rng = np.random.default_rng(seed)
    out = [
        ("roll H=0.30 6dec", spectrum(0.3, True, 6, 1e2)),
        ("steep H=0.95 6dec", spectrum(0.95, False, 6, 1e2)),
    ]
    hs = 0.3 + 0.65 * (np.arange(n - 2) + rng.random(n - 2)) / (n - 2)
    rng.shuffle(hs)
    for k, H in enumerate(hs):
        roll = bool(k % 2)
        decades = float(rng.integers(3, 7))
        q_L = float(10 ** rng.uniform(2, 4))
        name = f"{'roll' if roll else 'flat'} H={H:.2f} {decades:.0f}dec"
        out.append((name, spectrum(H, roll, decades, q_L)))
    return out


def held_out(n: int = 12, seed: int = 2026) -> list[tuple[str, dict]]:
    """``n`` stratified draws of the same domain with another seed, without the two named
    scenes: the design the claims were not made on."""
    return design(n + 2, seed)[2:]


def labelled(seeds: list[int], held: list[int]) -> list[tuple[str, dict]]:
    """The scenes of :func:`design` for each of ``seeds`` (each spectrum once: the two named
    scenes of every seed are the same; labelled ``seed S: `` unless S is the speed design's
    36) and of :func:`held_out` for each of ``held`` (labelled ``held-out S: ``)."""
    scenes, seen = [], set()
    for seed in seeds:
        for name, spec in design(12, seed):
            if repr(spec) not in seen:
                seen.add(repr(spec))
                scenes.append((name if seed == 36 else f"seed {seed}: {name}", spec))
    for seed in held:
        scenes += [(f"held-out {seed}: {name}", spec) for name, spec in held_out(12, seed)]
    return scenes


def scene(spec: dict, loads: object = "100 kPa", **sections: object) -> dict:
    """An elastic scene on ``spec`` with the shared 50-point zeta grid."""
    out = {
        "spectrum": dict(spec),
        "material": {"E": "10 MPa", "nu": 0.5},
        "load": {"p0": loads},
        "output": {"zeta": ZETA},
    }
    out.update(sections)
    return out


def load_range(n: int, lo: float = 1e3, hi: float = 1e6) -> dict:
    """``n`` log-spaced loads as a range table."""
    return {"start": f"{lo!r} Pa", "stop": f"{hi!r} Pa", "num": n}


def cpu(fn: Callable[[], object]) -> float:
    """CPU time [s] of one call (warnings silenced)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        t = time.process_time()
        fn()
        return time.process_time() - t


def best(fns: dict[str, Callable[[], object]], rounds: int) -> dict[str, float]:
    """Best CPU time [s] of each function over ``rounds`` interleaved rounds (one warm-up)."""
    for fn in fns.values():
        cpu(fn)
    out = dict.fromkeys(fns, np.inf)
    for _ in range(rounds):
        for k, fn in fns.items():
            out[k] = min(out[k], cpu(fn))
    return out


def repeated(
    fn: Callable[[], object], seconds: float = 0.02, once: float | None = None
) -> tuple[Callable[[], None], int]:
    """``fn`` run often enough to take about ``seconds`` of CPU time, and the count (a timed
    call of a millisecond is mostly the clock's and the machine's noise); ``once``: one call's
    CPU time [s] where already measured (else the best of 3 calls)."""
    one = min(cpu(fn) for _ in range(3)) if once is None else once
    n = max(1, int(seconds / max(one, 1e-6)))

    def many() -> None:
        for _ in range(n):
            fn()

    return many, n


def timed(fns: dict[str, Callable[[], object]], rounds: int) -> dict[str, float]:
    """CPU time [s] per call of each function: the best of ``rounds`` interleaved rounds, each
    round timing ~20 ms of repeated calls (:func:`repeated`; one call where a call is
    longer). The table's in-process rows are timed so (the cold row times fresh interpreters,
    the parallel rows wall clocks): a single timed call of a ~1 ms solve right after a 10 ms
    one runs on caches the other evicted (a 100-load bare solve: 0.82-1.02 ms so,
    0.75-0.82 ms in a loop, as a study solving it again and again runs it:
    ``timing_method.py``)."""
    reps = {k: repeated(fn) for k, fn in fns.items()}
    t = best({k: many for k, (many, _) in reps.items()}, rounds)
    return {k: t[k] / reps[k][1] for k in t}


def peak_mib(fn: Callable[[], object]) -> float:
    """Peak traced memory [MiB] of one call (``tracemalloc``: Python and numpy buffers)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        tracemalloc.start()
        try:
            fn()
            return tracemalloc.get_traced_memory()[1] / 2**20
        finally:
            tracemalloc.stop()


#: The host probe's fixed workload: ``erf`` of these values (scipy's, one call).
_PROBE_X = np.linspace(0.0, 3.0, 200_000)


def probe() -> float:
    """The host's speed now: CPU time [ms] of ``erf`` over 2e5 fixed values, best of 3.

    The same work at every call, so its spread over a run (:func:`over_design` takes it before
    each scene) is the host's drift, not the code's: on a shared virtual machine the absolute
    times of two rows, or of two runs, compare only within it."""
    from scipy.special import erf

    return 1e3 * min(cpu(lambda: erf(_PROBE_X)) for _ in range(3))
