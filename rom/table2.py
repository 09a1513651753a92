"""The paper's published parameter set (Tables 1-2, tip values from Eq. 3).

Only numbers printed in the paper are used; nothing here is fitted. Known inconsistencies
(Table 2 puts L1 above B2 while the paper's ANSYS puts it below; Table 1's ``c^E_11`` gives an
L1 frequency far above 40 kHz) are documented in ``docs/contact.md`` and ``docs/fem.md``.
"""

from __future__ import annotations

from fem.beam_shapes import phi_B, phi_L
from rom.params import MotorParams
from rom.shape_data import ShapeData, beam_shape_data

TABLE1 = {
    "length_m": 30e-3,
    "width_m": 7.5e-3,
    "thickness_m": 3e-3,
    "rho_kg_m3": 7600.0,
    "cE11_Pa": 12.6e10,
    "cE66_Pa": 3.46e10,
    "e31_C_m2": -5.2,
    "M_slider_kg": 0.2,
    "mu_s": 0.5,
    "mu_d": 0.35,
    "mu_sd": 0.04,
    "preload_spring_N_m": 4000.0,
}
"""Table 1 of the paper, physical parameters of the motor (SI units as keyed)."""

TABLE2 = {
    "M_l_kg": 0.0029,
    "C_l_Ns_m": 173.0,
    "K_l_N_m": 1.888e8,
    "M_b_kg": 0.005,
    "C_b_Ns_m": 178.0,
    "K_b_N_m": 3.147e8,
    "A_l_N_V": 0.1086,
    "A_b_N_V": -0.1246,
    "k_contact_N_m": 1.7378e7,
}
"""Table 2 of the paper, parameters of the numerical simulation (SI units as keyed)."""

FRICTION_LAW = {"a_mu": 0.15, "b_mu_per_m": 1e6}
"""Eq. 11 constants chosen in Section 4.1 of the paper."""

PAPER_ANSYS_HZ = {"L1": 39841.0, "B2": 40257.0}
"""Natural frequencies the paper reports from ANSYS (Section 4) (Hz)."""

PAPER_DRIVE_HZ = 40e3
"""Excitation frequency used throughout the paper's simulations (Hz)."""


def table1_shape_data() -> ShapeData:
    """Appendix A's beam shapes on Table 1's plate (30 x 7.5 x 3 mm, ``cE11`` = 12.6e10 Pa,
    PZT-8 limits): the velocity and stress per unit modal amplitude of Table 2's set."""
    from fem.material import MATERIAL_LIMITS

    return beam_shape_data(TABLE1["length_m"], TABLE1["width_m"], TABLE1["thickness_m"],
                           TABLE1["cE11_Pa"], "paper", MATERIAL_LIMITS["paper"],
                           "Appendix A beam shapes (Eq. 3) on Table 1's plate")


def table2() -> MotorParams:
    """The paper's published parameter set as a :class:`MotorParams`.

    Modal constants from Table 2, slider and friction constants from Table 1 and
    Section 4.1, tip mode values from Eq. 3 at ``y = 0`` and ``y = l``.
    """
    length = TABLE1["length_m"]
    # Table 2's mass, damping, stiffness and force factor of each mode (l: L1, b: B2)
    modal = {f"{q}_{mode}": TABLE2[f"{q}_{mode}_{unit}"]
             for mode in ("l", "b") for q, unit in (("M", "kg"), ("C", "Ns_m"), ("K", "N_m"),
                                                    ("A", "N_V"))}
    return MotorParams(
        **modal,
        phi_L0=float(phi_L(0.0, length)),
        phi_Ll=float(phi_L(length, length)),
        phi_B0=float(phi_B(0.0, length)),
        phi_Bl=float(phi_B(length, length)),
        k_contact=TABLE2["k_contact_N_m"],
        M_slider=TABLE1["M_slider_kg"],
        mu_s=TABLE1["mu_s"],
        mu_d=TABLE1["mu_d"],
        mu_sd=TABLE1["mu_sd"],
        a_mu=FRICTION_LAW["a_mu"],
        b_mu=FRICTION_LAW["b_mu_per_m"],
        source="Li, Yao & Wu (2016), Tables 1-2 and Eq. 3",
        shape=table1_shape_data(),
    )
