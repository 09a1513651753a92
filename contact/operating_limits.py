"""The physical limits of an operating point: vibration velocity, stress, field, heat.

The reduced model gives each steady state's modal motion; the parameter set's shape data
(:class:`rom.shape_data.ShapeData`: the FE mode shapes' or the beam shapes' peaks per unit
modal amplitude) turn it into what a ceramic survives or not:

* **vibration velocity**: the larger of the two modes' antinode velocity amplitudes,
  ``omega U max|phi_L|`` and ``omega W max|phi_B|`` (the figure of Uchino's maximum vibration
  velocity, measured on one resonating mode);
* **stress**: the peak principal stress of L1 and B2 together over the period at the worst
  phase between them (:meth:`rom.shape_data.ShapeData.stress_Pa`: the FE shapes' stress
  fields, or the beam shapes', combined point by point), with ``s_L U + s_B W``, each mode's
  largest principal stress per unit amplitude times its amplitude added as if both peaked
  at one point in phase, as the upper bound beside it (the sum alone where the shape data
  carry no combined stress);
* **drive field**: ``V0 / h``, the voltage amplitude over the electrode spacing;
* **dissipated power**: the mean power in the modal dampers ``C_l``, ``C_b`` (the paper's
  model of the stator's loss; no limit of its own: it heats the ceramic, the mount and
  the contact), and **power density**: the heat generated in the ceramic over its volume,
  the ceramic's own loss's share of each mode's damper power, ``1 / (2 Q_m zeta)`` (at most
  1) with the ceramic's ``Q_m`` (:attr:`fem.material.MaterialLimits.mechanical_Q`).

The modal amplitudes of a steady branch come from its damper powers: ``<C_l du_l^2>`` is
L1's share (:attr:`contact.steady.branches.SteadyBranch.damping_power_B2_W` is B2's), so the
modal velocity amplitude is ``sqrt(2 P / C)``, exact for the harmonic motion a resonating
mode keeps. Where a result has no powers (a map point, computed without them) the free
stator's steady amplitudes at the drive stand in: ``|A V0 / (K - M omega^2 + i C omega)|``,
what the modes reach without the contact's load, an estimate from above near resonance.

The material's limits (:class:`fem.material.MaterialLimits`) come with the shape data.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from rom.params import MotorParams

QUANTITIES = {
    "vibration_velocity": ("m/s", "vibration_velocity_m_s", 1.0, "m/s"),
    "stress": ("Pa", "dynamic_tensile_stress_Pa", 1e-6, "MPa"),
    "drive_field": ("V/m", "drive_field_V_m", 1e-3, "V/mm"),
    "dissipated_power": ("W", None, 1.0, "W"),
    "power_density": ("W/m^3", "power_density_W_m3", 1e-6, "W/cm^3"),
}
"""Each checked quantity: its SI unit (the JSON's), the :class:`fem.material.MaterialLimits`
field that bounds it (None: no limit, the dissipated power), and the factor and unit it is
printed in."""


STRESS_COMBINED = ("L1 and B2 combined over the period, point by point, at the worst phase "
                   "between them")
STRESS_BOUND = "the L1 and B2 peak stresses added (an upper bound)"
"""What the ``stress`` value is, said in its JSON entry (``basis``)."""


@dataclass(frozen=True)
class OperatingLimits:
    """An operating point's peak quantities against the material's limits.

    Attributes
    ----------
    values, limits : dict of str to float
        Each of :data:`QUANTITIES` in SI units; a limit NaN where the material has none.
    amplitudes_m : (float, float)
        The modal amplitudes ``(U, W)`` of L1 and B2 (m) behind them.
    basis : str
        Where the amplitudes come from: ``"steady state"`` (the damper powers of the steady
        branch) or ``"free response"`` (no powers: the free stator's).
    stress_bound_Pa : float
        The modes' peak stresses added (Pa), the upper bound of ``values["stress"]``.
    stress_basis : str
        What ``values["stress"]`` is: :data:`STRESS_COMBINED` or :data:`STRESS_BOUND`.
    """

    values: dict
    limits: dict
    amplitudes_m: tuple[float, float]
    basis: str
    stress_bound_Pa: float = math.nan
    stress_basis: str = STRESS_BOUND

    def ratio(self, quantity: str) -> float:
        """Value over limit (-); NaN without a limit."""
        lim = self.limits[quantity]
        return self.values[quantity] / lim if lim > 0 else math.nan

    def exceeded(self) -> list[str]:
        """The quantities beyond their limit, in :data:`QUANTITIES` order."""
        return [q for q in QUANTITIES if self.ratio(q) > 1.0]

    def to_dict(self) -> dict:
        """``{quantity: {value, limit, ratio, unit}}`` (SI) and ``basis``, for ``--json``;
        the ``stress`` entry also says what it is (``basis``) and carries the peaks' sum
        (``sum_of_peaks``, Pa)."""
        out: dict = {q: {"value": self.values[q], "limit": self.limits[q],
                         "ratio": self.ratio(q), "unit": QUANTITIES[q][0]} for q in QUANTITIES}
        out["stress"].update(basis=self.stress_basis, sum_of_peaks=self.stress_bound_Pa)
        out["basis"] = self.basis
        return out

    def warning(self, where: str = "") -> str | None:
        """One line naming every quantity beyond its limit, with value and limit, or None."""
        over = self.exceeded()
        if not over:
            return None
        parts = []
        for q in over:
            _, _, factor, unit = QUANTITIES[q]
            parts.append(f"{q.replace('_', ' ')} {self.values[q] * factor:.3g} {unit} > limit "
                         f"{self.limits[q] * factor:.3g} {unit}")
        return (f"beyond the ceramic's limits{' ' + where if where else ''}: "
                f"{'; '.join(parts)} (docs/designer.md, 'Physical limits')")

    def rows(self) -> list[tuple[str, str, str, str]]:
        """``(quantity, value, limit, ratio)`` text rows in the printed units."""
        out = []
        for q, (_, _, factor, unit) in QUANTITIES.items():
            lim = self.limits[q]
            out.append((q.replace("_", " "), f"{self.values[q] * factor:.3g} {unit}",
                        f"{lim * factor:.3g} {unit}" if lim > 0 else "-",
                        f"{self.ratio(q):.3g}" if lim > 0 else "-"))
        return out


def branch_amplitudes_m(params: MotorParams, branch, omega: float) -> tuple[float, float] | None:
    """``(U, W)`` (m): the modal amplitudes of a steady branch from its damper powers,
    ``sqrt(2 P / C) / omega`` per mode; None where the branch has no powers."""
    total = getattr(branch, "damping_power_W", math.nan)
    p_b = getattr(branch, "damping_power_B2_W", math.nan)
    if not (math.isfinite(total) and math.isfinite(p_b)):
        return None
    p_l = max(total - p_b, 0.0)
    return (math.sqrt(2.0 * p_l / params.C_l) / omega,
            math.sqrt(2.0 * max(p_b, 0.0) / params.C_b) / omega)


def free_amplitudes_m(params: MotorParams, voltage_V: float, omega: float) -> tuple[float, float]:
    """``(U, W)`` (m): the free stator's steady modal amplitudes at the drive."""
    p = params
    u = abs(p.A_l) * voltage_V / abs(complex(p.K_l - p.M_l * omega**2, p.C_l * omega))
    w = abs(p.A_b) * voltage_V / abs(complex(p.K_b - p.M_b * omega**2, p.C_b * omega))
    return u, w


def ceramic_heat_W(params: MotorParams, powers_W: tuple[float, float]) -> float:
    """The heat generated in the ceramic (W) of the L1 and B2 damper powers ``powers_W``: the
    ceramic's own loss's share of each, ``min(1, 1 / (2 Q_m zeta))``; all of it without a
    known ``Q_m``."""
    lim = params.shape.limits if params.shape is not None else None
    if lim is None:
        return float(sum(powers_W))
    zeta_ceramic = 0.5 / lim.mechanical_Q
    return (powers_W[0] * min(1.0, zeta_ceramic / params.zeta_L1)
            + powers_W[1] * min(1.0, zeta_ceramic / params.zeta_B2))


def limits_from_amplitudes(params: MotorParams, voltage_V: float, omega: float,
                           amplitudes_m: tuple[float, float], basis: str,
                           powers_W: tuple[float, float] | None = None
                           ) -> OperatingLimits | None:
    """:class:`OperatingLimits` of the modal amplitudes ``(U, W)`` (m) at the angular drive
    frequency ``omega`` (rad/s) and voltage amplitude ``voltage_V`` (V); ``powers_W`` the L1
    and B2 damper powers (W), default those of harmonic modes, ``omega^2 C U^2 / 2``.
    None when the set carries no shape data."""
    s = params.shape
    if s is None:
        return None
    u, w = amplitudes_m
    if powers_W is None:
        powers_W = (0.5 * omega**2 * params.C_l * u**2, 0.5 * omega**2 * params.C_b * w**2)
    values = {
        "vibration_velocity": omega * max(u * s.velocity_L1, w * s.velocity_B2),
        "stress": s.stress_Pa(u, w),
        "drive_field": voltage_V / s.thickness_m,
        "dissipated_power": float(sum(powers_W)),
        "power_density": ceramic_heat_W(params, powers_W) / s.volume_m3,
    }
    lim = s.limits
    limits = {q: math.nan for q in QUANTITIES}
    if lim is not None:
        for q, (_, field, _, _) in QUANTITIES.items():
            if field is not None:
                limits[q] = float(getattr(lim, field))
    return OperatingLimits(values, limits, (u, w), basis, s.stress_bound_Pa(u, w),
                           STRESS_BOUND if s.combined_stress is None else STRESS_COMBINED)


def operating_limits(params: MotorParams, voltage_V: float, frequency_Hz: float,
                     branch=None) -> OperatingLimits | None:
    """The limits of an operating point: from the steady ``branch``'s damper powers where it
    has them, else from the free response (module docstring). None without shape data."""
    omega = 2.0 * math.pi * frequency_Hz
    amps = None if branch is None else branch_amplitudes_m(params, branch, omega)
    if amps is not None:
        p_b = float(branch.damping_power_B2_W)
        return limits_from_amplitudes(params, voltage_V, omega, amps, "steady state",
                                      (max(float(branch.damping_power_W) - p_b, 0.0), p_b))
    return limits_from_amplitudes(params, voltage_V, omega,
                                  free_amplitudes_m(params, voltage_V, omega), "free response")


def simulation_limits(result) -> OperatingLimits | None:
    """The limits of a :func:`contact.simulate.simulate` run: its steady branch from rest
    (``method="steady"``), else the modal amplitudes of its last window (half the swing of
    ``u_l`` and ``w_b``, with the dissipated power of harmonic modes). None without shape
    data or a branch from rest."""
    p, op = result.params, result.op
    omega = 2.0 * math.pi * op.frequency_Hz
    if result.branches is not None:
        branch = next((b for b in result.branches if b.from_rest), None)
        return None if branch is None else operating_limits(p, op.voltage_V, op.frequency_Hz,
                                                            branch)
    w = result.window
    if w is None or len(w.t_s) < 2:
        return None
    amps = (0.5 * float(w.u_l_m.max() - w.u_l_m.min()),
            0.5 * float(w.w_b_m.max() - w.w_b_m.min()))
    return limits_from_amplitudes(p, op.voltage_V, omega, amps, "transient window")
