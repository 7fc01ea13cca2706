"""Issue 36 items 3, 5, 6: analyses per load, one curve against its kernel, engine against C.

Run from the checkout::

    python benchmarks/kernels_speed.py [--rounds 3] [--parts analyses,single,plastic,engine]

One process, ``OPENBLAS_NUM_THREADS=1`` (set here before numpy is imported), CPU time of this
process (``time.process_time``), each figure the best of ``--rounds`` rounds in which the
quantities of a ratio are measured alternately. Every part runs over several scenes and
reports each and the worst:

* ``analyses``: ``gap_pdf``, ``leakage``, ``mean_gap`` at 100, 1000 and 1e4 loads (given as a
  ``{start, stop, num}`` range, 1 kPa to 3 MPa) on a roll-off H = 0.3 and a steep H = 0.95
  spectrum without roll-off, 3 and 6 decades: time per load of the analysis (solve with it
  minus the bare solve) and the ratio of the whole solve to the bare one.
* ``single``: one closed-form load (fixed cost: ``xpersson.solve`` against its kernel
  ``solve_batch``), one ``jkr`` load, one friction curve of 50 speeds (one load, one
  temperature) against the kernel ``friction_curve``.
* ``plastic``: ``plastic_scale_dependent`` per load and node-steps per load on the roll-off
  H = 0.3 scene (and H = 0.8 for comparison).
* ``engine``: every grid level the ``cn`` engine marches (a spy on
  ``xpersson.engine._cn._march``) is replayed by the C Thomas march of
  ``../shared/peers/c_march/thomas.c`` (built here with ``gcc -O2``; skipped without a
  compiler or without the peer) at rtol 1e-6 and 1e-8: solve / C, with the compiled inner
  march (numba, where installed) and with ``set_options(compiled=False)`` (numpy path).

Writes ``benchmarks/results/kernels_speed.md``.
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import copy  # noqa: E402
import ctypes  # noqa: E402
import platform  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import tomllib  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from summary_design import best, cpu  # noqa: E402  (the timing helpers of summary.py)

import xpersson  # noqa: E402

HERE = Path(__file__).resolve().parent
#: the peer C march (``../shared/peers``, as the other peer benchmarks; ``XPERSSON_PEERS``
#: overrides the folder, e.g. from a worktree)
PEERS = Path(os.environ.get("XPERSSON_PEERS", HERE.parents[1] / "shared" / "peers"))
C_MARCH = PEERS / "c_march" / "thomas.c"
ANALYSES = ("gap_pdf", "leakage", "mean_gap")
LOADS = (100, 1000, 10_000)
#: (name, H, roll-off, decades above q_r)
SPECTRA = (
    ("rolloff H=0.3, 3 dec", 0.3, True, 3),
    ("rolloff H=0.3, 6 dec", 0.3, True, 6),
    ("steep H=0.95, 3 dec", 0.95, False, 3),
    ("steep H=0.95, 6 dec", 0.95, False, 6),
)


def spectrum(H: float, roll: bool, decades: int, q_L: float = 1e3) -> dict:
    """A self-affine spectrum from ``q_L`` [1/m]; roll-off over one decade or none."""
    q_r = 10.0 * q_L if roll else q_L
    return {"model": "self_affine", "H": H, "q_L": f"{q_L!r} 1/m", "q_r": f"{q_r!r} 1/m",
            "q_1": f"{q_r * 10.0**decades!r} 1/m", "h_rms": "1 um"}  # fmt: skip


def loads_scene(spec: dict, n: int, analysis: str | None = None) -> dict:
    """``n`` loads from 1 kPa to 3 MPa (a range) on a 10 MPa rubber, one analysis or none."""
    p0 = {"start": "1 kPa", "stop": "3 MPa", "num": n, "spacing": "log"} if n > 1 else "100 kPa"
    return {"spectrum": spec, "material": {"E": "10 MPa", "nu": 0.5}, "load": {"p0": p0},
            "analyses": {analysis: {}} if analysis else {}}  # fmt: skip


def analyses_part(rounds: int) -> list[str]:
    """Per-load cost and ratio to the bare solve of each analysis, every scene and load count."""
    lines = ["## Interface analyses (loads as a range)", "",
             "| scene | loads | bare [ms] | analysis | extra per load [us] | ratio to bare |",
             "|---|---:|---:|---|---:|---:|"]  # fmt: skip
    worst: dict[tuple[str, int], tuple[float, str]] = {}
    per_load: dict[tuple[str, str, int], float] = {}
    for name, H, roll, dec in SPECTRA:
        spec = spectrum(H, roll, dec)
        for n in LOADS:
            fns = {"": lambda s=spec, n=n: xpersson.solve(loads_scene(s, n))}
            for a in ANALYSES:
                fns[a] = lambda s=spec, n=n, a=a: xpersson.solve(loads_scene(s, n, a))
            t = best(fns, rounds if n < 10_000 else max(1, rounds // 2))
            bare = t.pop("")
            for a, ta in t.items():
                extra = max(ta - bare, 0.0) / n * 1e6
                per_load[name, a, n] = extra
                lines.append(f"| {name} | {n} | {bare * 1e3:.1f} | `{a}` | {extra:.0f} | "
                             f"{ta / bare:.1f} |")  # fmt: skip
                if ta / bare > worst.get((a, n), (0.0, ""))[0]:
                    worst[a, n] = (ta / bare, name)
    lines += ["", "| analysis | loads | worst ratio to bare (scene) | worst per-load growth "
              "against 100 loads |", "|---|---:|---|---:|"]  # fmt: skip
    for (a, n), (r, name) in sorted(worst.items()):
        growth = max(per_load[s[0], a, n] / per_load[s[0], a, 100] for s in SPECTRA)
        lines.append(f"| `{a}` | {n} | {r:.1f}x ({name}) | {growth:.2f} |")
    return lines


def _friction_case():
    """The tread example as one friction curve: 50 speeds, one temperature, one load."""
    sys.path.insert(0, str(HERE))
    from viscoelastic_friction import NU, SHIFT, V, _psd

    from xpersson_viscoelastic import friction_curve, synthetic_tread

    path = HERE.parent / "plugins/xpersson-viscoelastic/examples/tread_on_asphalt.toml"
    sc = tomllib.loads(path.read_text())
    sc["load"] = {"p0": "0.3 MPa"}
    sc["coefficient"]["velocity"] = {"start": "1e-8 m/s", "stop": "100 m/s", "num": 50,
                                     "spacing": "log"}  # fmt: skip
    psd, model, aT = _psd(), synthetic_tread(), SHIFT.aT(np.array([293.15]))
    return sc, lambda: friction_curve(psd, model, NU, [3e5], V, aT)


def _jkr_scene(spec: dict) -> dict:
    return {"spectrum": spec, "material": {"E": "1 MPa", "nu": 0.5}, "load": {"p0": "1000 Pa"},
            "boundary": {"model": "jkr", "work_of_adhesion": "0.05 J/m**2"},
            "output": {"zeta_per_decade": 4}}  # fmt: skip


def single_part(rounds: int) -> list[str]:
    """One closed-form load, one jkr load, one friction curve."""
    from xpersson.engine import solve_batch  # noqa: F401  (the kernel: imported, not timed)

    lines = ["## One curve", "", "| case | scene | solve [ms] | kernel [ms] | ratio |",
             "|---|---|---:|---:|---:|"]  # fmt: skip
    for name, H, roll, dec in SPECTRA:
        spec = spectrum(H, roll, dec)
        t = best({"one": lambda s=spec: xpersson.solve(loads_scene(s, 1))}, rounds * 5)
        lines.append(f"| one closed-form load | {name} | {t['one'] * 1e3:.2f} | | |")
    for name, H, roll, dec in SPECTRA[:1] + SPECTRA[2:3] + (("README H=0.8, 4 dec", 0.8, True,
                                                             4),):  # fmt: skip
        spec = spectrum(H, roll, dec, q_L=1e4)
        try:
            t = best({"jkr": lambda s=spec: xpersson.solve(_jkr_scene(s))}, rounds)
        except Exception as exc:  # noqa: BLE001  (plugin missing)
            lines.append(f"| one `jkr` load | {name} | skipped: {exc} | | |")
            continue
        lines.append(f"| one `jkr` load | {name} | {t['jkr'] * 1e3:.1f} | | (target 5 ms) |")
    try:
        sc, kernel = _friction_case()
    except ImportError as exc:
        return [*lines, f"| friction curve | skipped: {exc} | | | |"]
    t = best({"solve": lambda: xpersson.solve(sc), "kernel": kernel}, rounds * 3)
    ratio = t["solve"] / t["kernel"]
    lines.append(
        f"| friction curve, 50 v | tread example | {t['solve'] * 1e3:.1f} | "
        f"{t['kernel'] * 1e3:.1f} | {ratio:.1f}x (target 5x) |"
    )
    return lines


def levels_of(scene: dict) -> list[tuple[int, int, int]]:
    """(loads, nodes, steps) of every grid level the ``cn`` engine marches for ``scene``."""
    from xpersson.engine import _cn

    seen: list[tuple[int, int, int]] = []
    orig = _cn._march

    def spy(pbs, plan, n, *args):  # noqa: ANN001, ANN202
        res = orig(pbs, plan, n, *args)
        seen.append((len(pbs), n + 1, int(res.nsteps)))
        return res

    _cn._march = spy
    try:
        cpu(lambda: xpersson.solve(scene))
    finally:
        _cn._march = orig
    return seen


def _plastic(spec: dict, rtol: float = 1e-6) -> dict:
    return {"spectrum": spec, "material": {"E": "210 GPa", "nu": 0.3},
            "load": {"p0": ["5 MPa", "20 MPa", "100 MPa"]},
            "boundary": {"model": "plastic_scale_dependent", "Y1": "3 GPa", "n": 0.1},
            "output": {"zeta_per_decade": 10}, "solver": {"rtol": rtol}}  # fmt: skip


PLASTIC_SPECTRA = {
    "rolloff H=0.3 (q 1e2..1e9)": {"model": "self_affine", "H": 0.3, "q_L": "1e2 1/m",
                                   "q_r": "1e3 1/m", "q_1": "1e9 1/m", "h_rms": "1 um"},
    "README H=0.8 (q 1e3..1e8)": {"model": "self_affine", "H": 0.8, "q_L": "1e3 1/m",
                                  "q_r": "1e4 1/m", "q_1": "1e8 1/m", "h_rms": "1 um"},
}  # fmt: skip


def plastic_part(rounds: int) -> list[str]:
    """``plastic_scale_dependent``: ms and node-steps per load (3 loads)."""
    lines = ["## plastic_scale_dependent (3 loads)", "",
             "| scene | ms/load | node-steps/load |", "|---|---:|---:|"]  # fmt: skip
    for name, spec in PLASTIC_SPECTRA.items():
        sc = _plastic(spec)
        steps = sum(a * b * c for a, b, c in levels_of(sc)) / 3
        t = best({"s": lambda sc=sc: xpersson.solve(sc)}, rounds)
        lines.append(f"| {name} | {t['s'] / 3 * 1e3:.1f} (target 20) | {steps:.3g} |")
    return lines


def build_c() -> ctypes.CDLL | None:
    """The peer's C march, built with ``gcc -O2`` into a temporary folder (None: no compiler)."""
    cc = os.environ.get("CC", "gcc")
    if shutil.which(cc) is None or not C_MARCH.is_file():
        return None
    out = Path(tempfile.mkdtemp()) / "libthomas.so"
    subprocess.run([cc, "-O2", "-shared", "-fPIC", str(C_MARCH), "-o", str(out)], check=True)
    lib = ctypes.CDLL(str(out))
    dp = ctypes.POINTER(ctypes.c_double)
    lib.march.argtypes = [ctypes.c_int, ctypes.c_int, dp, dp]
    return lib


def c_march(lib: ctypes.CDLL, levels: list[tuple[int, int, int]]) -> None:
    """The C march over the same levels (loads concatenated)."""
    dp = ctypes.POINTER(ctypes.c_double)
    for nb, nn, steps in levels:
        m = nb * nn
        r = np.random.default_rng(1).random(m)
        ws = np.empty(3 * m)
        lib.march(m, steps, r.ctypes.data_as(dp), ws.ctypes.data_as(dp))


def _numpy_solve(sc: dict) -> None:
    """The solve with the compiled march off (the pure-numpy path)."""
    with xpersson.set_options(compiled=False):
        xpersson.solve(sc)


def engine_part(rounds: int) -> list[str]:
    """solve / C march on the plastic and jkr scenes at rtol 1e-6 and 1e-8."""
    lib = build_c()
    if lib is None:
        return ["## Engine against the C march", "", "skipped: no compiler or no peer source"]
    lines = ["## Engine against the C march (gcc -O2)", "",
             "| scene | rtol | node-steps | solve [ms] | numpy path [ms] | C [ms] | solve / C "
             "| numpy path / C |", "|---|---:|---:|---:|---:|---:|---:|---:|"]  # fmt: skip
    cases = {f"plastic {k}": (lambda r, s=s: _plastic(s, r)) for k, s in PLASTIC_SPECTRA.items()}
    jkr = _jkr_scene(spectrum(0.8, True, 4, q_L=1e4))
    cases["jkr README H=0.8"] = lambda r: dict(copy.deepcopy(jkr), solver={"rtol": r})
    for name, make in cases.items():
        for rtol in (1e-6, 1e-8):
            sc = make(rtol)
            try:
                levels = levels_of(sc)
            except Exception as exc:  # noqa: BLE001  (plugin missing)
                lines.append(f"| {name} | {rtol:g} | skipped: {exc} | | | |")
                continue
            ns = sum(a * b * c for a, b, c in levels)
            t = best({"solve": lambda sc=sc: xpersson.solve(sc),
                      "numpy": lambda sc=sc: _numpy_solve(sc),
                      "c": lambda lv=levels: c_march(lib, lv)}, rounds)  # fmt: skip
            lines.append(f"| {name} | {rtol:g} | {ns:.3g} | {t['solve'] * 1e3:.1f} | "
                         f"{t['numpy'] * 1e3:.1f} | {t['c'] * 1e3:.1f} | "
                         f"{t['solve'] / t['c']:.1f}x | {t['numpy'] / t['c']:.1f}x |")  # fmt: skip
    return lines


PARTS = {"analyses": analyses_part, "single": single_part, "plastic": plastic_part,
         "engine": engine_part}  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--parts", default=",".join(PARTS))
    args = ap.parse_args()
    lines = ["# Kernels and fixed costs (issue 36, items 3, 5, 6)", "",
             f"Measured by `python benchmarks/kernels_speed.py --rounds {args.rounds}`: "
             "OPENBLAS_NUM_THREADS=1, CPU time, best of interleaved rounds; "
             f"{platform.machine()}, Python {platform.python_version()}, "
             f"numpy {np.__version__}.", ""]  # fmt: skip
    for part in args.parts.split(","):
        new = [*PARTS[part](args.rounds), ""]
        print("\n".join(new), flush=True)
        lines += new
    (HERE / "results" / "kernels_speed.md").write_text("\n".join(lines))


if __name__ == "__main__":
    main()
