"""Coefficient plugin ``viscoelastic``: f(zeta; v, T) of a rubber sliding on a rough surface.

Persson (2001), physics.md §4.2: ``G(q) = (1/8) int q'^3 C(q') int_0^2pi |E(q' v cos phi)|^2
dphi dq' / ((1 - nu^2) p0)^2``, i.e. the elastic theory with ``E*^2`` replaced, scale by scale,
by the angular mean of ``|E(q v a_T cos phi)|^2 / (1 - nu^2)^2``. One (v, T) point per solve:
``velocity`` and ``temperature`` are sweepable parameters that the core turns into the Dataset
dimensions ``v`` and ``T``.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from xpersson.cache import content_key
from xpersson.physics import closures
from xpersson.plugins import CLOSURE_PARAMETERS, Coefficient, FastPaths, ParamSpec, VarSpec

from . import _graded, kernel
from ._build import build_model, build_shift
from ._inline import INLINE_TABLES, archived
from ._modulus import ModulusModel, Prony
from ._outputs import check_outputs
from ._paired import block_nodes, dense_block, shared_block
from ._shift import WLF_UNIVERSAL

if TYPE_CHECKING:  # pragma: no cover
    from xpersson.plugins import SceneContext

__all__ = ["ViscoelasticCoefficient", "OUTPUTS"]

_PERSSON2001 = "10.1063/1.1388626"
_WLF1955 = "10.1021/ja01619a008"

OUTPUTS: dict[str, VarSpec] = {
    "effective_modulus": VarSpec(
        ("zeta",),
        "Pa",
        "angular rms contact modulus at scale q",
        description="sqrt(<|E(q v a_T cos phi)|^2>_phi) / (1 - nu^2): the E* the elastic theory "
        "would need at this scale",
        valid_min=0.0,
    ),
    "loss_angular_integral": VarSpec(
        ("zeta",),
        "Pa",
        "angular loss integral at scale q",
        description="int_0^2pi cos(phi) Im E(q v a_T cos phi) dphi / (1 - nu^2)",
        valid_min=0.0,
    ),
    "loss_integral": VarSpec(
        ("zeta",),
        "Pa",
        "cumulative viscoelastic loss integral L(zeta)",
        description="int_{q_L}^{zeta q_L} q^3 C(q) int_0^2pi cos(phi) Im E(q v a_T cos phi) dphi "
        "dq / (1 - nu^2); mu_visc = (1/(2 p0)) int P S dL",
        valid_min=0.0,
    ),
    "sliding_speed": VarSpec((), "m s-1", "sliding speed of the rubber", valid_min=0.0),
    "rubber_temperature": VarSpec((), "K", "temperature of the rubber", valid_min=0.0),
    "shift_factor": VarSpec(
        (),
        "1",
        "time-temperature shift factor a_T",
        description="E(omega, T) = E_ref(a_T omega)",
        valid_min=0.0,
    ),
    "flash_temperature": VarSpec(
        ("zeta",),
        "K",
        "rubber temperature seen at scale q",
        description="temperature + flash heating from the longer scales (opt-in approximate "
        "mode; equal to the temperature when flash_temperature is off)",
        valid_min=0.0,
    ),
    "rubbery_modulus": VarSpec((), "Pa", "rubbery (low-frequency) modulus E_r", valid_min=0.0),
    "glassy_modulus": VarSpec((), "Pa", "glassy (high-frequency) modulus E_g", valid_min=0.0),
}


class ViscoelasticCoefficient(Coefficient):
    """Diffusion coefficient of a viscoelastic solid sliding at speed ``velocity`` [m/s] at
    ``temperature`` [K] (Persson 2001), with the elastic coefficient's correction closures.

    Modulus models (``modulus``): ``sls`` (``E_r``, ``E_g``, ``relaxation_time``), ``prony``
    (``E_r`` plus modes ``delta_E``/``relaxation_times`` inline or ``prony_file``; without modes
    the synthetic tread-like default of physics.md §4.3 between ``E_r`` and ``E_g``),
    ``master_curve`` (``master_curve`` file, or ``master_omega``/``master_E_storage``/
    ``master_E_loss`` inline). Shift (``shift``): ``none``, ``wlf`` (``C1``, ``C2``,
    ``T_ref``), ``arrhenius`` (``activation_energy``, ``T_ref``), ``table`` (``shift_table``
    file, or ``shift_T``/``shift_a_T`` inline). ``material.nu`` is used; the moduli come
    from the model (the core's ``material.E`` is not used by this coefficient).
    """

    summary = "viscoelastic sliding contact: f(zeta; v, T) from E(omega) (Persson 2001)"
    references = (_PERSSON2001, _WLF1955, "10.1016/j.surfrep.2006.04.001")
    parameters: ClassVar = {
        "velocity": ParamSpec(
            "m/s",
            bounds=(0, None),
            sweepable=True,
            dim="v",
            example=0.01,
            description="sliding speed",
        ),
        "temperature": ParamSpec(
            "K",
            default=293.15,
            bounds=(0, None),
            inclusive=(False, True),
            sweepable=True,
            dim="T",
            description="rubber temperature",
        ),
        "modulus": ParamSpec(
            "1",
            default="prony",
            kind="choice",
            choices=("sls", "prony", "master_curve"),
            description="modulus model at the reference temperature",
        ),
        "E_r": ParamSpec(
            "Pa",
            default=3e6,
            bounds=(0, None),
            inclusive=(False, True),
            description="rubbery modulus (sls, prony)",
        ),
        "E_g": ParamSpec(
            "Pa",
            default=3e9,
            bounds=(0, None),
            inclusive=(False, True),
            description="glassy modulus (sls; synthetic prony default)",
        ),
        "relaxation_time": ParamSpec(
            "s",
            default=1e-3,
            bounds=(0, None),
            inclusive=(False, True),
            description="relaxation time (sls)",
        ),
        "delta_E": ParamSpec(
            "Pa",
            default=None,
            array=True,
            bounds=(0, None),
            description="Prony mode strengths (with relaxation_times)",
        ),
        "relaxation_times": ParamSpec(
            "s",
            default=None,
            array=True,
            bounds=(0, None),
            inclusive=(False, True),
            description="Prony relaxation times (with delta_E)",
        ),
        "prony_file": ParamSpec(
            "1", default=None, kind="path", description="Prony modes table: tau [s], delta_E [Pa]"
        ),
        "master_curve": ParamSpec(
            "1",
            default=None,
            kind="path",
            description="master curve table: omega [rad/s] (or f [Hz]), "
            "E_storage [Pa], E_loss [Pa]",
        ),
        "phi_nodes": ParamSpec(
            "1",
            default=6,
            bounds=(2, 64),
            kind="int",
            description="Gauss-Legendre nodes in phi per piece between "
            "table frequencies (master_curve)",
        ),
        "shift": ParamSpec(
            "1",
            default="none",
            kind="choice",
            choices=("none", "wlf", "arrhenius", "table"),
            description="time-temperature shift a_T(T)",
        ),
        "T_ref": ParamSpec(
            "K",
            default=293.15,
            bounds=(0, None),
            inclusive=(False, True),
            description="reference temperature of the modulus model",
        ),
        "C1": ParamSpec(
            "1",
            default=WLF_UNIVERSAL[0],
            bounds=(0, None),
            inclusive=(False, True),
            description="WLF C1 (universal 17.44 with T_ref = T_g)",
        ),
        "C2": ParamSpec(
            "K",
            default=WLF_UNIVERSAL[1],
            bounds=(0, None),
            inclusive=(False, True),
            description="WLF C2 (universal 51.6 K with T_ref = T_g)",
        ),
        "activation_energy": ParamSpec(
            "J/mol", default=None, bounds=(0, None), description="Arrhenius activation energy"
        ),
        "shift_table": ParamSpec(
            "1", default=None, kind="path", description="a_T table: T [K], a_T [1]"
        ),
        "flash_temperature": ParamSpec(
            "1",
            default=False,
            kind="bool",
            description="opt-in approximate flash temperature (physics.md §4.5, structure only)",
        ),
        "thermal_conductivity": ParamSpec(
            "W/(m*K)",
            default=0.25,
            bounds=(0, None),
            inclusive=(False, True),
            description="rubber thermal conductivity (flash)",
        ),
        "thermal_diffusivity": ParamSpec(
            "m**2/s",
            default=1e-7,
            bounds=(0, None),
            inclusive=(False, True),
            description="rubber thermal diffusivity (flash)",
        ),
        **INLINE_TABLES,  # a master curve's and a shift table's rows instead of their files
        **CLOSURE_PARAMETERS,  # closure, gamma: the core's one declaration
    }
    outputs: ClassVar = OUTPUTS
    #: stacked: a block of (v, T) points is one kernel call (:meth:`tau_stacked`,
    #: :meth:`interpret_stacked`); shared tau: without a closure, effective_tau is tau(zeta);
    #: reused: the model and shift law are built from the parameters once, at construction
    fast_paths: ClassVar = FastPaths(
        stacked_params=frozenset({"velocity", "temperature"}),
        shared_tau={"closure": "persson01"},
        reused=True,
    )

    def __init__(self, **params: Any) -> None:
        super().__init__(**params)
        self._model = build_model(self._params)
        self._shift = build_shift(self._params)
        self._shift.check(self._params["temperature"])
        closures.closure_S(self._params["closure"], 1.0, self._params["gamma"])  # validates
        self._aT = float(self._shift.aT(self._params["temperature"]))
        if not (np.isfinite(self._aT) and self._aT > 0):
            raise ValueError(
                f"temperature: {self._params['temperature']:g} K gives a shift factor a_T = "
                f"{self._aT:g} outside (0, inf); choose a temperature closer to T_ref"
            )

    def archived_params(self) -> dict[str, Any]:
        """The parameters with each table read from a file given inline (the archive's scene:
        no file path in it; the archive rebuilds this coefficient bit for bit)."""
        return archived(self._params, self._model, self._shift)

    # -- the model -------------------------------------------------------------------------
    @property
    def model(self) -> ModulusModel:
        """The modulus model at the reference temperature."""
        return self._model

    @property
    def shift_factor(self) -> float:
        """``a_T`` at this coefficient's temperature [1]."""
        return self._aT

    def _v(self) -> float:
        return float(self._params["velocity"])

    def _flash(self, psd: Any, nu: float) -> Any:
        """The solved flash-temperature profile (:func:`._flash.flash_profile`, cached)."""
        from ._flash import flash_profile

        p = self._params
        T, k, D = (
            float(p[n]) for n in ("temperature", "thermal_conductivity", "thermal_diffusivity")
        )
        return flash_profile(psd, self._model, self._shift, float(nu), self._v(), T, k, D)

    def _ppd(self, ctx: SceneContext) -> int:
        """q panels per decade: Prony integrands are analytic (4 give ~1e-14); tabulated
        curves converge at third order (4: ~4e-7, 8: ~5e-8, 16: ~4e-9 relative)."""
        if not self._model.breakpoints().size:
            return kernel.PANELS_PER_DECADE
        return 4 if ctx.rtol >= 1e-6 else (8 if ctx.rtol >= 1e-7 else 16)

    def _a_T_of(self, ctx: SceneContext) -> Any:
        """``a_T`` [1]: a number, or ``a_T(q)`` with the flash temperature."""
        if not self._params["flash_temperature"]:
            return self._aT
        prof = self._flash(ctx.psd, float(ctx.nu))
        shift = self._shift
        return lambda q: shift.aT(prof(q))

    # -- the coefficient contract ------------------------------------------------------------
    def _own_block(self, ctx: SceneContext, zeta: np.ndarray) -> dict[str, np.ndarray] | None:
        """The output grid's integrals of this point as a block of one (tau, f and
        :meth:`interpret` from one modulus pass; bitwise the kernel functions), or ``None``
        (other magnifications, the flash temperature, a tabulated curve)."""
        if zeta is not ctx.zeta or not self._one_call([ctx], [self]):
            return None
        return None if self._model.breakpoints().size else self._block([ctx], [self], zeta)

    def f(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """f(zeta) [Pa^2] at this (v, T)."""
        own = self._own_block(ctx, zeta)
        if own is not None:
            return own["f"][0]
        return kernel.coefficient_f(
            ctx.psd, self._model, ctx.nu, zeta, self._v(), self._a_T_of(ctx)
        )

    def tau(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """tau(zeta) [Pa^2] (Gauss-Legendre in ln q: ~1e-14 relative for Prony/SLS, below the
        scene's rtol for master curves; exact E_r^2 part)."""
        own = self._own_block(ctx, zeta)
        if own is not None:
            return own["tau"][0]
        return kernel.diffusion_time(
            ctx.psd,
            self._model,
            ctx.nu,
            zeta,
            self._v(),
            self._a_T_of(ctx),
            panels_per_decade=self._ppd(ctx),
        )

    def _one_call(self, ctxs: Sequence[SceneContext], points: Sequence[Any]) -> bool:
        """Whether a block is one kernel call: one spectrum (by content: equal spectra are
        one, shared or not) and Poisson ratio, no flash."""
        first = ctxs[0]
        psd = content_key(first.psd)
        return not self._params["flash_temperature"] and all(
            (x.psd is first.psd or content_key(x.psd) == psd)
            and x.nu == first.nu
            and x.rtol == first.rtol
            for x in ctxs
        )

    @staticmethod
    def _stacked_vT(points: Sequence[Any]) -> tuple[np.ndarray, np.ndarray]:
        """Sliding speeds [m/s] and shift factors [1] of a block, shape ``(n_point,)``."""
        v = np.array([float(c._params["velocity"]) for c in points])
        return v, np.array([c._aT for c in points])

    def tau_stacked(
        self, ctxs: Sequence[SceneContext], points: Sequence[Any], zeta: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """``(tau, f)`` [Pa^2] of a block of (v, T) points, ``(n_point, n_zeta)``: one kernel
        call over the stacked speeds and shift factors (per point for a tabulated curve: its
        q panels split where ``q v a_T`` crosses a table frequency, different per point)."""
        if not self._one_call(ctxs, points) or self._model.breakpoints().size:
            return super().tau_stacked(ctxs, points, zeta)
        got = self._block(ctxs, points, zeta)
        return got["tau"], got["f"]

    def _block(
        self, ctxs: Sequence[SceneContext], points: Sequence[Any], zeta: np.ndarray
    ) -> dict[str, np.ndarray]:
        """:func:`~xpersson_viscoelastic._paired.block_integrals` of a block (one call serves
        ``tau_stacked`` and ``interpret_stacked`` of the same block: kept from the first to
        the second)."""
        ctx = ctxs[0]
        v, aT = self._stacked_vT(points)
        z = np.asarray(zeta, dtype=float)
        return shared_block(ctx.psd, self._model, ctx.nu, z, v, aT, self._ppd(ctx))

    def _nodes(self, ctx: SceneContext) -> Any:
        """The q panels' node values of this solve's first block (:func:`._paired.block_nodes`)."""
        return block_nodes(ctx.psd, self._model, ctx.nu, self._ppd(ctx))

    def dense_stacked(
        self, ctxs: Sequence[SceneContext], points: Sequence[Any], zeta: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """``(tau [Pa^2], L [Pa])`` of a block of points, row k at its own magnifications
        ``zeta[k]`` (K, m): each row equals :meth:`tau` and :meth:`loss_integral` of point k
        there (the friction analysis's dense grids). ``None`` where the block is not one call."""
        if not self._one_call(ctxs, points):
            return None
        v, aT = self._stacked_vT(points)
        return dense_block(ctxs[0].psd, self._model, ctxs[0].nu, zeta, v, aT, self._ppd(ctxs[0]))

    def graded_stacked(
        self, ctxs: Sequence[SceneContext], points: Sequence[Any], lay: Any, index: Any = None
    ) -> tuple[np.ndarray, np.ndarray] | None:
        """``tau`` [Pa^2] and ``dL`` [Pa] at the nodes of the friction analysis's graded
        panels (:mod:`~xpersson_viscoelastic._graded`), each (K, N), of points ``index`` of
        the block whose output grid this coefficient integrated last (its node values reused
        where the panels coincide); ``None`` unless a Prony model (shared spectrum, ``nu``)."""
        if not isinstance(self._model, Prony):
            return None
        known = None
        if self._one_call(ctxs, points):
            v, aT = self._stacked_vT(points)
            w = (v * aT)[:, None] * lay.qn
            known = _graded.known_nodes(self._nodes(ctxs[0]), v, aT, index)
        else:  # the flash temperature's a_T(q): each point's frequencies at the nodes
            pairs = zip(points, ctxs, strict=True)
            w = np.stack([kernel._w(c._v(), c._a_T_of(x), lay.qn) for c, x in pairs])
        return _graded.integrals(ctxs[0].psd, self._model, ctxs[0].nu, lay, w, known)

    def interpret_stacked(
        self, ctxs: Sequence[SceneContext], points: Sequence[Any]
    ) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """:meth:`interpret` of a block of (v, T) points (each value with a leading point
        axis): one kernel call over the stacked speeds and shift factors."""
        if not self._one_call(ctxs, points) or self._model.breakpoints().size:
            return super().interpret_stacked(ctxs, points)
        ctx = ctxs[0]
        zeta = ctx.zeta
        v, aT = self._stacked_vT(points)
        got = self._block(ctxs, points, zeta)
        rms, loss, L = got["rms"], got["loss"], got["L"]
        T0 = np.array([float(c._params["temperature"]) for c in points])
        n = len(points)
        out = {
            "effective_modulus": (("zeta",), rms),
            "loss_angular_integral": (("zeta",), loss),
            "loss_integral": (("zeta",), L),
            "flash_temperature": (("zeta",), np.repeat(T0[:, None], zeta.size, axis=1)),
            "sliding_speed": ((), v),
            "rubber_temperature": ((), T0),
            "shift_factor": ((), aT),
            "rubbery_modulus": ((), np.full(n, float(self._model.E_r))),
            "glassy_modulus": ((), np.full(n, float(self._model.E_g))),
        }
        for name, (dims, arr) in out.items():  # the checks of interpret, per point
            check_outputs({name: (dims, arr[0])}, OUTPUTS, "coefficient 'viscoelastic'")
            check_outputs({name: (dims, arr.min(axis=0))}, OUTPUTS, "coefficient 'viscoelastic'")
            check_outputs({name: (dims, arr.max(axis=0))}, OUTPUTS, "coefficient 'viscoelastic'")
        return out

    def effective_tau(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """Per-load diffusion time [Pa^2] of the selected correction closure."""
        return closures.effective_tau(
            self.tau(ctx, zeta),
            ctx.p0,
            self._params["closure"],
            self._params["gamma"],
            rtol=1e-10,
        )

    def loss_integral(self, ctx: SceneContext, zeta: np.ndarray) -> np.ndarray:
        """The cumulative loss integral ``L(zeta)`` [Pa] at any magnifications ``zeta`` [1]
        (the Dataset's ``loss_integral``; the friction analysis samples it densely where the
        output grid does not resolve the contact area)."""
        return kernel.loss_integral(
            ctx.psd,
            self._model,
            ctx.nu,
            zeta,
            self._v(),
            self._a_T_of(ctx),
            panels_per_decade=self._ppd(ctx),
        )

    def interpret(self, ctx: SceneContext) -> dict[str, tuple[tuple[str, ...], np.ndarray]]:
        """The angular integrals and the cumulative loss integral on the output ``zeta``."""
        zeta = ctx.zeta
        aT = self._a_T_of(ctx)
        own = self._own_block(ctx, zeta)
        if own is not None:
            rms, loss, L = own["rms"][0], own["loss"][0], own["L"][0]
        else:
            rms, loss = kernel.angular_averages(ctx.psd, self._model, ctx.nu, zeta, self._v(), aT)
            L = self.loss_integral(ctx, zeta)
        T0 = float(self._params["temperature"])
        if callable(aT):
            T_q = self._flash(ctx.psd, float(ctx.nu))(zeta * ctx.q_L)
        else:
            T_q = np.full(zeta.shape, T0)
        out = {
            "effective_modulus": (("zeta",), rms),
            "loss_angular_integral": (("zeta",), loss),
            "loss_integral": (("zeta",), L),
            "flash_temperature": (("zeta",), T_q),
            "sliding_speed": ((), np.float64(self._v())),
            "rubber_temperature": ((), np.float64(self._params["temperature"])),
            "shift_factor": ((), np.float64(self._aT)),
            "rubbery_modulus": ((), np.float64(self._model.E_r)),
            "glassy_modulus": ((), np.float64(self._model.E_g)),
        }
        return check_outputs(out, OUTPUTS, "coefficient 'viscoelastic'")
