"""Appendix A of Li, Yao & Wu (2016): modal constants of the stator from beam theory.

The stator is a plate of length ``l`` (axis ``y``), width ``b_s`` (axis ``x``, the in-plane
bending direction, Eq. 1: ``u1 = w``, ``u2 = u - x psi``) and thickness ``h_s`` (axis ``z``,
the poling direction). The assumed modes are the free-free Euler-Bernoulli shapes of Eq. 3
(:mod:`fem.beam_shapes`), so every constant below is a Rayleigh-Ritz integral of those
shapes. The extracted text of Appendix A is garbled; the reading used here is (``A = b_s h_s``,
``I = h_s b_s^3 / 12``, ``E3 = V0 / h_s``):

* A.1 ``M_l = int rho A phi_L^2 dy`` (= ``rho A l / 2`` exactly).
* A.2 ``M_b = int rho A phi_B^2 dy``.
* A.3 ``K_l = int cE11 A (phi_L')^2 dy`` (the prime was lost; = ``cE11 A pi^2 / (2 l)``).
* A.4 ``K_b = int cE11 I (phi_B'')^2 dy`` by default (``b2_stiffness="euler-bernoulli"``):
  the strain energy of in-plane bending about the thickness axis, consistent with the
  Euler-Bernoulli shapes of Eq. 3 and with the curvature in A.6. The printed
  ``1/2 cE66 A (phi_B')^2`` is the shear energy of a Timoshenko beam whose rotation is set
  to zero; it is available for comparison through :func:`b2_stiffness_readings`. The
  option ``b2_stiffness="timoshenko"`` uses bending and shear (``kappa cE66 A int phi_B'^2``)
  in series, i.e. the Ritz stiffness with the rotation condensed statically (the paper's
  argument that the rotation is fast), together with the matching force factor.
* A.5 ``A_l V0 = sum_e int_e e31 E3 (dphi_L/dy) dV``: the generalized force of the
  piezoelectric stress ``e31 E3`` over the driven electrodes. Per electrode
  ``[y1, y2] x [x1, x2]`` (through the full thickness) this is
  ``e31 (x2 - x1) (phi_L(y2) - phi_L(y1)) V0`` (the prime was lost in A.5; without it the
  integral vanishes over a full-length electrode and has units of N m / V).
* A.6 ``A_b V0 = -sum_e int_e e31 E3 x phi_B''(y) dV``: axial piezo stress times the bending
  strain ``-x phi_B''``; per electrode ``-e31 (x2^2 - x1^2) / 2 (phi_B'(y2) - phi_B'(y1)) V0``.
  Over the full width ``int x dx = 0``: only an electrode pattern antisymmetric in ``x``
  drives bending, and since ``phi_B''`` of B2 is antisymmetric about ``y = l/2`` the
  diagonal quadrants (1 and 4) add up. The other diagonal flips the sign.
* A.7 ``eta_N = phi_L(0) - phi_L(l)``, A.8 ``eta_T = phi_B(0) - phi_B(l)`` (Eq. 3 values).

Damping cannot come from beam theory (the paper identified ``C_l``, ``C_b`` from measured
tip amplitudes): ``C = 2 zeta sqrt(K M)`` with ``zeta`` from the Table 2 set by default.
The contact tip is taken as rigid and massless (Section 3.1). See ``docs/beam.md``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from bounds import ParameterError
from fem.beam_shapes import BETA2_L, phi_B, phi_L
from rom.beam_stator import SHEAR_FACTOR, BeamStator
from rom.params import MotorParams
from rom.table2 import table2

_QUAD_POINTS = 64
"""Gauss-Legendre points for the B2 integrals (converged to machine precision)."""

B2Stiffness = Literal["euler-bernoulli", "timoshenko"]


@dataclass(frozen=True)
class Electrode:
    """One driven electrode, through the full thickness, on a rectangle of the stator face.

    Attributes
    ----------
    y_start, y_stop : float
        Axial extent as fractions of the length ``l``, ``0 <= y_start < y_stop <= 1`` (-).
        ``y = 0`` is the preload end, ``y = l`` the contact tip.
    x_start, x_stop : float
        Lateral extent as fractions of the width ``b_s`` measured from the centre line,
        ``-0.5 <= x_start < x_stop <= 0.5`` (-). ``x`` is the bending direction (Eq. 1).
    polarity : float
        Sign (or relative amplitude) of the drive voltage on this electrode (-).
    """

    y_start: float
    y_stop: float
    x_start: float
    x_stop: float
    polarity: float = 1.0

    def __post_init__(self) -> None:
        for name in ("y_start", "y_stop", "x_start", "x_stop", "polarity"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"Electrode.{name} must be finite, got {getattr(self, name)!r}")
        if not 0.0 <= self.y_start < self.y_stop <= 1.0:
            raise ValueError(
                "Electrode.y_start, y_stop must satisfy 0 <= y_start < y_stop <= 1 (fractions "
                f"of the length), got {self.y_start!r}, {self.y_stop!r}"
            )
        if not -0.5 <= self.x_start < self.x_stop <= 0.5:
            raise ValueError(
                "Electrode.x_start, x_stop must satisfy -0.5 <= x_start < x_stop <= 0.5 "
                f"(fractions of the width), got {self.x_start!r}, {self.x_stop!r}"
            )


B2_STIFFNESSES = ("euler-bernoulli", "timoshenko")
"""The B2 stiffness models a beam parameter set takes (:func:`beam_params`)."""

ELECTRODE_LAYOUTS: dict[str, tuple[Electrode, ...]] = {
    # Quadrant numbering used here (Fig. 1 of the paper does not fix x): 1 = preload half,
    # x > 0; 2 = preload half, x < 0; 3 = tip half, x > 0; 4 = tip half, x < 0.
    "quadrants-1-4": (Electrode(0.0, 0.5, 0.0, 0.5), Electrode(0.5, 1.0, -0.5, 0.0)),
    "quadrants-2-3": (Electrode(0.0, 0.5, -0.5, 0.0), Electrode(0.5, 1.0, 0.0, 0.5)),
    "full": (Electrode(0.0, 1.0, -0.5, 0.5),),
}
"""Named electrode layouts. The paper drives the diagonal quadrants 1 and 4."""

_PLATE_QUADRANTS: dict[int, Electrode] = {
    1: Electrode(0.0, 0.5, 0.0, 0.5),    # preload half, x > 0
    2: Electrode(0.5, 1.0, 0.0, 0.5),    # tip half, x > 0
    3: Electrode(0.0, 0.5, -0.5, 0.0),   # preload half, x < 0
    4: Electrode(0.5, 1.0, -0.5, 0.0),   # tip half, x < 0
}


def plate_layout(drive_electrodes: Sequence[int]) -> tuple[Electrode, ...]:
    """The electrodes a plate stator drives, numbered as the FE plate numbers them
    (``fem.geometry.PlateStator.electrode_of``: 1, 2 at x > 0, 1, 3 in the preload half),
    as beam electrodes. The FE plate's ``(1, 4)`` is :data:`ELECTRODE_LAYOUTS`'s
    ``"quadrants-1-4"`` and its ``(2, 3)`` is ``"quadrants-2-3"``: the same regions, whose
    names number the quadrants differently."""
    try:
        return tuple(_PLATE_QUADRANTS[int(e)] for e in drive_electrodes)
    except KeyError:
        raise ParameterError("drive_electrodes", tuple(drive_electrodes), choices=(1, 2, 3, 4),
                             message=f"drive_electrodes must be plate electrodes 1..4, got "
                             f"{tuple(drive_electrodes)!r}") from None


@dataclass(frozen=True)
class BeamConstants:
    """Every Appendix A quantity of one beam, including the alternative B2 stiffnesses.

    Attributes
    ----------
    area_m2, inertia_m4 : float
        Cross-section ``A = b_s h_s`` (m^2) and in-plane second moment ``h_s b_s^3/12`` (m^4).
    M_l, K_l, A_l : float
        L1 modal mass (kg), stiffness (N/m), force factor (N/V).
    M_b, A_b : float
        B2 modal mass (kg), force factor (N/V) of the Euler-Bernoulli reading.
    K_b_bending : float
        ``int cE11 I phi_B''^2 dy``: Euler-Bernoulli bending stiffness (N/m).
    K_b_shear : float
        ``int kappa cE66 A phi_B'^2 dy`` with ``kappa = 5/6``: shear stiffness (N/m).
    K_b_timoshenko : float
        Bending and shear in series, ``1/K = 1/K_bend + 1/K_shear`` (N/m).
    K_b_printed : float
        The printed A.4, ``int 1/2 cE66 A phi_B'^2 dy`` (N/m).
    A_b_timoshenko : float
        Force factor consistent with ``K_b_timoshenko`` (N/V): the piezoelectric moment acts
        on the rotation ``psi``, and condensing ``psi`` passes the fraction
        ``K_shear / (K_bend + K_shear)`` of ``A_b`` to ``w``.
    phi_L0, phi_Ll, phi_B0, phi_Bl : float
        Eq. 3 tip values at ``y = 0`` and ``y = l`` (-).
    """

    area_m2: float
    inertia_m4: float
    M_l: float
    K_l: float
    A_l: float
    M_b: float
    A_b: float
    K_b_bending: float
    K_b_shear: float
    K_b_timoshenko: float
    K_b_printed: float
    A_b_timoshenko: float
    phi_L0: float
    phi_Ll: float
    phi_B0: float
    phi_Bl: float


@dataclass(frozen=True)
class BeamFrequencies:
    """Natural frequencies of the beam stator (Hz).

    Attributes
    ----------
    f_L1_Hz : float
        Rod L1 frequency ``sqrt(K_l/M_l)/(2 pi) = sqrt(cE11/rho)/(2 l)``.
    f_B2_euler_bernoulli_Hz : float
        ``sqrt(K_b_bending/M_b)/(2 pi)``, the Euler-Bernoulli B2 frequency of the assumed mode.
    f_B2_condensed_Hz : float
        ``sqrt(K_b_timoshenko/M_b)/(2 pi)``: one-mode Timoshenko estimate (no rotary inertia).
    f_B2_timoshenko_Hz : float
        Converged free-free Timoshenko B2 frequency (shear ``kappa = 5/6``, ``G = cE66``,
        rotary inertia included), from :func:`timoshenko_b2_frequency`. For the record only.
    f_B2_params_Hz : float
        The B2 frequency of the :class:`MotorParams` built with the same options.
    b2_stiffness : str
        Which stiffness the :class:`MotorParams` uses.
    """

    f_L1_Hz: float
    f_B2_euler_bernoulli_Hz: float
    f_B2_condensed_Hz: float
    f_B2_timoshenko_Hz: float
    f_B2_params_Hz: float
    b2_stiffness: str


def _resolve_layout(electrode_layout: str | Sequence[Electrode]) -> tuple[Electrode, ...]:
    """Turn a layout name or a sequence of :class:`Electrode` into a non-empty tuple."""
    if isinstance(electrode_layout, str):
        try:
            return ELECTRODE_LAYOUTS[electrode_layout]
        except KeyError:
            raise ParameterError(
                "electrode_layout", electrode_layout, choices=tuple(sorted(ELECTRODE_LAYOUTS)),
                message=f"electrode_layout must be one of {sorted(ELECTRODE_LAYOUTS)} or a "
                f"sequence of Electrode, got {electrode_layout!r}") from None
    layout = tuple(electrode_layout)
    if not layout or not all(isinstance(e, Electrode) for e in layout):
        raise ParameterError(
            "electrode_layout", electrode_layout, choices=tuple(sorted(ELECTRODE_LAYOUTS)),
            message=f"electrode_layout must be one of {sorted(ELECTRODE_LAYOUTS)} or a "
            f"non-empty sequence of Electrode, got {electrode_layout!r}")
    return layout


def _gauss(length_m: float, n: int = _QUAD_POINTS) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes (m) and weights (m) on ``[0, l]``."""
    xi, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * length_m * (xi + 1.0), 0.5 * length_m * w


def beam_constants(
    beam: BeamStator | None = None,
    *,
    electrode_layout: str | Sequence[Electrode] = "quadrants-1-4",
) -> BeamConstants:
    """Evaluate formulas A.1-A.8 (and the alternative readings of A.4) for one beam.

    Parameters
    ----------
    beam : BeamStator, optional
        Geometry and material (default: Table 1).
    electrode_layout : str or sequence of Electrode
        A key of :data:`ELECTRODE_LAYOUTS` or explicit electrodes.

    Returns
    -------
    BeamConstants
        The modal constants; see the module docstring for the formulas.

    Raises
    ------
    ValueError
        If a dimension or modulus is not finite and positive, ``e31`` is not finite, or the
        layout is unknown.
    """
    beam = BeamStator() if beam is None else beam
    l_, b = beam.length_m, beam.width_m
    rho, c11, c66, e31 = beam.rho_kg_m3, beam.cE11_Pa, beam.cE66_Pa, beam.e31_C_m2
    layout = _resolve_layout(electrode_layout)

    area, inertia = beam.area_m2, beam.inertia_m4
    # A.1 and A.3 in closed form for phi_L = cos(pi y / l).
    m_l = rho * area * l_ / 2.0
    k_l = c11 * area * math.pi**2 / (2.0 * l_)
    # A.2 and A.4 by Gauss-Legendre quadrature of the Eq. 3 shape.
    y, w = _gauss(l_)
    int_phi2 = float(np.sum(w * phi_B(y, l_) ** 2))
    int_dphi2 = float(np.sum(w * phi_B(y, l_, 1) ** 2))
    int_ddphi2 = float(np.sum(w * phi_B(y, l_, 2) ** 2))
    m_b = rho * area * int_phi2
    k_bend = c11 * inertia * int_ddphi2
    k_shear = SHEAR_FACTOR * c66 * area * int_dphi2
    k_timo = k_bend * k_shear / (k_bend + k_shear)
    k_printed = 0.5 * c66 * area * int_dphi2
    # A.5 and A.6, electrode by electrode (E3 = V0/h_s times the thickness h_s: h cancels).
    a_l = 0.0
    a_b = 0.0
    for e in layout:
        y1, y2 = e.y_start * l_, e.y_stop * l_
        x1, x2 = e.x_start * b, e.x_stop * b
        a_l += e.polarity * e31 * (x2 - x1) * float(phi_L(y2, l_) - phi_L(y1, l_))
        a_b -= (
            e.polarity * e31 * 0.5 * (x2**2 - x1**2)
            * float(phi_B(y2, l_, 1) - phi_B(y1, l_, 1))
        )
    return BeamConstants(
        area_m2=area,
        inertia_m4=inertia,
        M_l=m_l,
        K_l=k_l,
        A_l=a_l,
        M_b=m_b,
        A_b=a_b,
        K_b_bending=k_bend,
        K_b_shear=k_shear,
        K_b_timoshenko=k_timo,
        K_b_printed=k_printed,
        A_b_timoshenko=a_b * k_shear / (k_bend + k_shear),
        phi_L0=float(phi_L(0.0, l_)),
        phi_Ll=float(phi_L(l_, l_)),
        phi_B0=float(phi_B(0.0, l_)),
        phi_Bl=float(phi_B(l_, l_)),
    )


def b2_stiffness_readings(beam: BeamStator | None = None) -> dict[str, float]:
    """The candidate readings of A.4 (N/m) for one beam (default Table 1), keyed by a short
    description."""
    c = beam_constants(beam)
    return {
        "bending cE11 I int phi''^2 (Euler-Bernoulli)": c.K_b_bending,
        "printed 1/2 cE66 A int phi'^2": c.K_b_printed,
        "shear 5/6 cE66 A int phi'^2": c.K_b_shear,
        "bending + shear in series (Timoshenko, condensed)": c.K_b_timoshenko,
    }


def beam_params(
    beam: BeamStator | None = None,
    *,
    base: MotorParams | None = None,
    damping_ratios: tuple[float, float] | None = None,
    electrode_layout: str | Sequence[Electrode] = "quadrants-1-4",
    b2_stiffness: B2Stiffness = "euler-bernoulli",
) -> MotorParams:
    """A :class:`MotorParams` whose stator constants come from Appendix A beam theory.

    Parameters
    ----------
    beam : BeamStator, optional
        Geometry (m) and material (kg/m^3, Pa, C/m^2); default Table 1.
    base : MotorParams, optional
        Source of the contact, slider and friction constants (``k_contact``, ``M_slider``,
        ``mu_s``, ``mu_d``, ``mu_sd``, ``a_mu``, ``b_mu``) and of the default damping ratios.
        Defaults to :func:`rom.table2.table2`.
    damping_ratios : (float, float), optional
        Modal damping ratios ``(zeta_L1, zeta_B2)``, each in (0, 1); ``C = 2 zeta sqrt(K M)``.
        Defaults to ``(base.zeta_L1, base.zeta_B2)``.
    electrode_layout : str or sequence of Electrode
        Driven electrodes; default the paper's diagonal quadrants 1 and 4.
    b2_stiffness : {"euler-bernoulli", "timoshenko"}
        ``K_b`` used: the bending stiffness ``cE11 I int phi_B''^2`` (default) or bending and
        shear in series with the consistent ``A_b_timoshenko`` (see :class:`BeamConstants`).

    Returns
    -------
    MotorParams
        The beam-theory parameter set (``source`` names the options).

    Raises
    ------
    ValueError
        For non-finite or non-positive geometry/moduli, damping ratios outside (0, 1), an
        unknown layout or ``b2_stiffness``.
    """
    if b2_stiffness not in B2_STIFFNESSES:
        raise ParameterError(
            "b2_stiffness", b2_stiffness, choices=B2_STIFFNESSES,
            message=f"b2_stiffness must be 'euler-bernoulli' or 'timoshenko', got {b2_stiffness!r}")
    c = beam_constants(beam, electrode_layout=electrode_layout)
    base = table2() if base is None else base
    if not isinstance(base, MotorParams):
        raise ParameterError("base", base, message=f"base must be a MotorParams or None, got "
                             f"{type(base).__name__}")
    if damping_ratios is None:
        zeta_l, zeta_b = base.zeta_L1, base.zeta_B2
    else:
        try:
            zeta_l, zeta_b = damping_ratios
        except (TypeError, ValueError):
            raise ParameterError(
                "damping_ratios", damping_ratios, message=f"damping_ratios must be a pair "
                f"(zeta_L1, zeta_B2), got {damping_ratios!r}") from None
    for name, z in (("zeta_L1", zeta_l), ("zeta_B2", zeta_b)):
        # one message with the range that holds, (0, 1), for 0.0 too
        if isinstance(z, bool) or not isinstance(z, (int, float, np.floating, np.integer)) \
                or not (math.isfinite(float(z)) and 0.0 < float(z) < 1.0):
            raise ParameterError(name, z, 0.0, 1.0, low_open=True, high_open=True,
                                 message=f"damping_ratios[{0 if name == 'zeta_L1' else 1}] "
                                 f"({name}) must be a number in (0, 1), got {z!r}")
    if b2_stiffness == "euler-bernoulli":
        k_b, a_b = c.K_b_bending, c.A_b
    else:
        k_b, a_b = c.K_b_timoshenko, c.A_b_timoshenko
    layout_name = electrode_layout if isinstance(electrode_layout, str) else "custom electrodes"
    return MotorParams.from_modal(
        M_l=c.M_l, K_l=c.K_l, A_l=c.A_l, phi_L0=c.phi_L0, phi_Ll=c.phi_Ll,
        M_b=c.M_b, K_b=k_b, A_b=a_b, phi_B0=c.phi_B0, phi_Bl=c.phi_Bl,
        damping_ratios=(float(zeta_l), float(zeta_b)), base=base,
        source=f"beam theory (Appendix A, K_b {b2_stiffness}, {layout_name})",
        shape=_beam_shape(beam),
    )


def _beam_shape(beam: BeamStator | None):
    """Appendix A's shapes on the beam (:func:`rom.shape_data.beam_shape_data`), with PZT-8's
    limits: beam theory takes Table 1's constants, the paper's PZT-8."""
    from fem.material import MATERIAL_LIMITS
    from rom.shape_data import beam_shape_data

    b = BeamStator() if beam is None else beam
    return beam_shape_data(b.length_m, b.width_m, b.thickness_m, b.cE11_Pa, "paper",
                           MATERIAL_LIMITS["paper"], "Appendix A beam shapes (Eq. 3)")


def beam_frequencies(
    beam: BeamStator | None = None,
    *,
    b2_stiffness: B2Stiffness = "euler-bernoulli",
) -> BeamFrequencies:
    """L1 and B2 frequencies of the beam stator under each B2 theory (Hz).

    Parameters
    ----------
    beam : BeamStator, optional
        As in :func:`beam_params`.
    b2_stiffness : {"euler-bernoulli", "timoshenko"}
        The choice :func:`beam_params` would make; sets ``f_B2_params_Hz``.

    Returns
    -------
    BeamFrequencies
        ``f_L1_Hz``, the Euler-Bernoulli, condensed-Timoshenko and full Timoshenko B2
        frequencies, and the one the parameter set uses.
    """
    if b2_stiffness not in B2_STIFFNESSES:
        raise ParameterError(
            "b2_stiffness", b2_stiffness, choices=B2_STIFFNESSES,
            message=f"b2_stiffness must be 'euler-bernoulli' or 'timoshenko', got {b2_stiffness!r}")
    # imported here: the full Timoshenko figure, kept for the record, is the one use of
    # scipy.linalg in the beam set (0.35 s at start-up)
    from rom.timoshenko import timoshenko_b2_frequency

    beam = BeamStator() if beam is None else beam
    c = beam_constants(beam)
    two_pi = 2.0 * math.pi
    f_eb = math.sqrt(c.K_b_bending / c.M_b) / two_pi
    f_cond = math.sqrt(c.K_b_timoshenko / c.M_b) / two_pi
    return BeamFrequencies(
        f_L1_Hz=math.sqrt(c.K_l / c.M_l) / two_pi,
        f_B2_euler_bernoulli_Hz=f_eb,
        f_B2_condensed_Hz=f_cond,
        f_B2_timoshenko_Hz=timoshenko_b2_frequency(beam),
        f_B2_params_Hz=f_eb if b2_stiffness == "euler-bernoulli" else f_cond,
        b2_stiffness=b2_stiffness,
    )


def euler_bernoulli_b2_frequency(beam: BeamStator | None = None) -> float:
    """Closed-form free-free B2 frequency ``(beta2 l)^2 / (2 pi l^2) sqrt(EI / rho A)`` (Hz).

    Uses the ``beta2 l`` printed under Eq. 3, ``E = cE11`` and ``I = h_s b_s^3 / 12``
    (in-plane bending; the thickness cancels in ``I / A``).
    """
    beam = BeamStator() if beam is None else beam
    l_ = beam.length_m
    return float(BETA2_L**2 / (2.0 * math.pi * l_**2)
                 * math.sqrt(beam.cE11_Pa * beam.inertia_m4 / (beam.rho_kg_m3 * beam.area_m2)))
