"""A (v, T) friction sweep stacked in one run (issue 25): one kernel call for the block,
equal to the point-by-point path to 1e-12; the paired kernel equals the per-point one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import xpersson
from xpersson.physics import SelfAffineRollOff
from xpersson.pipeline import stacked
from xpersson.sweep import blocks, fast, plain_paths
from xpersson_viscoelastic import kernel, synthetic_tread
from xpersson_viscoelastic._paired import cumulative_paired

SCENE = Path(__file__).resolve().parents[1] / "examples" / "tread_on_asphalt.toml"


def test_paired_integrals_equal_the_per_point_kernel():
    psd = SelfAffineRollOff.from_h_rms(6e-5, 0.8, 600.0, 3000.0, 1e7)
    model = synthetic_tread()
    v, aT = np.array([1e-3, 1.0, 30.0]), np.array([1.0, 0.3, 5.0])
    grids = [np.geomspace(1, 1e3, 40), np.geomspace(1, 50, 70), 1 + np.geomspace(1e-6, 1e4, 100)]
    m = max(z.size for z in grids)
    padded = np.stack([np.concatenate([z, np.full(m - z.size, z[-1])]) for z in grids])
    rest, loss = cumulative_paired(psd, model, padded, v, aT)
    for k, z in enumerate(grids):
        for which, got in (("tau", rest), ("loss", loss)):
            ref = kernel._cumulative_at(
                psd, model, z, v[k], aT[k], which, kernel.NODES, kernel.PANELS_PER_DECADE
            )
            np.testing.assert_allclose(got[k, : z.size], ref, rtol=1e-14, atol=0)


@pytest.mark.fast_paths
@pytest.mark.parametrize("chunk", [None, 3])
def test_friction_sweep_stacked_equals_point_by_point(monkeypatch, chunk):
    kw = {
        "coefficient__velocity": ["1e-6 m/s", "1e-3 m/s", "0.1 m/s", "10 m/s"],
        "coefficient__temperature": ["273.15 K", "313.15 K"],
    }
    calls = []
    run = stacked.run_stacked
    monkeypatch.setattr(stacked, "run_stacked", lambda pts: calls.append(len(pts)) or run(pts))
    point_run = blocks.run  # the point-by-point path of a block the stacked run did not solve
    monkeypatch.setattr(blocks, "run", lambda *a, **k: calls.append(-1) or point_run(*a, **k))
    templates, solved_alone = [], []
    own = stacked.StackedRun.point_dataset
    monkeypatch.setattr(
        stacked.StackedRun, "point_dataset", lambda self: templates.append(1) or own(self)
    )
    template = fast._template
    monkeypatch.setattr(fast, "_template", lambda *a: solved_alone.append(1) or template(*a))
    rows = []
    solve_rows = stacked._PointContexts.solve_rows
    monkeypatch.setattr(
        stacked._PointContexts,
        "solve_rows",
        lambda self, *a: rows.append(solve_rows(self, *a)) or rows[-1],
    )
    batch = xpersson.solve(SCENE, chunk=chunk, **kw)
    assert sum(calls) == 8 and -1 not in calls  # every point solved stacked, the result used
    # one template for every block of the sweep, assembled from the first stacked run: no
    # point is solved on its own for it
    assert len(templates) == 1 and not solved_alone
    # the dense areas of a block: one engine call for all its (point, load) rows
    assert len(rows) == len(calls) and all(r is not None and r.shape[0] >= 1 for r in rows)
    with plain_paths():
        point = xpersson.solve(SCENE, chunk=chunk, **kw)
    assert list(batch.variables) == list(point.variables)
    for name, var in point.variables.items():
        if var.dtype.kind == "f":
            np.testing.assert_allclose(batch[name].values, var.values, rtol=1e-12, atol=1e-300)
        else:
            np.testing.assert_array_equal(batch[name].values, var.values)
    assert batch.mu_visc.dims == ("v", "T", "p0")


def test_block_integrals_are_the_kernel_functions_bitwise():
    from xpersson_viscoelastic._paired import block_integrals

    psd = SelfAffineRollOff.from_h_rms(6e-5, 0.8, 600.0, 3000.0, 1e7)
    model = synthetic_tread()
    zeta, v, aT = np.geomspace(1, 1e4, 81), np.geomspace(1e-8, 1e2, 7), np.linspace(0.1, 9, 7)
    got = block_integrals(psd, model, 0.5, zeta, v, aT, 4)
    kw = {"panels_per_decade": 4}
    np.testing.assert_array_equal(
        got["tau"], kernel.diffusion_time(psd, model, 0.5, zeta, v, aT, **kw)
    )
    np.testing.assert_array_equal(
        got["L"], kernel.loss_integral(psd, model, 0.5, zeta, v, aT, **kw)
    )
    np.testing.assert_array_equal(got["f"], kernel.coefficient_f(psd, model, 0.5, zeta, v, aT))
    rms, loss = kernel.angular_averages(psd, model, 0.5, zeta, v, aT)
    np.testing.assert_array_equal(got["rms"], rms)
    np.testing.assert_array_equal(got["loss"], loss)
