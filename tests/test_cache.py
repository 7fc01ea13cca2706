"""The one cache mechanism (xpersson.cache) and its switch (xpersson.options)."""

from __future__ import annotations

import json
import pickle
import threading
import warnings
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import xpersson
from xpersson import cache as xc
from xpersson import options
from xpersson.options import CACHE_ENV, cache_enabled


@pytest.fixture(autouse=True)
def _caches_on() -> Iterator[None]:
    """The caches on (also in CI's run with XPERSSON_CACHE=off); tests turn them off inside."""
    with xpersson.set_options(cache=True):
        yield


@pytest.fixture(autouse=True)
def _environment_read_again() -> Iterator[None]:
    """Set up first, torn down last: after monkeypatch has restored the environment, the
    options read it again (they keep what they read)."""
    yield
    options._FROM_ENV.clear()


def _fresh(name: str, **kw: object) -> xc.Cache:
    try:
        old = xc.cache(name)
    except KeyError:
        return xc.Cache(name, **kw)  # type: ignore[arg-type]
    old.clear()
    return old


def test_content_key_distinguishes_bits_not_identity() -> None:
    assert xc.content_key(0.0) != xc.content_key(-0.0)
    a = np.arange(4.0)
    assert xc.content_key(a) == xc.content_key(a.copy())
    assert xc.content_key(a) != xc.content_key(a.astype(np.float32))
    assert xc.content_key(a) != xc.content_key(a.reshape(2, 2))
    assert xc.content_key((1, "x", None)) == (1, "x", None)

    class Opaque:
        pass

    with pytest.raises(TypeError, match="cannot key a cache on the content"):
        xc.content_key(Opaque())
    with pytest.raises(TypeError):
        xc.content_key(lambda: 0)


def test_content_key_keeps_types_byte_orders_and_bits_apart() -> None:
    """A float keys by its bits (never as the equal int), an array by its dtype (byte order
    too, for seen and unseen dtypes, small and digested), a NaN as its own bits."""
    assert xc.content_key(1.0) != xc.content_key(1)
    assert xc.content_key((1.0, "x")) != xc.content_key((1, "x"))
    nan = float("nan")
    assert xc.content_key(nan) == xc.content_key(float("nan"))
    assert xc.content_key(nan) != xc.content_key(-nan)
    for n in (4, 1000):  # kept as bytes, and digested
        a = np.arange(float(n))
        big = a.astype(">f8")
        assert xc.content_key(a) == xc.content_key(a.copy())
        assert xc.content_key(big) != xc.content_key(a)
        assert xc.content_key(big) == xc.content_key(big.copy())
        assert xc.content_key(a.view(np.int64)) != xc.content_key(a)
    with pytest.raises(TypeError):  # an object array is refused as before, also once seen
        for _ in range(2):
            xc.content_key((np.array([object()], dtype=object),))


@given(st.lists(st.floats(allow_nan=False, allow_infinity=False), min_size=1, max_size=8))
def test_content_key_equal_iff_equal_bits(values: list[float]) -> None:
    a = np.array(values)
    b = a.copy()
    assert xc.content_key(a) == xc.content_key(b)
    b[0] = np.nextafter(b[0], np.inf)
    assert xc.content_key(a) != xc.content_key(b)


def test_bounded_lru_and_read_only_values() -> None:
    c = _fresh("test.lru", scope="process", maxsize=2)
    calls: list[int] = []

    def make(k: int) -> np.ndarray:
        calls.append(k)
        return np.full(3, float(k))

    for k in (1, 2, 1, 3, 1, 2):
        v = c.get(k, lambda k=k: make(k))
        assert not v.flags.writeable
        assert v[0] == k
    assert calls == [1, 2, 3, 2]  # 2 was dropped when 3 came (1 had been used more recently)
    assert len(c) == 2


def test_solve_scope_keeps_values_only_inside() -> None:
    c = _fresh("test.solve", scope="solve", maxsize=8)
    n = [0]

    def make() -> int:
        n[0] += 1
        return n[0]

    assert c.get("k", make) == 1 and c.get("k", make) == 2  # outside a solve: nothing kept
    with xc.solve_scope():
        assert c.get("k", make) == 3 and c.get("k", make) == 3
        with xc.solve_scope():  # a nested solve has its own store
            assert c.get("k", make) == 4
        assert c.get("k", make) == 3
    assert c.get("k", make) == 5


def test_switch_turns_every_cache_off(monkeypatch: pytest.MonkeyPatch) -> None:
    c = _fresh("test.switch", scope="process", maxsize=8)
    n = [0]

    def make() -> np.ndarray:
        n[0] += 1
        return np.zeros(2)

    with xpersson.set_options(cache=False):
        assert not xpersson.get_options()["cache"]
        v = c.get("k", make)
        c.get("k", make)
        assert n[0] == 2 and not v.flags.writeable  # read-only also when not kept
    c.get("k", make)
    c.get("k", make)
    assert n[0] == 3
    monkeypatch.setenv(CACHE_ENV, "off")
    with xpersson.set_options(cache=None):  # back to the default: the environment variable
        assert not cache_enabled()
        with xpersson.set_options(cache=True):
            assert cache_enabled()
        monkeypatch.setenv(CACHE_ENV, "sometimes")
        xpersson.set_options(cache=None)
        with pytest.raises(ValueError, match=CACHE_ENV):
            cache_enabled()
    with pytest.raises(ValueError, match="unknown option"):
        xpersson.set_options(cash=False)
    with pytest.raises(ValueError, match="'cache' must be a bool"):
        xpersson.set_options(cache="no")


def test_memoize_and_pickle_by_name() -> None:
    calls: list[tuple] = []

    @xc.memoize("test.memoize", maxsize=4)
    def f(x: float, *, scale: float = 1.0) -> float:
        calls.append((x, scale))
        return x * scale

    assert f(2.0, scale=3.0) == f(2.0, scale=3.0) == 6.0
    assert f(np.float64(2.0), scale=3.0) == 6.0  # a numpy scalar keys as the Python number
    assert len(calls) == 1
    assert pickle.loads(pickle.dumps(f.cache)) is f.cache  # type: ignore[attr-defined]
    assert any(i.name == "test.memoize" for i in xc.caches())
    with pytest.raises(ValueError, match="exists already"):
        xc.Cache("test.memoize", scope="process", maxsize=1)
    with pytest.raises(ValueError, match="scope"):
        xc.Cache("test.badscope", scope="forever", maxsize=1)


def test_threads_get_one_value() -> None:
    c = _fresh("test.threads", scope="process", maxsize=4)
    got: list[object] = []
    barrier = threading.Barrier(8)

    def work() -> None:
        barrier.wait()
        got.append(c.get("k", lambda: np.ones(10_000)))

    threads = [threading.Thread(target=work) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len({id(v) for v in got}) >= 1
    kept = c.get("k", lambda: np.zeros(1))
    assert all(np.array_equal(v, kept) for v in got)


# -- the caches do not change results ------------------------------------------------------------
ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted(ROOT.glob("examples/*.toml")) + sorted(ROOT.glob("plugins/*/examples/*.toml"))
#: global attributes that differ from run to run (time stamps, run ids, timings)
VOLATILE = ("history", "date_created", "date_modified", "environment", "run_id", "provenance")


def _steady(value: Any) -> Any:
    """An attribute without its timings (JSON keys naming a time, e.g. ``wall_time_s``)."""

    def drop(obj: Any) -> Any:
        if isinstance(obj, dict):
            return {k: drop(v) for k, v in obj.items() if "time" not in k}
        return [drop(v) for v in obj] if isinstance(obj, list) else obj

    if isinstance(value, str) and value.startswith("{"):
        try:
            return drop(json.loads(value))
        except ValueError:
            return value
    return value


def _values(ds: Any) -> dict[str, Any]:
    """Every variable's dims, dtype and bytes, its attributes, and the steady global attrs."""
    out: dict[str, Any] = {}
    for name, var in ds.variables.items():
        arr = np.asarray(var.values)
        data = repr(arr.tolist()) if arr.dtype.kind == "O" else arr.tobytes()
        out[str(name)] = (var.dims, arr.dtype.str, arr.shape, data, repr(sorted(var.attrs.items())))
    steady = [(k, _steady(v)) for k, v in ds.attrs.items() if k not in VOLATILE]
    out[".attrs"] = repr(sorted(steady))
    return out


def _solve(path: Path) -> dict[str, Any]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return _values(xpersson.solve(path))


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.stem)
def test_examples_are_bitwise_equal_with_caches_on_warm_and_off(path: Path) -> None:
    """A cold solve (caches emptied), a warm one (the same process, caches filled) and one with
    every cache off give the same bits: no result depends on what was solved before."""
    with xpersson.set_options(cache=True):
        xc.clear_caches()
        cold = _solve(path)
        warm = _solve(path)
        assert any(i.size for i in xc.caches() if i.scope != "solve")  # the caches were used
    with xpersson.set_options(cache=False):
        off = _solve(path)
    assert warm.keys() == cold.keys() == off.keys()
    for name in cold:
        assert warm[name] == cold[name], f"{path.name}: {name} differs when the caches are warm"
        assert off[name] == cold[name], f"{path.name}: {name} differs with the caches off"


def test_every_cache_is_named_scoped_and_bounded() -> None:
    """The caches of the core and the plugins (imported by the example solves): dotted names,
    a known scope, a bound; none keeps anything with the caches off."""
    for path in EXAMPLES[:1]:
        _solve(path)
    found = {i.name: i for i in xc.caches() if not i.name.startswith("test.")}
    assert {"physics.spectrum_moments", "units.str_to_si", "checks.spectrum"} <= set(found)
    for info in found.values():
        assert "." in info.name and info.scope in xc.SCOPES and info.maxsize >= 1
    with xpersson.set_options(cache=False):
        xc.clear_caches()
        _solve(EXAMPLES[0])
        assert all(i.size == 0 for i in xc.caches())


def test_fast_paths_option_and_plain_paths(monkeypatch: pytest.MonkeyPatch) -> None:
    """``set_options(fast_paths=False)``, ``XPERSSON_FAST_PATHS=off`` and ``plain_paths()`` each
    send everything down the plain path; blocks nest."""
    from xpersson.options import FAST_PATHS_ENV
    from xpersson.plugins import fast_paths_on, plain_paths

    monkeypatch.delenv(FAST_PATHS_ENV, raising=False)
    xpersson.set_options(fast_paths=None)
    assert fast_paths_on() and xpersson.get_options()["fast_paths"]
    with xpersson.set_options(fast_paths=False):
        assert not fast_paths_on()
    with plain_paths():
        with plain_paths():
            assert not fast_paths_on()
        assert not fast_paths_on()
    assert fast_paths_on()
    monkeypatch.setenv(FAST_PATHS_ENV, "off")
    xpersson.set_options(fast_paths=None)
    assert not fast_paths_on()
    with xpersson.set_options(fast_paths=True):
        assert fast_paths_on()
