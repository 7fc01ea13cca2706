"""Import cost: ``import xpersson``, ``xpersson validate`` and a serial closed-form solve load
none of the optional heavy packages (each checked in a fresh interpreter); simple SI
quantities are converted without pint, to the float pint gives."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from xpersson.units import _simple_si, _to_si

OPTIONAL = ["dask", "distributed", "matplotlib", "tqdm", "SurfaceTopography"]
ROOT = Path(__file__).resolve().parents[1]
SCENE = """
[spectrum]
model = "self_affine"
H = 0.8
q_L = "1e3 1/m"
q_r = "1e4 1/m"
q_1 = "1e8 1/m"
h_rms = "1 um"
[material]
E = "10 MPa"
nu = 0.5
[load]
p0 = ["10 kPa", "1 MPa"]
[analyses.contact_area]
"""


def _loaded_after(code: str, watch: list[str], tmp_path: Path) -> list[str]:
    """The modules of ``watch`` present in ``sys.modules`` after running ``code`` in a fresh
    interpreter (the test's own import path)."""
    (tmp_path / "scene.toml").write_text(SCENE)
    report = f"print(__import__('json').dumps([m for m in {watch!r} if m in sys.modules]))"
    script = f"import sys\n{code}\n{report}"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    out = subprocess.run(
        [sys.executable, "-c", script],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        check=True,
        timeout=300,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def test_import_xpersson_loads_no_heavy_package(tmp_path):
    watch = [*OPTIONAL, "xarray", "pint", "scipy", "numpy"]
    assert _loaded_after("import xpersson", watch, tmp_path) == []


def test_validate_loads_no_optional_package(tmp_path):
    code = (
        "from xpersson.cli import main\n"
        "try:\n    main(['validate', 'scene.toml'])\nexcept SystemExit:\n    pass"
    )
    assert _loaded_after(code, [*OPTIONAL, "pint"], tmp_path) == []


def test_closed_form_solve_loads_no_optional_package(tmp_path):
    """xarray itself imports dask's core (``dask``, ``dask.array``) and pint when it builds
    the first index (its duck-array checks), so those two are not asserted here."""
    code = "import xpersson\nxpersson.solve('scene.toml')"
    watch = ["distributed", "matplotlib", "tqdm", "SurfaceTopography", "scipy.integrate"]
    assert _loaded_after(code, watch, tmp_path) == []


_UNITS = [
    ("MPa", "Pa"),
    ("kPa", "Pa"),
    ("GPa", "Pa"),
    ("um", "m"),
    ("nm", "m"),
    ("cm", "m"),
    ("1/m", "1/m"),
    ("1/um", "1/m"),
    ("cm/s", "m/s"),
    ("mJ/m**2", "J/m**2"),
    ("mPa*s", "Pa*s"),
    ("nm**4", "m**4"),
    ("ms", "s"),
]


@settings(max_examples=300, deadline=None)
@given(
    x=st.floats(min_value=-1e12, max_value=1e12, allow_nan=False, allow_infinity=False),
    pair=st.sampled_from(_UNITS),
)
def test_simple_si_equals_pint(x, pair):
    unit, target = pair
    text = f"{x!r} {unit}"
    assert _simple_si(text, target) == _to_si(text, target, "", False)


@pytest.mark.parametrize(
    ("text", "unit"),
    [("1 bar", "Pa"), ("3 MPa", "m"), ("1 Pa", "1"), ("nan Pa", "Pa"), ("2 W/(m*K)", "W/(m*K)")],
)
def test_simple_si_leaves_the_rest_to_pint(text, unit):
    assert _simple_si(text, unit) is None
