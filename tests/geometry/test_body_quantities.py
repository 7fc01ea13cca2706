"""The local-quantity contract: an analysis's quantity per area integrated over a finite body.

Closed forms of the three ways a quantity combines (:mod:`xpersson.pipeline._body_local`), the
declaration's checks (:mod:`xpersson.plugins._bodyquantity`), and the plugins' declarations
end to end: Holm's constriction of a smooth sphere, Barber's analogy with the body's stiffness,
and the uniform-pressure limit equal to the flat analysis.
"""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np
import pytest

import xpersson
from xpersson.errors import XperssonWarning
from xpersson.physics.body import BodySolution, Separation, cell_areas, solve_body
from xpersson.pipeline._body_local import combine, interpolate
from xpersson.plugins import Analysis, BodyQuantity, SpecError, VarSpec, get_registry

from .conftest import body_scene

E_STAR = 1e6 / (1 - 0.25)
RHO1, RHO2 = 1e-7, 3e-7


def _cells(symmetry: str, n: int, r_max: float, p: Any) -> BodySolution:
    """A body's solution with a given nominal pressure on ``n`` uniform cells of [0, r_max]."""
    h = r_max / n
    edges = np.arange(n + 1) * h
    p = np.broadcast_to(np.asarray(p, float), (n,))
    return BodySolution(edges[:-1] + h / 2, edges, cell_areas(symmetry, n, h), p, 0, 0, 0, 0)


# -- combining, closed forms ---------------------------------------------------------------


def test_area_of_a_uniform_disk_and_strip_is_value_times_area() -> None:
    disk = _cells("axisymmetric", 80, 1.25e-3, 1.0)
    q = np.where(disk.r < 1e-3, 7.0, 0.0)[None]
    assert combine("area", q, [disk], "axisymmetric")[0] == pytest.approx(7.0 * math.pi * 1e-6)
    strip = _cells("plane", 80, 1.25e-3, 1.0)
    q = np.where(strip.r < 1e-3, 7.0, 0.0)[None]
    assert combine("area", q, [strip], "plane")[0] == pytest.approx(7.0 * 2e-3)


def test_series_of_a_uniform_strip_is_the_flat_seal_and_undefined_on_a_disk() -> None:
    strip = _cells("plane", 80, 1.25e-3, 1.0)
    q = np.where(strip.r < 1e-3, 3.0, np.inf)[None]  # no resistance outside the contact
    assert combine("series", q, [strip], "plane")[0] == pytest.approx(3.0 / 2e-3)
    sealed = np.where(strip.r < 1e-4, 0.0, 3.0)[None]
    assert combine("series", sealed, [strip], "plane")[0] == 0.0
    disk = _cells("axisymmetric", 80, 1.25e-3, 1.0)
    assert np.isnan(combine("series", q, [disk], "axisymmetric")[0])


def test_constriction_without_bulk_resistance_is_the_areal_sum() -> None:
    disk = _cells("axisymmetric", 64, 1e-3, 1.0)
    q = (5.0 + disk.r / 1e-4)[None]
    got = combine("constriction", q, [disk], "axisymmetric", bulk=0.0)
    assert got[0] == pytest.approx(combine("area", q, [disk], "axisymmetric")[0], rel=1e-12)


def test_constriction_of_a_perfect_disk_is_holm() -> None:
    """Holm: two half-spaces joined by a perfectly conducting disk of radius a conduct
    4 a / (rho_1 + rho_2). The disk's edge singularity of the flux converges slowly with
    uniform rings (0.8 % low on 80 rings inside, 0.7 % on 320)."""
    a = 1e-3
    disk = _cells("axisymmetric", 100, 1.25 * a, 1.0)
    q = np.where(disk.r < a, 1e14, 0.0)[None]  # S/m^2: no interface resistance
    got = combine("constriction", q, [disk], "axisymmetric", bulk=0.5 * (RHO1 + RHO2))
    assert got[0] == pytest.approx(4 * a / (RHO1 + RHO2), rel=0.01)


@pytest.mark.parametrize(("symmetry", "load"), [("axisymmetric", 1e-2), ("plane", 1.0)])
def test_constriction_with_barbers_local_conductance_is_the_body_stiffness(
    symmetry: str, load: float
) -> None:
    """Barber's analogy holds over the body: with the local conductance 2 K(p)/((rho_1 + rho_2)
    E*), K the interface's stiffness -dp/du, the body conducts 2 k/((rho_1 + rho_2) E*), k the
    body's normal stiffness from the same discrete equations (a line contact: both referred to
    the distance R = 10 mm)."""
    p = np.geomspace(1e1, 1e6, 60)
    u0 = 1e-7
    sep = Separation(p, u0 * np.log(1e7 / p), np.full(p.size, -u0), np.minimum(p / 1e6, 1))
    (sol,) = solve_body(
        symmetry, lambda r: r * r / 0.02, load, E_STAR, sep, 1e-3, 96, scale=1e-6,
        guess=lambda r: np.full(r.shape, 1e3), datum=0.01,
    )  # fmt: skip
    K = sol.p / u0  # -dp/du of u = u0 ln(p*/p)
    c = 2.0 / ((RHO1 + RHO2) * E_STAR)
    bulk = 0.5 * (RHO1 + RHO2)
    got = combine("constriction", (c * K)[None], [sol], symmetry, bulk=bulk, datum=0.01)
    assert got[0] == pytest.approx(c * sol.stiffness, rel=1e-6)


def test_interpolation_is_exact_on_power_laws_and_extrapolates_them_below() -> None:
    grid = np.geomspace(1e2, 1e6, 17)
    p = np.array([0.0, 1.0, 3e2, 7.7e4, 1e6, 5e6])
    for k in (1.0, -2.5):
        got = interpolate(grid, 3.0 * grid**k, p)
        with np.errstate(divide="ignore"):
            want = 3.0 * np.minimum(p, 1e6) ** k
        np.testing.assert_allclose(got, want, rtol=1e-12)


def test_interpolation_toward_an_unbounded_value_is_linear_in_the_resistance() -> None:
    """Full contact (``inf``: no resistance) at the top of the grid: between a finite and an
    unbounded grid value the resistance 1/q falls linearly in ln p to 0."""
    grid = np.array([1e2, 1e3, 1e4, 1e5])
    q = np.array([1.0, 2.0, np.inf, np.inf])
    p = np.array([50.0, 1e3, 10**3.25, 10**3.5, 1e4, 3e4, 1e6])
    got = interpolate(grid, q, p)
    want = [0.5 ** math.log10(2.0), 2.0, 2.0 / 0.75, 4.0, np.inf, np.inf, np.inf]
    np.testing.assert_allclose(got, want, rtol=1e-12)
    assert np.isinf(interpolate(grid, np.full(4, np.inf), np.array([10.0, 500.0]))).all()


# -- the declaration -----------------------------------------------------------------------


def _analysis(**decl: BodyQuantity) -> type:
    class Probe(Analysis):
        summary = "a probe"
        outputs: ClassVar = {
            "g": VarSpec(("p0",), "S m-2", "g"), "g0": VarSpec((), "S m-2", "g0")
        }  # fmt: skip
        provides = ("g", "g0")
        body_quantities: ClassVar = decl

    return Probe


@pytest.mark.parametrize(
    ("name", "bq", "message"),
    [
        ("conductance", BodyQuantity("g", "area", "S", "G"), "starting with 'body_'"),
        ("body_g", BodyQuantity("h", "area", "S", "G"), "local='h'"),
        ("body_g", BodyQuantity("g0", "area", "S", "G"), "dims ('p0',)"),
        ("body_g", BodyQuantity("g", "sum", "S", "G"), "combine='sum'"),
        ("body_g", BodyQuantity("g", "constriction", "S", "G"), "bulk=callable"),
        ("body_g", BodyQuantity("g", "area", "S", "G", bulk=lambda p: 1.0), "bulk=callable"),
        ("body_g", BodyQuantity("g", "area", "S", "G", factor=2.0), "factor must be"),  # type: ignore[arg-type]
        ("body_g", BodyQuantity("g", "area", "S", "G", unbounded="g0"), "unbounded='g0' must be"),
        ("body_g", BodyQuantity("g", "area", "S", "G", unbounded="g"), "no 'full_contact'"),
    ],
)
def test_a_bad_declaration_fails_at_class_creation(name: str, bq: Any, message: str) -> None:
    with pytest.raises(SpecError, match=message.replace("(", r"\(").replace(")", r"\)")):
        _analysis(**{name: bq})


def test_the_first_party_declarations() -> None:
    reg = get_registry()
    got = {
        name: sorted(reg.load("analyses", name).body_quantities)
        for name in ("electrical_contact", "thermal_contact", "leakage", "elastic_energy")
    }
    assert got == {
        "electrical_contact": ["body_electrical_conductance"],
        "thermal_contact": ["body_thermal_conductance"],
        "leakage": ["body_leak_rate", "body_leak_rate_emt"],
        "elastic_energy": ["body_elastic_energy"],
    }


# -- end to end ----------------------------------------------------------------------------


_ELECTRICAL = {"resistivity_1": f"{RHO1} ohm*m", "resistivity_2": f"{RHO2} ohm*m"}


def test_smooth_sphere_conducts_as_holm_over_three_decades_of_force() -> None:
    """A 1 nm rough flat (Johnson's parameter < 1e-3) whose pressure grid reaches full contact
    (the local conductance NaN by its declared meaning, status full_contact: no interface
    resistance): the body conducts Holm's 4 a/(rho_1 + rho_2), a the Hertz radius (measured
    -0.07 %, +0.2 %, +0.5 %), the thermal analysis the same with 1/kappa_1 + 1/kappa_2, and
    Barber's analogy with the body's stiffness holds."""
    scene = body_scene(force=["1 mN", "31.6 mN", "1 N"], h_rms="1 nm")
    scene["analyses"] = {"electrical_contact": _ELECTRICAL, "leakage": {"n_bins": 10},
                         "thermal_contact": {"conductivity_1": "100 W/(m*K)",
                                             "conductivity_2": "300 W/(m*K)"}}  # fmt: skip
    with pytest.warns(XperssonWarning, match="body_leak_rate, body_leak_rate_emt: a series across"):
        ds = xpersson.solve(scene)
    assert np.all(np.isnan(ds["body_leak_rate"]))  # a sphere is no seal
    full = ds["electrical_contact_status"].values == 1
    assert full.any() and np.all(np.isnan(ds["electrical_contact_conductance"].values[full]))
    a = (3 * ds["force"].values * 0.01 / (4 * E_STAR)) ** (1 / 3)
    G = ds["body_electrical_conductance"]
    assert G.attrs["units"] == "S"
    np.testing.assert_allclose(G, 4 * a / (RHO1 + RHO2), rtol=0.01)
    G_t = ds["body_thermal_conductance"].values
    np.testing.assert_allclose(G_t, 4 * a / (1 / 100 + 1 / 300), rtol=0.01)
    barber = 2 * ds["normal_stiffness"].values / ((RHO1 + RHO2) * E_STAR)
    np.testing.assert_allclose(G, barber, rtol=3e-3)
    err = ds["body_electrical_conductance_grid_error"].values
    assert np.all((err > 0) & (err < 0.03))


def test_smooth_cylinder_conducts_as_the_line_contacts_barber_value() -> None:
    """A smooth cylinder: Barber's analogy on the Hertz line contact's stiffness dP/d(delta) =
    pi E*/(2 ln(2R/b)), with the approach referred to the distance R, gives the conductance
    per length pi/((rho_1 + rho_2) ln(2R/b)) (b the Hertz half-width)."""
    scene = body_scene("cylinder", force="0.1 N", h_rms="0.3 nm")
    scene["spectrum"].update(H=0.3, q_1="1e10 1/m")
    scene["analyses"] = {"electrical_contact": _ELECTRICAL}
    ds = xpersson.solve(scene)
    P = float(ds["force"]) / 0.02
    b = math.sqrt(4 * P * 0.01 / (math.pi * E_STAR))
    want = math.pi / ((RHO1 + RHO2) * math.log(2 * 0.01 / b)) * 0.02
    assert float(ds["body_electrical_conductance"]) == pytest.approx(want, rel=0.01)


def test_an_oring_leaks_as_the_flat_seal_at_uniform_pressure() -> None:
    """A rough cylinder under the leakage and elastic-energy analyses: the body's outputs come
    from the plugins' declarations; at a uniform pressure over the flat seal's width (cells
    exactly at a grid pressure) the declared combination gives back the flat analysis."""
    scene = body_scene("cylinder", force=["0.1 N", "1 N"], h_rms="0.5 um")
    scene["analyses"] = {"leakage": {"seal_width": "0.4 mm", "seal_length": "20 mm"},
                         "elastic_energy": {}}  # fmt: skip
    ds = xpersson.solve(scene)
    Q = ds["body_leak_rate"].values
    assert ds["body_leak_rate"].attrs["units"] == "m^3 s^-1"
    assert np.all(Q > 0) and Q[1] < Q[0]  # a harder press leaks less
    assert np.all(ds["body_leak_rate_grid_error"].values < 0.05)
    reg = get_registry()
    p0 = ds["p0"].values
    k = p0.size // 2
    strip = _cells("plane", 50, 0.25e-3, np.where(np.arange(50) < 40, p0[k], 0.0))
    for analysis, name, var, area in (
        ("leakage", "body_leak_rate", "leak_rate", None),
        ("elastic_energy", "body_elastic_energy", "elastic_energy", 0.4e-3 * 20e-3),
    ):
        cls = reg.load("analyses", analysis)
        params = cls(**({} if area else {"seal_width": 0.4e-3, "seal_length": 20e-3})).params
        bq = cls.body_quantities[name]
        q = interpolate(p0, bq.local_values(params, ds[var].values, p0), strip.p[None])
        q = np.where(strip.p > 0, q, np.inf if bq.combine == "series" else 0.0)
        flat = ds[var].values[k] * (area or 1.0)
        assert 20e-3 * combine(bq.combine, q, [strip], "plane")[0] == pytest.approx(flat)


def test_plugins_show_lists_the_body_quantities(capsys: pytest.CaptureFixture[str]) -> None:
    from xpersson.cli import main

    main(["plugins", "show", "analyses", "leakage"])
    out = capsys.readouterr().out
    assert "integrated over a [geometry] body (per force):" in out
    assert "  body_leak_rate [m3 s-1]: " in out and "(series of leak_rate)" in out
    main(["plugins", "show", "analyses", "electrical_contact"])
    out = capsys.readouterr().out
    assert "unbounded where electrical_contact_status says full_contact)" in out


def test_a_seal_sealing_on_the_finer_grid_only_has_a_grid_error_of_one() -> None:
    """Seed 5, scene 1840 of ``fuzz.py --bodies 1``: an O-ring whose effective medium seals at
    the larger force on the result's cells and not on half of them. Its relative grid error
    is 1 (as large as the coarser value), not inf."""
    scene = {
        "spectrum": {"model": "self_affine", "H": 0.47516472257819065,
                     "q_L": "784.147790517197 1/m", "q_r": "784.147790517197 1/m",
                     "q_1": "328129.941693396 1/m", "rms_slope": 0.10400774644879665},
        "material": {"E": "139077.6246644648 Pa", "nu": 0.16051622745865407},
        "load": {"force": ["0.035374114279289846 N", "0.05253210661756657 N"]},
        "output": {"zeta_per_decade": 18},
        "solver": {"rtol": 2.434876395834641e-05},
        "boundary": {"model": "elastic"},
        "analyses": {"elastic_energy": {"s_factor": "yang_persson", "gamma": 0.0851409049745464},
                     "mean_gap": {"s_factor": "auto"},
                     "leakage": {"fluid": "liquid", "p_in": "1078692.45423576 Pa",
                                 "p_out": "16102.742442158704 Pa",
                                 "seal_width": "0.004287482338484247 m"}},
        "geometry": {"model": "cylinder", "radius": "0.0030741008774813517 m",
                     "length": "0.016262743155621717 m"},
    }  # fmt: skip
    ds = xpersson.solve(scene)
    value, err = ds["body_leak_rate_emt"].values, ds["body_leak_rate_emt_grid_error"].values
    assert value[0] > 0 and value[1] == 0.0
    assert np.all(np.isfinite(err)) and err[1] == 1.0 and 0 < err[0] < 1
