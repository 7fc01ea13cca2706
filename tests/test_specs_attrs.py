"""A VarSpec's CF attributes are made once with the declaration: every call of ``attrs()``
returns what computing them from the fields gives, as a fresh dict (issue 36: the pipeline's
fixed cost; the attributes were formatted again for every output of every solve)."""

from __future__ import annotations

import re
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from xpersson.pipeline.diagnostics import DIAGNOSTICS
from xpersson.plugins import get_registry
from xpersson.plugins._groups import GROUP_NAMES
from xpersson.schema import COORDS, CORE_VARIABLES
from xpersson.specs import VarSpec, caret_units


def _every_varspec() -> list[tuple[str, VarSpec]]:
    """The schema's, the diagnostics' and every installed plugin's output declarations."""
    found = [(f"schema.{n}", s) for n, s in {**CORE_VARIABLES, **COORDS}.items()]
    found += [(f"diagnostics.{n}", s) for n, s in DIAGNOSTICS.items()]
    reg = get_registry()
    for group in GROUP_NAMES:
        for name in reg.names(group):
            cls = reg.load(group, name)
            found += [(f"{group}.{name}.{v}", s) for v, s in getattr(cls, "outputs", {}).items()]
    return found


def _same(a: dict[str, Any], b: dict[str, Any]) -> bool:
    if a.keys() != b.keys():
        return False
    for k, v in a.items():
        w = b[k]
        if isinstance(v, np.ndarray) or isinstance(w, np.ndarray):
            if not (
                isinstance(v, np.ndarray)
                and isinstance(w, np.ndarray)
                and v.dtype == w.dtype
                and np.array_equal(v, w)
            ):
                return False
        elif type(v) is not type(w) or v != w:
            return False
    return True


SPECS = _every_varspec()


@pytest.mark.parametrize("label,spec", SPECS, ids=[label for label, _ in SPECS])
def test_attrs_made_once_equal_the_computed_ones(label: str, spec: VarSpec) -> None:
    first, second = spec.attrs(), spec.attrs()
    assert _same(first, spec.cf_attrs()), label
    assert first is not second  # a fresh dict: a caller's change does not reach the next
    first["units"] = "changed"
    if isinstance(first.get("flag_values"), np.ndarray):
        assert first["flag_values"] is not second["flag_values"]
        second["flag_values"][...] = 0  # a caller may write into its copy
    assert _same(spec.attrs(), spec.cf_attrs()), label


def test_malformed_declaration_still_fails_in_check_not_when_made() -> None:
    from xpersson.specs import SpecError

    bad = VarSpec(("p0",), None, "x")  # type: ignore[arg-type]
    with pytest.raises(SpecError, match="units"):
        bad.check("Demo", "x")
    with pytest.raises((TypeError, AttributeError)):
        bad.attrs()  # computed at the call, as before


def _caret_by_template(units: str) -> str:
    """The former implementation (``re.Match.expand`` of a template)."""
    power = re.compile(r"^([A-Za-z_]+)(-?[0-9]+)$")
    return (
        " ".join(m.expand(r"\1^\2") if (m := power.match(t)) else t for t in units.split()) or units
    )


@given(
    st.lists(
        st.tuples(
            st.sampled_from(["Pa", "m", "s", "K", "W", "J", "kg", "mol", "A_b", "1"]),
            st.sampled_from(["", "2", "-1", "-2", "3", "10", "^2", "**2", "0"]),
        ),
        max_size=4,
    )
)
def test_caret_units_as_before(terms: list[tuple[str, str]]) -> None:
    units = " ".join(a + b for a, b in terms)
    assert caret_units(units) == _caret_by_template(units)
