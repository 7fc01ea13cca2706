"""Archives pass the IOOS compliance-checker (cf:1.11, acdd:1.3) as a real client runs it.

Every bundled example scene (core and first-party plugins), the seal example with every
interface analysis, and a sweep (one file and its netCDF parts): zero CF errors, and no highly
recommended ACDD attribute missing except ``standard_name`` (CF has none for these
quantities).
"""

from __future__ import annotations

from pathlib import Path

import pytest

import xpersson

checker = pytest.importorskip("compliance_checker.runner")

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted([*ROOT.glob("examples/*.toml"), *ROOT.glob("plugins/*/examples/*.toml")])


@pytest.fixture(scope="module")
def suite():
    cs = checker.CheckSuite()
    cs.load_all_available_checkers()
    return cs


def _problems(suite, path: Path) -> list[str]:
    ds = suite.load_dataset(str(path))
    groups = suite.run_all(ds, ["cf:1.11", "acdd:1.3"], skip_checks=[])
    out = []
    for name, (results, errors) in groups.items():
        out += [f"{name}: checker error {e}" for e in errors]
        for r in results:
            ok = r.value if isinstance(r.value, bool) else r.value[0] == r.value[1]
            if ok or r.weight < 3:
                continue
            msgs = [m for m in r.msgs if m != "standard_name"]
            if msgs or not r.msgs:
                out.append(f"{name}: {r.name}: {msgs}")
    return out


def _scene(path: Path) -> xpersson.Scene:
    sc = xpersson.load_scene(path)
    load = sc.data.get("load", {}).get("p0")
    if isinstance(load, dict):  # keep the test fast: fewer loads, same outputs
        sc.data["load"]["p0"] = {**load, "num": 4}
    if path.name == "rubber_seal.toml":
        sc.data["analyses"].update(
            {"gap_pdf": {"u_points": 32}, "elastic_energy": {}, "contact_stiffness": {}}
        )
    return sc


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.parent.parent.name + "/" + p.name)
def test_example_archives_pass_cf_and_acdd(suite, example, tmp_path):
    path = xpersson.to_netcdf(xpersson.solve(_scene(example)), tmp_path / "out.nc")
    assert _problems(suite, path) == []


def test_sweep_parts_pass_cf_and_acdd(suite, tmp_path):
    sc = _scene(ROOT / "examples" / "sweep.toml")
    sc.data["output"] = {"pressure_pdf": True, "p_points": 16, "zeta_per_decade": 2}
    xpersson.solve(sc, output=tmp_path / "parts", chunk=3)
    parts = sorted((tmp_path / "parts").glob("part-*.nc"))
    assert len(parts) == 3  # blocks of whole rows: 3 H x 2 E
    assert _problems(suite, parts[0]) == []
