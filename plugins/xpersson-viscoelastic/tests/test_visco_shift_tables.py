"""Time-temperature shifts (WLF, Arrhenius, table) and the table readers' refusals."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from xpersson_viscoelastic import (
    GAS_CONSTANT,
    WLF,
    WLF_UNIVERSAL,
    Arrhenius,
    TableError,
    ViscoelasticCoefficient,
    load_master_curve,
    load_prony,
    load_shift_table,
)


@pytest.mark.parametrize("T", [200.0, 230.0, 251.3, 273.15, 330.0])
def test_wlf_universal_constants_match_the_formula(T):
    Tg = 230.0
    dT = Fraction(T) - Fraction(Tg)
    exact = -Fraction("17.44") * dT / (Fraction("51.6") + dT)  # exact rational arithmetic
    got = WLF(*WLF_UNIVERSAL, T_ref=Tg).log10_aT(T)
    assert abs(float(got) - float(exact)) <= 1e-12 * max(1.0, abs(float(exact)))
    # the coefficient's defaults are the universal constants
    coef = ViscoelasticCoefficient(velocity=1.0, temperature=T, shift="wlf", T_ref=Tg)
    assert coef.shift_factor == pytest.approx(10.0 ** float(exact), rel=1e-12)


def test_wlf_refuses_temperatures_below_its_pole():
    with pytest.raises(ValueError, match=r"temperature: 170 K .* = \(178.4, inf\) K"):
        ViscoelasticCoefficient(velocity=1.0, temperature=170.0, shift="wlf", T_ref=230.0)


def test_arrhenius_formula_and_direction():
    law = Arrhenius(60e3, 293.15)
    T = np.array([263.15, 293.15, 323.15])
    ln_aT = 60e3 / GAS_CONSTANT * (1 / T - 1 / 293.15)
    np.testing.assert_allclose(law.log10_aT(T) * math.log(10), ln_aT, rtol=1e-13)
    assert law.aT(263.15) > 1 > law.aT(323.15)  # stiffer below T_ref


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


GOOD = """# a master curve
f [Hz], E_storage [MPa], E_loss [MPa]
1, 3.0, 0.1
10, 4.0, 0.5   # comment
100, 9.0, 2.0
"""


def test_master_curve_file_units_are_converted(tmp_path):
    mc = load_master_curve(_write(tmp_path, "mc.txt", GOOD))
    np.testing.assert_allclose(mc.omega, 2 * np.pi * np.array([1.0, 10.0, 100.0]))
    np.testing.assert_allclose(mc.storage, [3e6, 4e6, 9e6])
    np.testing.assert_allclose(mc.loss_modulus, [1e5, 5e5, 2e6])


@pytest.mark.parametrize(
    ("text", "line", "what"),
    [
        (GOOD.replace("100, 9.0, 2.0", "100, 9.0, -2.0"), 5, "E'' = -2e\\+06 Pa < 0"),
        (GOOD.replace("100, 9.0", "10, 9.0"), 5, "duplicate frequency"),
        (GOOD.replace("100, 9.0", "5, 9.0"), 5, "strictly increasing"),
        (GOOD.replace("E_loss [MPa]", "E_loss"), 2, "column 3 .* has no unit"),
        (GOOD.replace("f [Hz]", "f [m]"), 2, "not convertible to 1/s"),
        (GOOD.replace("10, 4.0", "10, four"), 4, "not a number"),
        (GOOD.replace("10, 4.0, 0.5", "10, 4.0"), 4, "expected 3 numbers"),
    ],
)
def test_malformed_master_curve_is_refused_naming_file_and_line(tmp_path, text, line, what):
    p = _write(tmp_path, "bad_curve.txt", text)
    with pytest.raises(TableError, match=rf"bad_curve\.txt, line {line}: .*{what}"):
        load_master_curve(p)


def test_malformed_master_curve_is_refused_by_the_scene(tmp_path):
    from visco_testlib import scene

    import xpersson

    p = _write(tmp_path, "bad.txt", GOOD.replace("100, 9.0, 2.0", "100, 9.0, -2.0"))
    sc = scene({"velocity": "1 m/s", "modulus": "master_curve", "master_curve": str(p)})
    with pytest.raises(ValueError, match=r"coefficient: .*bad\.txt, line 5: loss modulus"):
        xpersson.solve(sc)


def test_prony_and_shift_tables(tmp_path):
    dE, tau = load_prony(_write(tmp_path, "p.txt", "tau [ms], delta_E [MPa]\n1 2\n10 3\n"))
    np.testing.assert_allclose(tau, [1e-3, 1e-2])
    np.testing.assert_allclose(dE, [2e6, 3e6])
    law = load_shift_table(_write(tmp_path, "a.txt", "T [degC], a_T [1]\n0 100\n20 1\n40 0.01\n"))
    np.testing.assert_allclose(law.T, [273.15, 293.15, 313.15])
    assert law.aT(283.15) == pytest.approx(10.0, rel=1e-12)  # log-linear interpolation
    with pytest.raises(ValueError, match=r"temperature: 350 K .* allowed \[273.15, 313.15\] K"):
        law.check(350.0)
    with pytest.raises(TableError, match=r"p2\.txt, line 3: relaxation time 0.001 .*smaller"):
        load_prony(_write(tmp_path, "p2.txt", "tau [s], delta_E [Pa]\n0.01 2\n0.001 3\n"))
