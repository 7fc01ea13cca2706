"""The README's speed table, measured in one run: every user path as a ratio to its own limit.

Run from the checkout::

    python benchmarks/summary.py [--rounds 3] [--check]

One process, ``OPENBLAS_NUM_THREADS=1`` (set here before numpy is imported), CPU time of this
process (``time.process_time``: the machine may be shared), each quantity the best of
``--rounds`` rounds in which the quantities of a ratio are measured alternately. The scenes
are those of the other benchmarks (``sweep_scaling.scene``, ``interface_analyses.scene``, the
adhesion plugin's example); the fresh-process row starts new interpreters.

Writes ``benchmarks/results/summary.md`` and rewrites the block between
``<!-- speed-table:start -->`` and ``<!-- speed-table:end -->`` of ``README.md`` with it, so
that no speed claim of the README is older than the code (``--check`` only prints the table).
"""

from __future__ import annotations

import os

os.environ["OPENBLAS_NUM_THREADS"] = "1"

import argparse  # noqa: E402
import platform  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
import tomllib  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from interface_analyses import scene as loads_scene  # noqa: E402
from sweep_scaling import scene as eh_scene  # noqa: E402

import xpersson  # noqa: E402
from xpersson.sweep import plain_paths  # noqa: E402

START, END = "<!-- speed-table:start -->", "<!-- speed-table:end -->"
ANALYSES = ("mean_gap", "contact_stiffness", "gap_pdf", "leakage")
FIRST_SOLVE = (
    "import time; t = time.process_time(); import xpersson; "
    "xpersson.solve({'spectrum': {'model': 'self_affine', 'H': 0.8, 'q_L': '1e3 1/m', "
    "'q_r': '1e4 1/m', 'q_1': '1e8 1/m', 'h_rms': '1 um'}, 'material': {'E': '10 MPa', "
    "'nu': 0.5}, 'load': {'p0': '1 MPa'}}); print(time.process_time() - t)"
)
IMPORTS = (
    "import time; t = time.process_time(); import xarray, pint; print(time.process_time() - t)"
)


def cpu(fn) -> float:
    """CPU time [s] of one call."""
    t = time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        fn()
    return time.process_time() - t


def best(fns: dict, rounds: int) -> dict[str, float]:
    """Best CPU time [s] of each function, measured alternately in ``rounds`` rounds."""
    out = {k: np.inf for k in fns}
    for _ in range(rounds):
        for k, fn in fns.items():
            out[k] = min(out[k], cpu(fn))
    return out


def _point_by_point(sc: dict):
    def fn():
        with plain_paths():
            xpersson.solve(sc)

    return fn


def sweep_rows(rounds: int) -> list[tuple[str, str, str, str]]:
    """1e4-point E x H sweep against 1e4 batched loads; the point-by-point path on 900."""
    big, loads, small = eh_scene(100, 100, 1), eh_scene(1, 1, 10_000), eh_scene(30, 30, 1)
    t = best(
        {
            "sweep": lambda: xpersson.solve(big),
            "loads": lambda: xpersson.solve(loads),
            "small": lambda: xpersson.solve(small),
            "small_pp": _point_by_point(small),
        },
        rounds,
    )
    per_pp, per_batched = t["small_pp"] / 900, t["sweep"] / 10_000
    study = cpu(lambda: xpersson.solve(eh_scene(300, 100, 1)))  # 3e4 parameter points
    return [
        (
            "E x H sweep, 1e4 points x 1 load (batched as loads)",
            f"{t['sweep']:.2f} s",
            f"1e4 loads in one run: {t['loads'] * 1e3:.0f} ms",
            f"{t['sweep'] / t['loads']:.1f}x (target <= 10x)",
        ),
        (
            "same, point by point (timed on 900 points: the path before this, and the path "
            "of plugins without `pressure_scaled`)",
            f"{per_pp * 1e3:.2f} ms/point",
            f"batched (1e4 points): {per_batched * 1e3:.3f} ms/point",
            f"{per_pp / per_batched:.0f}x slower",
        ),
        (
            "E x H study of 3e4 parameter points (50 zeta each), serial, one core",
            f"{study:.2f} s",
            "1e6 area curves per minute",
            f"{3e4 / study * 60:.2g} curves/min",
        ),
    ]


def analysis_rows(rounds: int) -> list[tuple[str, str, str, str]]:
    """Each interface analysis at 100 loads against the bare solve of the same loads."""
    fns = {"bare": lambda: xpersson.solve(loads_scene(100))}
    for name in ANALYSES:
        fns[name] = lambda n=name: xpersson.solve(loads_scene(100, {n: {}}))
    t = best(fns, rounds)
    return [
        (
            f"`{name}`, 100 loads",
            f"{t[name] * 1e3:.1f} ms",
            f"bare solve: {t['bare'] * 1e3:.1f} ms",
            f"{t[name] / t['bare']:.1f}x (target <= 10x)",
        )
        for name in ANALYSES
    ]


def dmt_rows(rounds: int) -> list[tuple[str, str, str, str]]:
    """``dmt`` on the adhesion plugin's example (13 loads, 3 tensile) against the elastic solve."""
    path = HERE.parent / "plugins" / "xpersson-adhesion" / "examples" / "pdms_on_glass.toml"
    if not path.is_file():
        return []
    sc = tomllib.loads(path.read_text())
    sc["boundary"] = {"model": "dmt", "work_of_adhesion": "0.05 J/m**2", "range": "0.5 nm"}
    el = dict(sc, boundary={"model": "elastic"})
    el["load"] = {"p0": {"start": "1 kPa", "stop": "40 kPa", "num": 13}}
    t = best({"dmt": lambda: xpersson.solve(sc), "el": lambda: xpersson.solve(el)}, rounds)
    ms = t["dmt"] / 13 * 1e3
    return [
        (
            "`dmt`, adhesion example (13 loads)",
            f"{ms:.1f} ms/load",
            f"elastic solve: {t['el'] / 13 * 1e3:.2f} ms/load",
            f"{t['dmt'] / t['el']:.0f}x (target <= 20 ms/load: {'met' if ms <= 20 else 'not met'})",
        )
    ]


def friction_rows(rounds: int) -> list[tuple[str, str, str, str]]:
    """mu(v) for 50 v x 3 T through ``xpersson.solve`` against the ``friction_curve`` kernel."""
    from viscoelastic_friction import solve_vs_kernel

    _, solve, kernel, pp = solve_vs_kernel(rounds)
    return [
        (
            "friction mu(v), 50 v x 3 T x 2 loads through `xpersson.solve` (blocks stacked)",
            f"{solve * 1e3:.0f} ms (point by point: {pp * 1e3:.0f} ms)",
            f"`friction_curve` kernel: {kernel * 1e3:.1f} ms",
            f"{solve / kernel:.0f}x (target <= 10x)",
        )
    ]


def cn_wall_rows(rounds: int) -> list[tuple[str, str, str, str]]:
    """Moving walls through ``cn`` (``cn_walls.py``): ``jkr`` at rtol 1e-6 and
    ``plastic_scale_dependent`` with the yield wall reached, against bare O(N) steps (numpy
    flux product + LAPACK ``dgtsv``) of the same grids and step counts."""
    from cn_walls import measure

    cost = measure(rounds)
    rows = []
    for key, label, target in (
        ("jkr, 3 loads in one call", "`jkr`, 3 loads in one call (rtol 1e-6)", 10),
        ("jkr, 1000 Pa alone", "`jkr`, one load (rtol 1e-6)", 10),
        (
            "plastic_scale_dependent (wall reached), 3 loads in one call",
            "`plastic_scale_dependent`, yield wall reached, 3 loads",
            20,
        ),
    ):
        c = cost[key]
        n = c["loads"]
        rows.append(
            (
                label,
                f"{c['cpu'] / n * 1e3:.1f} ms/load",
                f"bare O(N) steps of its grids: {c['bare'] / n * 1e3:.1f} ms/load",
                f"{c['cpu'] / c['bare']:.1f}x (target <= {target} ms/load)",
            )
        )
    return rows


def fresh_rows(rounds: int) -> list[tuple[str, str, str, str]]:
    """First solve in a fresh interpreter against ``import xarray, pint``."""

    def run(code: str) -> float:
        out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        return float(out.stdout.strip().splitlines()[-1])

    first, imports = np.inf, np.inf
    for _ in range(rounds):
        first, imports = min(first, run(FIRST_SOLVE)), min(imports, run(IMPORTS))
    return [
        (
            "first solve in a fresh process",
            f"{first:.2f} s",
            f"`import xarray, pint`: {imports:.2f} s",
            f"{first / imports:.1f}x (target <= 2x)",
        )
    ]


def table(rows: list[tuple[str, str, str, str]]) -> str:
    head = (
        f"Measured by `python benchmarks/summary.py` ({time.strftime('%Y-%m-%d')}, one process, "
        f"OPENBLAS_NUM_THREADS=1, CPU time, best of interleaved rounds; {platform.machine()}, "
        f"Python {platform.python_version()}, numpy {np.__version__}).\n\n"
        "| path | time | its limit, same run | ratio |\n|---|---:|---|---|\n"
    )
    return head + "\n".join(f"| {a} | {b} | {c} | {d} |" for a, b, c, d in rows) + "\n"


def main(argv: list[str] | None = None) -> str:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--check", action="store_true", help="print only; write nothing")
    args = ap.parse_args(argv)
    xpersson.solve(loads_scene(3))  # warm-up: imports, entry points
    rows = []
    for part in (
        sweep_rows,
        analysis_rows,
        dmt_rows,
        cn_wall_rows,
        friction_rows,
        fresh_rows,
    ):
        rows += part(args.rounds)
        print(table(rows), flush=True)
    text = table(rows)
    if not args.check:
        (HERE / "results" / "summary.md").write_text("# Speed summary\n\n" + text)
        readme = HERE.parent / "README.md"
        body = readme.read_text()
        if START in body and END in body:
            head, rest = body.split(START, 1)
            readme.write_text(head + START + "\n" + text + END + rest.split(END, 1)[1])
    return text


if __name__ == "__main__":
    main()
