"""No silent fallback where a precondition fails: an error or a computed value, said aloud
(issue 33, part 4). Each case makes the precondition fail on purpose."""

from __future__ import annotations

import errno
import os
import sys
import warnings
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import xpersson
from xpersson import memory
from xpersson.pipeline.frontend import spectrum_kinks
from xpersson.sweep import folder
from xpersson.testing import schema

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "sweep"))
from xpersson_sweep_testlib import scene  # noqa: E402

SWEEP = scene(spectrum={"H": [0.6, 0.8]})


# -- memory: the available memory unknown --------------------------------------------------


def _no_memory_report(monkeypatch: pytest.MonkeyPatch) -> None:
    def no_meminfo(*args: Any, **kw: Any) -> Any:
        raise FileNotFoundError("/proc/meminfo")

    def no_sysconf(name: str) -> int:
        raise ValueError(f"unrecognized configuration name {name!r}")

    monkeypatch.setattr(memory, "open", no_meminfo, raising=False)  # shadows the builtin
    monkeypatch.setattr(memory.os, "sysconf", no_sysconf)
    monkeypatch.setattr(memory, "_WARNED", [])
    monkeypatch.setattr(memory, "_AVAILABLE", [])
    monkeypatch.delenv("XPERSSON_MEMORY_BUDGET", raising=False)


def test_unknown_available_memory_warns_once_naming_how_to_state_the_budget(monkeypatch):
    _no_memory_report(monkeypatch)
    with pytest.warns(xpersson.XperssonWarning, match="XPERSSON_MEMORY_BUDGET") as rec:
        assert memory._read_available() == memory.UNKNOWN_AVAILABLE == 4 * 2**30
    assert "set_budget" in str(rec[0].message) and "4 GiB" in str(rec[0].message)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert memory._read_available() == memory.UNKNOWN_AVAILABLE  # once per process
        assert memory.budget() == int(memory.DEFAULT_FRACTION * memory.UNKNOWN_AVAILABLE)


def test_a_stated_budget_needs_no_memory_report(monkeypatch):
    _no_memory_report(monkeypatch)
    monkeypatch.setenv("XPERSSON_MEMORY_BUDGET", "1 GB")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert memory.budget() == 10**9


# -- sweep folder: a file system without locks ---------------------------------------------


@pytest.mark.parametrize("code", [errno.ENOLCK, errno.EOPNOTSUPP])
def test_a_folder_without_locks_is_used_with_a_warning_naming_it(monkeypatch, tmp_path, code):
    def no_locks(fd: int, op: int) -> None:
        raise OSError(code, os.strerror(code))

    monkeypatch.setattr(folder.fcntl, "flock", no_locks)
    out = tmp_path / "nolock"
    with pytest.warns(xpersson.XperssonWarning, match="does not support locks") as rec:
        ds = xpersson.solve(SWEEP, output=out)
    assert str(out) in str(rec[0].message) and "mix its parts" in str(rec[0].message)
    assert ds.point_status.values.tolist() == [0, 0]


def test_any_other_lock_error_is_raised(monkeypatch, tmp_path):
    def broken(fd: int, op: int) -> None:
        raise OSError(errno.EIO, "Input/output error")

    monkeypatch.setattr(folder.fcntl, "flock", broken)
    with pytest.raises(OSError, match="Input/output error"):
        xpersson.solve(SWEEP, output=tmp_path / "eio")


# -- the clock's kinks: only a spectrum without nodes gives none ----------------------------


class _Spectrum:
    q_L = 1e3

    def __init__(self, nodes: Any) -> None:
        self._nodes = nodes

    def nodes(self) -> np.ndarray:
        if isinstance(self._nodes, Exception):
            raise self._nodes
        return np.asarray(self._nodes)


def test_spectrum_kinks_of_spectra_with_and_without_nodes():
    assert spectrum_kinks(_Spectrum([1e3, 1e4, 1e5])) == (1.0, 10.0, 100.0)
    assert spectrum_kinks(object()) == ()  # no nodes(): no hint
    assert spectrum_kinks(_Spectrum(NotImplementedError())) == ()  # nodes not available
    assert spectrum_kinks(_Spectrum(np.arange(5000.0) + 1e3)) == ()  # too many: no hint


def test_spectrum_kinks_lets_a_broken_spectrum_raise():
    with pytest.raises(ValueError, match="corrupt table"):
        spectrum_kinks(_Spectrum(ValueError("corrupt table")))

    class NoQL(_Spectrum):
        q_L = property(lambda self: self.missing)  # type: ignore[assignment]

    with pytest.raises(AttributeError, match="missing"):
        spectrum_kinks(NoQL([1e3, 1e4]))


# -- the schema check: pint is a dependency, its failure is not a skip ---------------------


def test_assert_schema_raises_when_the_unit_registry_fails(monkeypatch):
    import xarray as xr

    ds = xr.Dataset({"x": ("p0", [1.0], {"units": "Pa", "long_name": "x"})})
    schema.assert_schema(ds.assign_coords(p0=("p0", [1.0], {"units": "Pa", "long_name": "p0"})))

    def broken() -> Any:
        raise RuntimeError("unit registry cannot be built")

    monkeypatch.setattr(schema, "ureg", broken)
    with pytest.raises(RuntimeError, match="unit registry cannot be built"):
        schema.assert_schema(ds)


def test_assert_schema_checks_units():
    import xarray as xr

    ds = xr.Dataset({"x": ((), 1.0, {"units": "furlongs per fortnight", "long_name": "x"})})
    with pytest.raises(AssertionError, match="do not parse"):
        schema.assert_schema(ds)
