"""Verification rows of the ``viscoelastic`` coefficient's echoed and derived scalars and of the
``friction`` analysis's shear stress, for ``benchmarks/verify.py``.

- ``sliding_speed``, ``rubber_temperature``, ``rubbery_modulus``, ``glassy_modulus``: the
  scene's values, given in other units (mm/s, degC-free kelvin, MPa, GPa), converted to SI here;
  for a Prony series ``E_g = E_r + sum dE_i``.
- ``frictional_shear_stress``: ``tau_f0 exp(-c log10(a_T v / v*)^2)`` (physics.md §7) with the
  WLF ``a_T`` of ``visco_reference`` (the plugin tests' independent model), and the constant law.
- ``flash_temperature``: off, the temperature at every scale; on, the Volterra equation of
  {cite:p}`persson2006flash` as the plugin states it, ``dT/dq = (1/k) sqrt(D v / q) q^3 C(q)
  Lambda(q v a_T(T(q))) / (1 - nu^2)``, integrated here as an ODE in ``ln q`` (DOP853, rtol
  1e-11, the roll-off as a breakpoint) with the SLS angular closed form ``Lambda`` of
  ``visco_reference``. The reference checks the equation's solution, not Persson's kernel
  (which the plugin calls approximate: {cite:p}`persson2006flash` is structure only).
"""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import xpersson

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "plugins" / "xpersson-viscoelastic" / "tests"))

from verify_core import _row  # noqa: E402
from visco_reference import SLS, RefSpectrum, wlf_shift  # noqa: E402

E_R, E_G, TAU, NU = 2e6, 2e9, 1e-4, 0.5
WLF = (7.84, 114.75, 293.15)
SPEC = RefSpectrum(0.7, 2e3, 2e4, 2e6, 0.5)
K_TH, D_TH = 0.25, 1e-7
TAU_F0, C_LAW, V_STAR = 3e5, 0.1, 1e-2


def _scene(v_mm: list[float], temps: list[float], coef: dict, friction: dict) -> dict:
    return {
        "spectrum": {
            "model": "self_affine",
            "H": SPEC.H,
            "q_L": f"{SPEC.q_L!r} 1/m",
            "q_r": f"{SPEC.q_r!r} 1/m",
            "q_1": f"{SPEC.q_1!r} 1/m",
            "rms_slope": SPEC.rms_slope,
        },
        "material": {"E": f"{E_R!r} Pa", "nu": NU},
        "load": {"p0": ["0.2 MPa"]},
        "coefficient": {
            "model": "viscoelastic",
            **coef,
            "velocity": [f"{x!r} mm/s" for x in v_mm],
            "temperature": [f"{t!r} K" for t in temps],
        },
        "analyses": {"friction": friction},
        "output": {"zeta_per_decade": 10},
    }


def _sls(flash: bool = False) -> dict:
    out = {
        "modulus": "sls",
        "E_r": f"{E_R / 1e6!r} MPa",
        "E_g": f"{E_G / 1e9!r} GPa",
        "relaxation_time": f"{TAU * 1e3!r} ms",
        "shift": "wlf",
        "C1": WLF[0],
        "C2": f"{WLF[1]!r} K",
        "T_ref": f"{WLF[2]!r} K",
    }
    if flash:
        out |= {
            "flash_temperature": True,
            "thermal_conductivity": f"{K_TH!r} W/(m*K)",
            "thermal_diffusivity": f"{D_TH * 1e6!r} mm**2/s",
        }
    return out


def _solve(scene: dict):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return xpersson.solve(scene)


def _vals(ds, name: str, *dims: str) -> np.ndarray:
    """Values with the axes ``dims`` first (broadcast where the variable lacks one)."""
    da = ds[name]
    missing = {d: ds.sizes[d] for d in dims if d not in da.dims}
    return np.asarray(da.expand_dims(missing).transpose(*dims, ...).values, float)


def flash_reference(v: float, T0: float, q: np.ndarray) -> np.ndarray:
    """T(q) [K] of the §4.5 Volterra equation as an ODE in ln q (this file)."""
    sls = SLS(E_R, E_G, TAU)

    def rhs(s: float, y: np.ndarray) -> list[float]:
        qq = math.exp(s)
        aT = wlf_shift(float(y[0]), *WLF)
        lam = sls.angular(qq * v * aT)[1]
        dl = qq**3 * SPEC.C(qq) * lam / (1 - NU**2)  # dL/dq [Pa/m]
        return [qq * math.sqrt(D_TH * v / qq) * dl / K_TH]

    out = np.empty(q.size)
    y, s0 = np.array([T0]), math.log(SPEC.q_L)
    for i, qq in enumerate(q):
        for lo, hi in _pieces(s0, math.log(qq)):
            sol = solve_ivp(rhs, (lo, hi), y, method="DOP853", rtol=1e-11, atol=1e-9)
            y = sol.y[:, -1]
        out[i], s0 = y[0], math.log(qq)
    return out


def _pieces(a: float, b: float) -> list[tuple[float, float]]:
    r = math.log(SPEC.q_r)
    if b <= a:
        return []
    return [(a, r), (r, b)] if a < r < b else [(a, b)]


def rows(fast: bool) -> list[dict]:
    """Echoes, shear stress and flash temperature rows."""
    v_mm = [1e-3, 10.0, 1e3] if fast else [1e-6, 1e-3, 1.0, 10.0, 1e3, 1e5]
    temps = [263.15, 293.15, 323.15] if fast else [233.15, 263.15, 293.15, 323.15, 353.15]
    fric = {"tau_f": "0.3 MPa", "shear_law": "velocity", "c": C_LAW, "v_star": "10 mm/s"}
    ds = _solve(_scene(v_mm, temps, _sls(), fric))
    v = np.array(v_mm) * 1e-3
    aT = np.array([[wlf_shift(t, *WLF) for _ in v] for t in temps])
    tau_f = TAU_F0 * np.exp(-C_LAW * np.log10(aT * v[None, :] / V_STAR) ** 2)
    dims = ("T", "v")
    err = {
        "sliding_speed": np.max(np.abs(_vals(ds, "sliding_speed", *dims) / v[None, :] - 1)),
        "rubber_temperature": np.max(
            np.abs(_vals(ds, "rubber_temperature", *dims) - np.array(temps)[:, None])
        ),
        "rubbery_modulus": np.max(np.abs(_vals(ds, "rubbery_modulus", *dims) / E_R - 1)),
        "glassy_modulus": np.max(np.abs(_vals(ds, "glassy_modulus", *dims) / E_G - 1)),
        "frictional_shear_stress": np.max(
            np.abs(_vals(ds, "frictional_shear_stress", *dims) / tau_f - 1)
        ),
    }
    prony = {
        "modulus": "prony",
        "E_r": "2 MPa",
        "delta_E": ["0.5 GPa", "1 GPa", "0.5 GPa"],
        "relaxation_times": ["1 us", "0.1 ms", "10 ms"],
    }
    dp = _solve(_scene([1.0], [293.15], prony, {"tau_f": "0.1 MPa"}))
    err["glassy_modulus"] = max(
        err["glassy_modulus"], abs(dp["glassy_modulus"].item() / 2.002e9 - 1)
    )
    err["rubbery_modulus"] = max(
        err["rubbery_modulus"], abs(dp["rubbery_modulus"].item() / E_R - 1)
    )
    shear = abs(dp["frictional_shear_stress"].item() / 1e5 - 1)
    err["frictional_shear_stress"] = max(err["frictional_shear_stress"], shear)
    flat = _vals(ds, "flash_temperature", *dims)
    err_off = float(np.max(np.abs(flat - np.array(temps)[:, None, None])))
    regime = (
        f"SLS + WLF, v {v[0]:.0e}..{v[-1]:.0e} m/s (given in mm/s), T {temps[0]}..{temps[-1]} K"
    )
    refs = {
        "sliding_speed": ("velocity in mm/s x 1e-3", "rel"),
        "rubber_temperature": ("the scene's temperature [K]", "abs K"),
        "rubbery_modulus": ("E_r given in MPa x 1e6", "rel"),
        "glassy_modulus": ("E_g given in GPa x 1e9; Prony: E_r + sum dE_i", "rel"),
        "frictional_shear_stress": (
            "tau_f0 exp(-c log10(a_T v/v*)^2), WLF a_T written apart; constant law: tau_f",
            "rel",
        ),
    }
    out = [_row(n, regime, refs[n][0], err[n], refs[n][1]) for n in refs]
    out.append(_flash_row(fast, err_off, regime))
    return out


def _flash_row(fast: bool, err_off: float, regime_off: str) -> dict:
    v_mm = [1e2, 1e3] if fast else [1.0, 1e2, 1e3, 1e4]
    T0 = 293.15
    ds = _solve(_scene(v_mm, [T0], _sls(flash=True), {}))
    z = ds["zeta"].values
    got = _vals(ds, "flash_temperature", "v", "zeta").reshape(len(v_mm), -1)
    worst, rise = 0.0, 0.0
    for i, vm in enumerate(v_mm):
        ref = flash_reference(vm * 1e-3, T0, z * SPEC.q_L)
        worst = max(worst, float(np.max(np.abs(got[i] - ref) / np.maximum(ref - T0, 1.0))))
        rise = max(rise, float(ref[-1] - T0))
    return _row(
        "flash_temperature",
        f"off: {regime_off}; on: v {v_mm[0] * 1e-3:g}..{v_mm[-1] * 1e-3:g} m/s at {T0} K",
        "off: the temperature; on: {cite:p}`persson2006flash` Volterra equation as an ODE "
        "(this file)",
        max(worst, err_off),
        "rel (rise)",
        f"off: {err_off:.1g} K; on: relative to the rise (up to {rise:.3g} K), floor 1 K; "
        "the equation is the plugin's approximate model (Persson's kernel unavailable)",
    )


if __name__ == "__main__":
    for r in rows("--fast" in sys.argv):
        print(f"{r['output']:28s} {r['worst']:10.3g} {r['measure']:10s} {r['note']}")
