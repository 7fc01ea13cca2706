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
SCENE_DICT = {
    "spectrum": {
        "model": "self_affine",
        "H": 0.8,
        "q_L": "1e3 1/m",
        "q_r": "1e4 1/m",
        "q_1": "1e8 1/m",
        "h_rms": "1 um",
    },
    "material": {"E": "10 MPa", "nu": 0.5},
    "load": {"p0": ["10 kPa", "1 MPa"]},
}


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
    """xarray itself imports dask's core (``dask``) and pint when it builds the first index
    (its duck-array checks), so those two are not asserted here."""
    code = "import xpersson\nxpersson.solve('scene.toml')"
    watch = ["distributed", "matplotlib", "tqdm", "SurfaceTopography", "scipy.integrate"]
    assert _loaded_after(code, watch, tmp_path) == []


#: What the closed-form path does not need: the numerical methods' scipy modules
#: (interpolation, root finding, banded solves), the other engine methods, the sweep's block
#: and folder code, and dask.array (xarray imports it when it meets an object it must convert).
NOT_ON_THE_CLOSED_FORM_PATH = [
    "scipy.interpolate",
    "scipy.optimize",
    "scipy.linalg",
    "scipy.sparse",
    "scipy.fft",
    "dask.array",
    "xpersson.engine._cn",
    "xpersson.engine._sourced",
    "xpersson.engine._markov",
    "xpersson.engine._sine",
    "xpersson.sweep.blocks",
    "xpersson.sweep.execute",
]


@pytest.mark.parametrize("p0", ["'1 MPa'", "['10 kPa', '1 MPa']"])
def test_closed_form_solve_skips_what_it_does_not_need(tmp_path, p0):
    code = (
        "import xpersson\n"
        "xpersson.solve({'spectrum': {'model': 'self_affine', 'H': 0.8, 'q_L': '1e3 1/m',"
        " 'q_r': '1e4 1/m', 'q_1': '1e8 1/m', 'h_rms': '1 um'},"
        f" 'material': {{'E': '10 MPa', 'nu': 0.5}}, 'load': {{'p0': {p0}}}}})"
    )
    assert _loaded_after(code, NOT_ON_THE_CLOSED_FORM_PATH, tmp_path) == []


def test_validate_imports_neither_xarray_nor_the_solver_modules(tmp_path):
    code = (
        "from xpersson.cli import main\n"
        "try:\n    main(['validate', 'scene.toml'])\nexcept SystemExit:\n    pass"
    )
    watch = ["xarray", "pandas", "xpersson.pipeline", *NOT_ON_THE_CLOSED_FORM_PATH]
    assert _loaded_after(code, watch, tmp_path) == []


def test_opening_an_archive_file_imports_no_solver(tmp_path):
    import xpersson

    xpersson.to_netcdf(xpersson.solve(SCENE_DICT), tmp_path / "a.nc")
    code = "import xpersson\nxpersson.open_dataset('a.nc')"
    watch = ["xpersson.pipeline", "xpersson.physics", "xpersson.engine", "xpersson.sweep.blocks"]
    assert _loaded_after(code, watch, tmp_path) == []


def test_lazy_names_resolve_to_their_modules():
    """Every public name of the lazily loaded packages resolves, to the object of the
    module that defines it; the method table behaves as the dict it was."""
    import xpersson.engine as engine
    import xpersson.io as io
    import xpersson.sweep as sweep
    from xpersson.engine._cn import CNMethod
    from xpersson.engine._markov import MarkovMethod
    from xpersson.engine._methods import METHODS, get_method, register_method
    from xpersson.engine._sourced import solve_sourced
    from xpersson.sweep.execute import solve_sweep
    from xpersson.sweep.parts import open_parts

    assert all(getattr(engine, n) is not None for n in engine.__all__)
    assert all(getattr(sweep, n) is not None for n in sweep.__all__)
    assert engine.CNMethod is CNMethod and engine.solve_sourced is solve_sourced
    assert sweep.solve_sweep is solve_sweep and io.open_parts is open_parts is sweep.open_parts
    assert {"cn", "exact", "markov", "markov_ck", "sine"} <= set(METHODS)  # other tests add
    assert METHODS["cn"] is CNMethod and get_method("markov") is MarkovMethod
    assert dict(METHODS)["cn"] is CNMethod and "cn" in METHODS and "auto" not in METHODS
    register_method("lazy_test", CNMethod)
    assert METHODS.pop("lazy_test") is CNMethod and "lazy_test" not in METHODS
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        engine.nope  # noqa: B018
    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        sweep.nope  # noqa: B018


def test_one_scan_discovery_equals_per_group_entry_points():
    """Discovery reads the installed entry points once per pass: per group it finds exactly
    what ``importlib.metadata.entry_points(group=...)`` lists."""
    from importlib.metadata import entry_points

    from xpersson.plugins import ENTRY_POINT_PREFIX, GROUP_NAMES, _discovery, _metadata

    for group in GROUP_NAMES:
        ours = _discovery._entry_points(ENTRY_POINT_PREFIX + group)
        theirs = list(entry_points(group=ENTRY_POINT_PREFIX + group))
        assert sorted((e.name, e.value) for e in ours) == sorted((e.name, e.value) for e in theirs)
        for ep in ours:
            dist = ep.dist
            assert _metadata.dist_of(ep) == (dist.metadata["Name"], dist.version)


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


def test_info_on_an_archive_imports_neither_dask_array_nor_a_solver(tmp_path):
    """``xpersson info`` decodes the flag strings and prints one column per load with numpy:
    xarray's converting constructors and ``isel`` would import ``dask.array`` (~0.1 s)."""
    import xpersson

    xpersson.to_netcdf(xpersson.solve(SCENE_DICT), tmp_path / "a.nc")
    code = (
        "import contextlib, io\nfrom xpersson.cli import main\n"
        "with contextlib.redirect_stdout(io.StringIO()) as out:\n    main(['info', 'a.nc'])\n"
        "assert 'area_fraction' in out.getvalue() and 'status: success' in out.getvalue()"
    )
    watch = ["dask.array", "xpersson.pipeline", "xpersson.engine", "matplotlib"]
    assert _loaded_after(code, watch, tmp_path) == []
