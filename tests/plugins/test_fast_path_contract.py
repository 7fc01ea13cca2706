"""The declared fast-path contract (issue 33): checked at class creation, not inherited, and
every declared path checked by ``check_plugin`` against the plain path."""

from __future__ import annotations

import numpy as np
import pytest

from xpersson.builtin.area import ContactArea
from xpersson.builtin.elastic import ElasticBoundary, ElasticCoefficient
from xpersson.engine import Wall
from xpersson.options import cache_enabled
from xpersson.plugins import (
    NO_FAST_PATHS,
    Analysis,
    Boundary,
    FastPaths,
    SpecError,
    fast_paths_on,
    plain_paths,
)
from xpersson.testing import check_fast_paths, check_plugin
from xpersson.testing.fastpaths import RTOL

# -- test doubles whose declared fast path differs from the plain path by 1e-9 -----------------


class CreepingWall(ElasticBoundary):
    """Declares shared walls, but its wall moves with the load by 1e-9 of it."""

    summary = "absorbing wall at p = -1e-9 p0 (test double: not a shared wall)"
    fast_paths = FastPaths(shared_walls=True)

    def walls(self, ctx, p0, clock):
        return Wall.absorbing(-1e-9 * p0), None


class CountingWall(ElasticBoundary):
    """Declares reuse, but moves its wall 1e-9 of the load lower at every call: a later solve
    of the same instance differs from a fresh one's (a call changes what a later one gives)."""

    summary = "absorbing wall at p = -1e-9 p0 calls (test double: not reusable)"
    fast_paths = FastPaths(reused=True)

    def __init__(self, **params):
        super().__init__(**params)
        self.calls = [0]

    def walls(self, ctx, p0, clock):
        self.calls[0] += 1
        return Wall.absorbing(-1e-9 * p0 * self.calls[0]), None


def test_check_plugin_fails_on_a_broken_promise_of_reuse():
    if cache_enabled() and fast_paths_on():
        with pytest.raises(AssertionError, match="fast path 'reused'"):
            check_fast_paths(CountingWall, {})
    else:  # nothing is reused with the caches or fast paths off: no promise to break
        assert check_fast_paths(CountingWall, {})["fast_paths.reused"].startswith("ok")
    plain = type("CountingWall", (CountingWall,), {"__module__": __name__})
    assert check_fast_paths(plain, {}) == {}  # undeclared: resolved afresh at every solve


class CountingArea(ContactArea):
    """Declares reuse, but each compute of the same instance scales kappa by its count: a
    second solve on the reused instance differs from a fresh one's."""

    summary = "contact area counting its computes (test double: not reusable)"
    fast_paths = FastPaths(reused=True)

    def __init__(self, **params):
        super().__init__(**params)
        self.calls = [0]

    def compute(self, ctx, ds):
        self.calls[0] += 1
        out = super().compute(ctx, ds)
        dims, kappa = out["kappa"]
        out["kappa"] = (dims, kappa * self.calls[0])
        return out


def test_check_plugin_fails_on_an_analysis_that_breaks_reuse():
    if cache_enabled() and fast_paths_on():
        with pytest.raises(AssertionError, match="fast path 'reused'"):
            check_fast_paths(CountingArea, {})
    else:  # nothing is reused with the caches or fast paths off
        assert check_fast_paths(CountingArea, {})["fast_paths.reused"].startswith("ok")


class OffByOnePpb(ContactArea):
    """Declares a stacked path whose compute_stacked adds 1e-9 to the mean pressure."""

    summary = "contact area whose stacked path is off by 1e-9 (test double)"
    fast_paths = FastPaths(stacked_params=frozenset())

    def compute_stacked(self, ctx_of, ds):
        out = super().compute_stacked(ctx_of, ds)
        out["mean_contact_pressure"] = out["mean_contact_pressure"] * (1 + 1e-9)
        return out


class TauOffByOnePpb(ElasticCoefficient):
    """Declares shared tau, but its effective tau is 1e-9 above tau(zeta) at the larger loads."""

    summary = "elastic coefficient whose effective tau is off by 1e-9 (test double)"
    fast_paths = FastPaths(shared_tau=True)

    def effective_tau(self, ctx, zeta):
        tau = np.asarray(self.tau(ctx, zeta), dtype=float)
        bump = 1 + 1e-9 * (ctx.p0 > ctx.p0.min())
        return bump[:, None] * tau[None, :]


class NotQuiteSimilar(ContactArea):
    """Declares contact similarity, but its mean pressure depends on E* beyond its unit."""

    summary = "contact area that breaks similarity by 1e-9 (test double)"
    fast_paths = FastPaths(contact_similarity=True)

    def compute(self, ctx, ds):
        out = super().compute(ctx, ds)
        dims, mean_p = out["mean_contact_pressure"]
        return {**out, "mean_contact_pressure": (dims, mean_p * (1 + 1e-9 * ctx.E_star / 1e7))}


@pytest.mark.fast_paths
@pytest.mark.parametrize(
    ("cls", "path", "variable"),
    [
        (CreepingWall, "shared_walls", "walls()[0] position"),
        (OffByOnePpb, "stacked", "mean_contact_pressure"),
        (TauOffByOnePpb, "shared_tau", "effective_tau rows"),
        (NotQuiteSimilar, "contact_similarity", "mean_contact_pressure"),
    ],
)
def test_check_plugin_fails_on_a_fast_path_off_by_1e9(cls, path, variable):
    with pytest.raises(AssertionError) as err:
        check_plugin(cls, cheap_import=False, markov=0)
    msg = str(err.value)
    assert cls.__qualname__ in msg and f"fast path {path!r}" in msg and repr(variable) in msg
    rel = float(msg.split("max relative difference ")[1].split()[0])
    assert 1e-10 < rel < 1e-8  # the 1e-9 it was given, named


def test_the_test_doubles_pass_without_their_declaration():
    """The same classes declaring nothing pass: the failure above is the fast path's."""
    for cls in (CreepingWall, OffByOnePpb, TauOffByOnePpb, NotQuiteSimilar):
        plain = type(cls.__name__, (cls,), {"__module__": __name__})
        assert plain.fast_paths is NO_FAST_PATHS
        assert check_fast_paths(plain, {}) == {}


def test_first_party_declared_paths_pass_and_are_reported():
    report = check_fast_paths(ElasticBoundary, {})
    assert set(report) == {
        "fast_paths.contact_similarity",
        "fast_paths.stacked",
        "fast_paths.shared_walls",
        "fast_paths.reused",
    }
    assert all(v.startswith("ok") for v in report.values()), report
    assert RTOL == 1e-12


# -- the declaration is checked when the class is created --------------------------------------


def _boundary(**attrs):
    body = {"summary": "test double", "__module__": __name__, **attrs}
    return type("Misdeclared", (Boundary,), body)


@pytest.mark.parametrize(
    ("attrs", "fix"),
    [
        ({"wall_per_load": False}, "fast_paths = FastPaths(shared_walls=True)"),
        ({"walls_per_load": False}, "fast_paths = FastPaths(shared_walls=True)"),
        ({"pressure_scaled": True}, "fast_paths = FastPaths(contact_similarity=True)"),
        ({"batched": frozenset()}, "fast_paths = FastPaths(stacked_params="),
        ({"tau_per_load": False}, "fast_paths = FastPaths(shared_tau=True)"),
        ({"shared_walls": True}, "fast_paths = FastPaths(shared_walls=...)"),
        ({"shared_wall": True}, "fast_paths = FastPaths(shared_walls=...)"),
        ({"fast_path": FastPaths()}, "fast_paths = FastPaths(...)"),
        ({"tau_per_load": property(lambda self: False)}, "FastPaths(shared_tau=True)"),
    ],
)
def test_a_misspelled_or_leftover_declaration_fails_at_class_creation(attrs, fix):
    with pytest.raises(SpecError) as err:
        _boundary(**attrs)
    msg = str(err.value)
    assert "Misdeclared" in msg and repr(next(iter(attrs))) in msg and fix in msg


@pytest.mark.parametrize(
    ("fp", "why"),
    [
        ("shared_walls", "must be a FastPaths"),
        (FastPaths(shared_walls=1), "shared_walls must be True or False"),
        (FastPaths(stacked_params=frozenset({"s"})), "['s'] are not parameters of the class"),
        (FastPaths(stacked_params="s"), "must be None or a frozenset"),
        (FastPaths(shared_tau=True), "shared_tau applies to coefficients only, not boundaries"),
    ],
)
def test_a_malformed_declaration_fails_at_class_creation(fp, why):
    with pytest.raises(SpecError, match="Misdeclared") as err:
        _boundary(fast_paths=fp)
    assert why in str(err.value)


def test_shared_tau_condition_names_a_parameter_and_one_of_its_choices():
    for cond, why in (
        ({"closur": "persson01"}, "'closur', not a parameter"),
        ({"closure": "x"}, "choices"),
    ):
        with pytest.raises(SpecError, match=why):
            type("Bad", (ElasticCoefficient,), {"fast_paths": FastPaths(shared_tau=cond)})


def test_the_declaration_is_not_inherited():
    sub = type("Sub", (ElasticBoundary,), {"summary": "subclass", "__module__": __name__})
    assert sub.fast_paths is NO_FAST_PATHS and sub.fast_paths.declared() == ()
    assert ElasticBoundary.fast_paths.declared() == (
        "contact_similarity",
        "stacked",
        "shared_walls",
        "reused",
    )


@pytest.mark.fast_paths
def test_shared_tau_follows_the_instance_parameters():
    from xpersson.pipeline.stages import shared_tau

    assert shared_tau(ElasticCoefficient())
    assert not shared_tau(ElasticCoefficient(closure="yp08"))
    with plain_paths():
        assert not shared_tau(ElasticCoefficient())


@pytest.mark.fast_paths
def test_plain_paths_nests_and_restores_on_error():
    assert fast_paths_on()
    with pytest.raises(RuntimeError), plain_paths():
        with plain_paths():
            assert not fast_paths_on()
        assert not fast_paths_on()
        raise RuntimeError("a failing solve")
    assert fast_paths_on()


def test_an_analysis_cannot_declare_shared_walls():
    with pytest.raises(SpecError, match="shared_walls applies to boundaries only"):
        type(
            "Wrong",
            (Analysis,),
            {"summary": "x", "provides": (), "fast_paths": FastPaths(shared_walls=True)},
        )
