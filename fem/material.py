"""Piezoelectric material constants (IEEE stress-charge form) and their plane-stress reduction.

Voigt order everywhere: ``1..6 = 11, 22, 33, 23, 13, 12``; engineering shear strains
(``S6 = 2 S12``). Axis 3 is the poling direction (the plate thickness); axes 1 and 2 lie in
the plate (1: across the width, x; 2: along the length, y).

Constitutive law (IEEE Std 176, e-form)::

    T = c^E S - e^T E
    D = e S + eps^S E
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field, replace

import numpy as np

from bounds import ParameterError

EPS0_F_M = 8.8541878128e-12
"""Vacuum permittivity (F/m)."""

PZT8_SOURCE = (
    "PZT-8 (Navy type III): compliance-form constants s^E, d, eps^T and rho of "
    "D. A. Berlincourt, H. A. Krueger & C. Near, 'Properties of Morgan Electro Ceramic "
    "ceramics', Technical Publication TP-226, Morgan Electro Ceramics, as reprinted in "
    "C. H. Sherman & J. L. Butler, 'Transducers and Arrays for Underwater Sound' (Springer, "
    "2007), Appendix A.5: s11E=11.5, s12E=-3.7, s13E=-4.8, s33E=13.5, s44E=31.9 (1e-12 m^2/N), "
    "s66E=2(s11E-s12E); d31=-97, d33=225, d15=330 (1e-12 C/N); eps11T/eps0=1290, "
    "eps33T/eps0=1000; rho=7600 kg/m^3. Stiffness form derived exactly: c^E=(s^E)^-1, "
    "e=d c^E, eps^S=eps^T-d c^E d^T."
)

PZT4_SOURCE = (
    "PZT-4 (Navy type I): compliance-form constants of Berlincourt, Krueger & Near, Morgan "
    "Electro Ceramics TP-226, as reprinted in Sherman & Butler (2007), Appendix A.5: "
    "s11E=12.3, s12E=-4.05, s13E=-5.31, s33E=15.5, s44E=39.0 (1e-12 m^2/N), "
    "s66E=2(s11E-s12E); d31=-123, d33=289, d15=496 (1e-12 C/N); eps11T/eps0=1475, "
    "eps33T/eps0=1300; rho=7500 kg/m^3. Stiffness form derived as for pzt8(). Not re-read "
    "from the appendix here; checked against the APC chart's Navy I equivalent (APC 840: "
    "k31 0.35, d31 -125, d33 290, d15 480, eps33T/eps0 1275, rho 7600): k31 from these "
    "constants is 0.327."
)

PZT5A_SOURCE = (
    "PZT-5A (Navy type II): compliance-form constants of Berlincourt, Krueger & Near, Morgan "
    "Electro Ceramics TP-226, as reprinted in Sherman & Butler (2007), Appendix A.5, and "
    "identical in A. Erturk & D. J. Inman, 'Piezoelectric Energy Harvesting' (Wiley, 2011), "
    "Appendix E, Table E.1: s11E=16.4, s12E=-5.74, s13E=-7.22, s33E=18.8, s44E=47.5 "
    "(1e-12 m^2/N), s66E=2(s11E-s12E)=44.3; d31=-171, d33=374, d15=584 (1e-12 C/N); "
    "eps11T/eps0=1730, eps33T/eps0=1700; rho=7750 kg/m^3. Stiffness form derived as for "
    "pzt8()."
)

PZT5H_SOURCE = (
    "PZT-5H (Navy type VI, soft): A. Erturk & D. J. Inman, 'Piezoelectric Energy "
    "Harvesting' (Wiley, 2011), Appendix E, Table E.1 (after the Morgan/Berlincourt data): "
    "s11E=16.5, s12E=-4.78, s13E=-8.45, s33E=20.7, s44E=43.5 (1e-12 m^2/N), "
    "s66E=2(s11E-s12E)=42.6; d31=-274, d33=593, d15=741 (1e-12 C/N); eps11T/eps0=3130, "
    "eps33T/eps0=3400; rho=7500 kg/m^3. Stiffness form derived as for pzt8()."
)

APC880_SOURCE = (
    "APC 880 (APC International, hard, Navy III equivalent): 'Physical and Piezoelectric "
    "Properties of APC Materials' chart (americanpiezo.com, rev. 2017): YE11=9.0, YE33=7.2 "
    "(1e10 Pa), so s11E=1/YE11=11.1, s33E=1/YE33=13.9 (1e-12 m^2/N); d31=-95, d33=215, "
    "d15=330 (1e-12 C/N); KT=eps33T/eps0=1050; k31=0.30, kp=0.50, k15=0.55, g15=28e-3 V m/N; "
    "rho=7600 kg/m^3; Q_m=1000; N_L=1725 Hz m. The chart has no s12E, s13E, s44E, eps11T; "
    "they are derived where the chart allows and borrowed where it does not: "
    "eps11T=d15/g15 (eps11T/eps0=1331); s44E=d15^2/(k15^2 eps11T)=30.5e-12 m^2/N; "
    "s12E=-sigma s11E with Poisson's ratio sigma=1-2 k31^2/kp^2=0.28 (the planar coupling "
    "relation kp^2=2 k31^2/(1-sigma)), s12E=-3.11e-12 m^2/N; s13E=-4.8e-12 m^2/N is PZT-8's "
    "(pzt8(), Navy III: an assumption, not an APC figure). Stiffness form derived as for "
    "pzt8()."
)

MATERIAL_NAMES = ("pzt8", "paper", "pzt4", "pzt5a", "pzt5h", "apc880")
"""Names accepted by :func:`get_material`."""

LIMITS_SOURCE = (
    "Mechanical Q_m: APC International materials chart (APC 880 = Navy III: 1000, APC 840 = "
    "Navy I: 500, APC 850 = Navy II: 80) and Morgan TP-226 (PZT-8 1000, PZT-4 500, PZT-5A "
    "75). Maximum vibration velocity: K. Uchino et al., 'Loss mechanisms and high power "
    "piezoelectrics', J. Mater. Sci. 41 (2006) 217-228, and S. Takahashi, S. Hirose & K. "
    "Uchino, J. Am. Ceram. Soc. 77 (1994) 2429-2432: the vibration velocity at which a "
    "resonating bar's temperature rises by 20 K, about 0.3-0.6 m/s for commercial hard PZT "
    "(over 1 m/s only for the Mn/Sb-doped high-power compositions), far less for soft PZT. "
    "Rated dynamic tensile strength: Morgan TP-226 (Berlincourt, Krueger & Near), about "
    "3500 psi = 24 MPa for PZT-4 and PZT-8, 4000 psi = 28 MPa for PZT-5A. AC drive field: "
    "hard PZT is driven to a few hundred V/mm before its loss and depoling rise (Sherman & "
    "Butler 2007, ch. 2; Morgan TP-226), soft PZT to about a tenth of its coercive field. "
    "Heating: 20 K rise (Uchino's criterion) of a plate of about 1 cm^3 with about 8 cm^2 "
    "of surface cooled at about 25 W/(m^2 K) (natural convection and radiation): 0.4 W, "
    "about 0.5 W/cm^3; the figure scales with surface/volume, not with the material. All "
    "are data-sheet orders of magnitude: a real design checks its supplier's figures. "
    "PZT-5H (Navy VI): Q_m 65 (APC 855); AC field 80 V/mm, a tenth of the coercive field "
    "of about 0.8 kV/mm of the 5H-type CTS 3203HD (CTS 'PZT5A & 5H Materials Technical "
    "Data'; the 5A-type 3195HD has 1.2 kV/mm, so PZT-5A's 100 V/mm is on the safe side); "
    "vibration velocity and tensile strength as PZT-5A's (soft PZT; not found for 5H in a "
    "data sheet read here). APC 880: Q_m 1000 and the maximum AC voltage 9-11 V/mil "
    "(354-433 V/mm) of the APC chart, hence 400 V/mm; velocity, strength and heating as "
    "PZT-8's (its Navy type; not APC figures). Read in stored public pages: CTS 'PZT5A & 5H "
    "Materials Technical Data' (https://dtsheet.com/doc/1396950/3195std---cts-corp.): Q_m 80 "
    "(5A types 3195STD/HD), 30 (5H types 3203STD/HD), coercive field 12.0 kV/cm (3195HD), "
    "8.0 kV/cm (3203HD); a supplier's table (https://gnaxel.ru/en/produktsiya/piezoelectric-"
    "elements-and-crystals/tsirkonato-titanat-svintsa/): Q_m PZT-8 800, PZT-4A 600, PZT-4D "
    "800, PZT-5A 60, PZT-5H 60. Not found readable: the tensile strength, the vibration "
    "velocity and the hard types' AC field (cited above from the literature, unread here)."
)
"""Where :data:`MATERIAL_LIMITS` and the materials' ``mechanical_Q`` come from."""


@dataclass(frozen=True)
class MaterialLimits:
    """Operating limits of a piezoceramic (peak values of a sinusoidal drive).

    Attributes
    ----------
    vibration_velocity_m_s : float
        Maximum vibration velocity amplitude at a mode's antinode (m/s): beyond it the
        ceramic's loss and heating rise steeply (Uchino's 20 K criterion).
    dynamic_tensile_stress_Pa : float
        Rated dynamic tensile strength (Pa), against the peak principal stress.
    drive_field_V_m : float
        Largest AC drive field amplitude (V/m) before loss and depoling rise.
    power_density_W_m3 : float
        Heat generated per ceramic volume (W/m^3) that warms a plate of about 1 cm^3 by
        about 20 K in still air.
    mechanical_Q : float
        The ceramic's own mechanical Q (-): its loss's share of a mode's damping ratio
        ``zeta`` is ``1 / (2 Q zeta)``, the share of the modal dampers' power that heats the
        ceramic (the rest heats the mount and the contact).
    source : str
        Where the numbers come from (:data:`LIMITS_SOURCE`).
    """

    vibration_velocity_m_s: float
    dynamic_tensile_stress_Pa: float
    drive_field_V_m: float
    power_density_W_m3: float
    mechanical_Q: float
    source: str = LIMITS_SOURCE


HARD_PZT_LIMITS = MaterialLimits(0.5, 24e6, 400e3, 0.5e6, 1000.0)
"""PZT-8 (Navy III): 0.5 m/s, 24 MPa, 400 V/mm, 0.5 W/cm^3, Q_m 1000 (:data:`LIMITS_SOURCE`)."""

MATERIAL_LIMITS = {
    "pzt8": HARD_PZT_LIMITS,
    "paper": HARD_PZT_LIMITS,  # the paper's stator is PZT-8
    "pzt4": MaterialLimits(0.4, 24e6, 300e3, 0.5e6, 500.0),
    "pzt5a": MaterialLimits(0.1, 28e6, 100e3, 0.5e6, 75.0),
    "pzt5h": MaterialLimits(0.1, 28e6, 80e3, 0.5e6, 65.0),
    "apc880": HARD_PZT_LIMITS,
}
"""Operating limits of the named materials (:data:`LIMITS_SOURCE`)."""

MECHANICAL_Q = {"pzt8": 1000.0, "pzt4": 500.0, "pzt5a": 75.0, "pzt5h": 65.0, "apc880": 1000.0}
"""Data-sheet mechanical quality factor ``Q_m`` (-) of the named materials
(:data:`LIMITS_SOURCE`); the paper's material has none: its set keeps Table 2's damping."""


def combined_quality_factor(*quality_factors: float) -> float:
    """The quality factor of independent losses in one mode: ``1/Q = sum 1/Q_i`` (-).

    Each loss (the material's, the mount's, the contact's) takes its share of the stored
    energy per cycle, so their inverse Q add (e.g. K. Uchino, *Micromechatronics*, loss
    factors; IEEE Std 176). ``math.inf`` is a loss that is absent.

    Raises
    ------
    ValueError
        If no factor is given, or one is not a number > 0.
    """
    if not quality_factors:
        raise ValueError("combined_quality_factor needs at least one quality factor")
    inverse = 0.0
    for q in quality_factors:
        if not (isinstance(q, (int, float)) and q > 0.0):
            raise ValueError(f"a quality factor must be a number > 0, got {q!r}")
        inverse += 1.0 / q
    if inverse == 0.0:
        raise ValueError("at least one quality factor must be finite (a lossless mode has no "
                         "resonance width)")
    return 1.0 / inverse


DEFAULT_Q_MOUNT = 300.0
"""Default mount loss ``Q_mount`` (-): the loss of the stator's mount (holder, bond, preload
spring) as a quality factor, combined with the material's ``Q_m`` in the default damping of
a stator without damping ratios (:func:`material_damping`; a stator file's ``[damping]
Q_mount``). Assembled ultrasonic-motor stators are quoted at mechanical Q of about 100-1000
free, against 1000-2000 for hard PZT itself (docs/designer.md, "The default damping", for
the sources); 300 is the middle of that range on a logarithmic scale. A measured Q of the
mounted stator (impedance analyser: ``f_s / (f_2 - f_1)`` at -3 dB) replaces it."""


def material_damping(material: PiezoMaterial, q_mount: float | None = None,
                     q_contact: float | None = None) -> tuple[float, str]:
    """The default modal damping ratio of a stator of ``material`` and where it comes from.

    The material's data-sheet ``Q_m`` combined with the mount's and the contact's losses
    (:func:`combined_quality_factor`), ``zeta = 1 / (2 Q)``, the same in both modes.

    Parameters
    ----------
    material : PiezoMaterial
        The ceramic; its ``mechanical_Q`` must be known.
    q_mount : float, optional
        The mount's quality factor (-), as a stator file's ``[damping] Q_mount`` gives it;
        default :data:`DEFAULT_Q_MOUNT`, said as the default.
    q_contact : float, optional
        A lossy contact layer's quality factor (-); default none (no such loss).

    Returns
    -------
    zeta : float
        The damping ratio of L1 and of B2 (-).
    origin : str
        Where it comes from, for :func:`validation.summaries.damping_line`.

    Raises
    ------
    ValueError
        If the material has no ``Q_m`` (the paper's: its set keeps Table 2's ratios).
    """
    if material.mechanical_Q is None:
        raise ValueError(f"material {material.name!r} has no data-sheet mechanical Q_m")
    mount = (f"the default Q_mount = {DEFAULT_Q_MOUNT:g}" if q_mount is None
             else f"[damping] Q_mount = {q_mount:g}")
    contact = "" if q_contact is None else f" and [damping] Q_contact = {q_contact:g}"
    q = combined_quality_factor(material.mechanical_Q,
                                DEFAULT_Q_MOUNT if q_mount is None else q_mount,
                                math.inf if q_contact is None else q_contact)
    return 1.0 / (2.0 * q), (f"material {material.name}'s Q_m = {material.mechanical_Q:g} "
                             f"(data sheet) combined with {mount}{contact}: Q = {q:.4g}, "
                             "zeta = 1/(2 Q)")


def _refused(name: str, kind: str, value: object = None) -> ParameterError:
    """The refusal of ``PiezoMaterial.name``: what it must be (``kind``), with the value
    where one is worth showing."""
    got = "" if value is None else f", got {value!r}"
    return ParameterError(name, value, kind=kind, label=f"PiezoMaterial.{name}",
                          message=f"PiezoMaterial.{name} must be {kind}{got}")


def _frozen(a: np.ndarray, shape: tuple[int, int], name: str) -> np.ndarray:
    arr = np.array(a, dtype=float)
    if arr.shape != shape:
        raise _refused(name, f"of shape {shape}", arr.shape)
    if not np.all(np.isfinite(arr)):
        raise _refused(name, "finite")
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class PiezoMaterial:
    """Linear piezoelectric material in IEEE stress-charge (e) form.

    Attributes
    ----------
    name : str
        Short identifier.
    cE_Pa : numpy.ndarray
        6x6 elastic stiffness at constant electric field (Pa), Voigt order 11,22,33,23,13,12.
    e_C_m2 : numpy.ndarray
        3x6 piezoelectric stress constants (C/m^2).
    epsS_F_m : numpy.ndarray
        3x3 permittivity at constant strain (F/m).
    rho_kg_m3 : float
        Mass density (kg/m^3).
    source : str
        Where the numbers come from.
    mechanical_Q : float or None
        Data-sheet mechanical quality factor ``Q_m`` (-); None when unknown (the paper's
        material, inline constants without a base).
    limits : MaterialLimits or None
        Operating limits (peak vibration velocity, dynamic tensile strength, drive field,
        heating); None when unknown.

    Notes
    -----
    Arrays are stored read-only; equality and hashing use their values, so a material can key
    an ``functools.lru_cache``.
    """

    name: str
    cE_Pa: np.ndarray
    e_C_m2: np.ndarray
    epsS_F_m: np.ndarray
    rho_kg_m3: float
    source: str = field(default="unspecified")
    mechanical_Q: float | None = None
    limits: MaterialLimits | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "cE_Pa", _frozen(self.cE_Pa, (6, 6), "cE_Pa"))
        object.__setattr__(self, "e_C_m2", _frozen(self.e_C_m2, (3, 6), "e_C_m2"))
        object.__setattr__(self, "epsS_F_m", _frozen(self.epsS_F_m, (3, 3), "epsS_F_m"))
        if not np.allclose(self.cE_Pa, self.cE_Pa.T, rtol=1e-12, atol=0.0):
            raise _refused("cE_Pa", "symmetric")
        if np.any(np.linalg.eigvalsh(self.cE_Pa) <= 0.0):
            raise _refused("cE_Pa", "positive definite")
        if np.any(np.linalg.eigvalsh(self.epsS_F_m) <= 0.0):
            raise _refused("epsS_F_m", "positive definite")
        if not (np.isfinite(self.rho_kg_m3) and self.rho_kg_m3 > 0.0):
            raise _refused("rho_kg_m3", "> 0", self.rho_kg_m3)
        q = self.mechanical_Q
        if q is not None and not (np.isfinite(q) and q > 0.5):
            raise _refused("mechanical_Q", "> 0.5 or None", q)

    def _key(self) -> tuple:
        return (
            self.name,
            self.cE_Pa.tobytes(),
            self.e_C_m2.tobytes(),
            self.epsS_F_m.tobytes(),
            float(self.rho_kg_m3),
            self.source,
            self.mechanical_Q,
            self.limits,
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, PiezoMaterial):
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self) -> int:
        return hash(self._key())

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary (nested lists, SI units in the keys)."""
        return {
            "name": self.name,
            "cE_Pa": self.cE_Pa.tolist(),
            "e_C_m2": self.e_C_m2.tolist(),
            "epsS_F_m": self.epsS_F_m.tolist(),
            "rho_kg_m3": float(self.rho_kg_m3),
            "source": self.source,
            "mechanical_Q": self.mechanical_Q,
            "limits": None if self.limits is None else {
                k: v for k, v in asdict(self.limits).items() if k != "source"},
        }


def _transversely_isotropic_s(
    s11: float, s12: float, s13: float, s33: float, s44: float
) -> np.ndarray:
    s = np.zeros((6, 6))
    s[0, 0] = s[1, 1] = s11
    s[0, 1] = s[1, 0] = s12
    s[0, 2] = s[2, 0] = s[1, 2] = s[2, 1] = s13
    s[2, 2] = s33
    s[3, 3] = s[4, 4] = s44
    s[5, 5] = 2.0 * (s11 - s12)
    return s


def _from_compliance(name: str, s_e6: tuple[float, float, float, float, float],
                     d3: tuple[float, float, float], eps_t: tuple[float, float], rho: float,
                     source: str) -> PiezoMaterial:
    """A transversely isotropic ceramic from its compliance-form data-sheet constants:
    ``s_e6 = (s11E, s12E, s13E, s33E, s44E)`` (m^2/N), ``d3 = (d31, d33, d15)`` (C/N),
    ``eps_t = (eps11T, eps33T) / eps0`` (-), ``rho`` (kg/m^3); ``c^E = (s^E)^-1``,
    ``e = d c^E``, ``eps^S = eps^T - d c^E d^T``, with its ``Q_m`` and limits from
    :data:`MECHANICAL_Q` and :data:`MATERIAL_LIMITS`."""
    s_e = _transversely_isotropic_s(*s_e6)
    d = np.zeros((3, 6))
    d[2, 0] = d[2, 1] = d3[0]
    d[2, 2] = d3[1]
    d[0, 4] = d[1, 3] = d3[2]
    eps = np.diag([eps_t[0], eps_t[0], eps_t[1]]) * EPS0_F_M
    c_e = np.linalg.inv(s_e)
    c_e = 0.5 * (c_e + c_e.T)
    eps_s = eps - d @ c_e @ d.T
    return PiezoMaterial(
        name=name, cE_Pa=c_e, e_C_m2=d @ c_e, epsS_F_m=0.5 * (eps_s + eps_s.T),
        rho_kg_m3=rho, source=source, mechanical_Q=MECHANICAL_Q.get(name),
        limits=MATERIAL_LIMITS.get(name),
    )


def pzt8() -> PiezoMaterial:
    """PZT-8 in stress-charge form, derived from the published compliance-form constants.

    Returns
    -------
    PiezoMaterial
        ``c^E = (s^E)^-1``, ``e = d c^E``, ``eps^S = eps^T - d c^E d^T`` (see
        :data:`PZT8_SOURCE` for the numbers and the reference), ``Q_m = 1000`` and the hard
        PZT limits (:data:`LIMITS_SOURCE`).
    """
    return _from_compliance("pzt8", (11.5e-12, -3.7e-12, -4.8e-12, 13.5e-12, 31.9e-12),
                            (-97e-12, 225e-12, 330e-12), (1290.0, 1000.0), 7600.0, PZT8_SOURCE)


def pzt4() -> PiezoMaterial:
    """PZT-4 (Navy type I, hard) from :data:`PZT4_SOURCE`, ``Q_m = 500``."""
    return _from_compliance("pzt4", (12.3e-12, -4.05e-12, -5.31e-12, 15.5e-12, 39.0e-12),
                            (-123e-12, 289e-12, 496e-12), (1475.0, 1300.0), 7500.0, PZT4_SOURCE)


def pzt5a() -> PiezoMaterial:
    """PZT-5A (Navy type II, soft) from :data:`PZT5A_SOURCE`, ``Q_m = 75``."""
    return _from_compliance("pzt5a", (16.4e-12, -5.74e-12, -7.22e-12, 18.8e-12, 47.5e-12),
                            (-171e-12, 374e-12, 584e-12), (1730.0, 1700.0), 7750.0,
                            PZT5A_SOURCE)


def paper_material() -> PiezoMaterial:
    """The paper's Table 1 constants completed with PZT-8 values where Table 1 is silent.

    Table 1 gives ``c^E_11 = 12.6e10 Pa``, ``c^E_66 = 3.46e10 Pa``, ``e31 = -5.2 C/m^2`` and
    ``rho = 7600 kg/m^3``. Transverse isotropy about the poling axis is kept: ``c^E_22 = c^E_11``,
    ``e32 = e31`` and ``c^E_12 = c^E_11 - 2 c^E_66``. Every other constant
    (``c^E_13, c^E_33, c^E_44, e33, e15, eps^S``) is taken from :func:`pzt8`.
    """
    base = pzt8()
    c = base.cE_Pa.copy()
    c11, c66 = 12.6e10, 3.46e10
    c[0, 0] = c[1, 1] = c11
    c[5, 5] = c66
    c[0, 1] = c[1, 0] = c11 - 2.0 * c66
    e = base.e_C_m2.copy()
    e[2, 0] = e[2, 1] = -5.2
    return replace(
        base,
        name="paper",
        cE_Pa=c,
        e_C_m2=e,
        rho_kg_m3=7600.0,
        mechanical_Q=None,  # the paper's set keeps Table 2's damping
        limits=MATERIAL_LIMITS["paper"],
        source=(
            "Li, Yao & Wu (2016) Table 1: cE11=cE22=12.6e10 Pa, cE66=3.46e10 Pa, "
            "e31=e32=-5.2 C/m^2, rho=7600 kg/m^3; cE12=cE11-2cE66 (transverse isotropy); "
            "cE13, cE33, cE44, e33, e15 and eps^S from pzt8(): " + PZT8_SOURCE
        ),
    )


def pzt5h() -> PiezoMaterial:
    """PZT-5H (Navy type VI, soft) from :data:`PZT5H_SOURCE`, ``Q_m = 65``."""
    return _from_compliance("pzt5h", (16.5e-12, -4.78e-12, -8.45e-12, 20.7e-12, 43.5e-12),
                            (-274e-12, 593e-12, 741e-12), (3130.0, 3400.0), 7500.0,
                            PZT5H_SOURCE)


def apc880() -> PiezoMaterial:
    """APC 880 (APC International's hard PZT, Navy III) from :data:`APC880_SOURCE`.

    ``s12E``, ``s44E`` and ``eps11T`` are derived from the chart's couplings and voltage
    constants, ``s13E`` is PZT-8's (the chart has none); ``Q_m = 1000``.
    """
    s11, s33 = 1.0 / 9.0e10, 1.0 / 7.2e10
    eps11_t = 330e-12 / 28e-3  # d15 / g15 (F/m)
    s44 = (330e-12) ** 2 / (0.55 ** 2 * eps11_t)  # d15^2 / (k15^2 eps11T)
    poisson = 1.0 - 2.0 * 0.30 ** 2 / 0.50 ** 2  # kp^2 = 2 k31^2 / (1 - sigma)
    return _from_compliance("apc880", (s11, -poisson * s11, -4.8e-12, s33, s44),
                            (-95e-12, 215e-12, 330e-12), (eps11_t / EPS0_F_M, 1050.0), 7600.0,
                            APC880_SOURCE)


_FACTORIES = {"pzt8": pzt8, "paper": paper_material, "pzt4": pzt4, "pzt5a": pzt5a,
              "pzt5h": pzt5h, "apc880": apc880}


def get_material(name: str | PiezoMaterial) -> PiezoMaterial:
    """Material by name (:data:`MATERIAL_NAMES`, case and hyphens ignored: ``"PZT-5H"``); a
    :class:`PiezoMaterial` passes through.

    Raises
    ------
    ValueError
        If ``name`` is not one of :data:`MATERIAL_NAMES`.
    """
    if isinstance(name, PiezoMaterial):
        return name
    key = str(name).strip().lower().replace("-", "").replace(" ", "")
    if key not in _FACTORIES:
        raise ValueError(f"material must be one of {', '.join(MATERIAL_NAMES)}; got {name!r}")
    return _FACTORIES[key]()


def transverse_coupling(material: PiezoMaterial) -> dict[str, float]:
    """The compliance-form constants of a k31 bar, recovered from the stored e-form.

    Returns
    -------
    dict
        ``s11E_m2_N`` (``(c^E)^-1``), ``d31_C_N`` (``d = e s^E``), ``eps33T_F_m``
        (``eps^S + d c^E d^T``), ``k31 = |d31| / sqrt(s11E eps33T)`` (-) and the length
        mode's frequency constant ``N31_Hz_m = 1 / (2 sqrt(rho s11E))``: a free bar of
        length L, electroded on its faces and short-circuited, resonates at ``N31 / L``.
    """
    s = np.linalg.inv(material.cE_Pa)
    d = material.e_C_m2 @ s
    eps_t = material.epsS_F_m + d @ material.cE_Pa @ d.T
    s11, d31, e33 = float(s[0, 0]), float(d[2, 0]), float(eps_t[2, 2])
    return {"s11E_m2_N": s11, "d31_C_N": d31, "eps33T_F_m": e33,
            "k31": abs(d31) / float(np.sqrt(s11 * e33)),
            "N31_Hz_m": 1.0 / (2.0 * float(np.sqrt(material.rho_kg_m3 * s11)))}


@dataclass(frozen=True)
class ElasticMaterial:
    """An isotropic, non-piezoelectric material a stator's contact tip may be made of.

    Attributes
    ----------
    name : str
        Short identifier (:data:`TIP_MATERIALS`).
    young_Pa : float
        Young's modulus (Pa).
    poisson : float
        Poisson's ratio (-), in (-1, 0.5).
    rho_kg_m3 : float
        Mass density (kg/m^3).
    relative_permittivity : float
        eps_r (-) of the 3D model's potential in the tip (no piezoelectric coupling there).
    source : str
        Where the numbers come from.
    """

    name: str
    young_Pa: float
    poisson: float
    rho_kg_m3: float
    relative_permittivity: float
    source: str

    def stiffness_Pa(self) -> np.ndarray:
        """The 6x6 isotropic stiffness (Pa), Voigt order 11,22,33,23,13,12."""
        e, nu = self.young_Pa, self.poisson
        lam, mu = e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))
        c = np.zeros((6, 6))
        c[:3, :3] = lam
        c[range(3), range(3)] = lam + 2 * mu
        c[range(3, 6), range(3, 6)] = mu
        return c

    def plane_stress_Pa(self) -> np.ndarray:
        """The 3x3 plane-stress stiffness (Pa), order (11, 22, 12), engineering shear."""
        e, nu = self.young_Pa, self.poisson
        return e / (1 - nu**2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])

    def thickness_ratio(self) -> np.ndarray:
        """``a`` of the plane-stress thickness strain ``S3 = -a . [S1, S2, S6]`` (-)."""
        r = self.poisson / (1 - self.poisson)
        return np.array([r, r, 0.0])

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary."""
        return asdict(self)


TIP_MATERIALS = {
    "alumina": ElasticMaterial(
        "alumina", 310e9, 0.22, 3800.0, 9.0,
        "97-99 % alumina, ASTM D2442 Type III / IEC 60672 C-795 (MakeItFrom.com material "
        "card): Young's modulus 310 GPa, Poisson's ratio 0.22, density 3.8 g/cm^3, relative "
        "permittivity 9.0 at 1 Hz. Purer grades are stiffer (99.9 %: about 380 GPa, "
        "3.97 g/cm^3, Kientec's data): give inline constants for them."),
    "steel": ElasticMaterial(
        "steel", 193e9, 0.29, 8000.0, 1.0,
        "AISI 304 stainless steel (UNS S30400; the MatWeb-style data sheet Elgin Fasteners and "
        "Alloys International reprint): modulus of elasticity 193 GPa, Poisson's ratio 0.29, "
        "density 8.0 g/cm^3. A metal tip's own potential is not modelled: the 3D model "
        "treats it as a dielectric of eps_r 1 without piezoelectric coupling (its field is "
        "the fringe beyond the unelectroded end)."),
}
"""Materials a parametric stator's tip may be made of (``[tip] material``)."""


def tip_material(name: str) -> ElasticMaterial:
    """The tip material ``name`` (:data:`TIP_MATERIALS`, case ignored).

    Raises
    ------
    ValueError
        If ``name`` is not one of :data:`TIP_MATERIALS`.
    """
    key = str(name).strip().lower()
    if key not in TIP_MATERIALS:
        raise ValueError(f"a tip material must be one of {', '.join(TIP_MATERIALS)}; got "
                         f"{name!r}")
    return TIP_MATERIALS[key]


@dataclass(frozen=True, eq=False)
class PlaneStressConstants:
    """Effective 2D constants of a thin plate poled through its thickness (plane stress).

    Attributes
    ----------
    c_Pa : numpy.ndarray
        3x3 in-plane stiffness at constant ``E3`` (Pa), order (11, 22, 12) with engineering
        shear strain: ``[T1, T2, T6] = c_Pa @ [S1, S2, S6] - e_C_m2 * E3``.
    e_C_m2 : numpy.ndarray
        Effective piezoelectric constants ``[e31*, e32*, e36*]`` (C/m^2).
    eps33_F_m : float
        Effective thickness permittivity ``eps33*`` (F/m): ``D3 = e_C_m2 @ S + eps33 * E3``.
    c_open_Pa : numpy.ndarray
        3x3 in-plane stiffness at ``D3 = 0`` (Pa): ``c + e e^T / eps33`` (unelectroded plate).
    """

    c_Pa: np.ndarray
    e_C_m2: np.ndarray
    eps33_F_m: float
    c_open_Pa: np.ndarray

    @property
    def e31_C_m2(self) -> float:
        """Effective ``e31*`` (C/m^2)."""
        return float(self.e_C_m2[0])

    @property
    def e32_C_m2(self) -> float:
        """Effective ``e32*`` (C/m^2)."""
        return float(self.e_C_m2[1])

    def young_modulus_Pa(self, axis: int = 1) -> float:
        """Uniaxial in-plane Young's modulus along ``axis`` (0: x/1-axis, 1: y/2-axis) (Pa)."""
        s = np.linalg.inv(self.c_Pa)
        return float(1.0 / s[axis, axis])

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary."""
        return {
            "c_Pa": self.c_Pa.tolist(),
            "e31_C_m2": self.e31_C_m2,
            "e32_C_m2": self.e32_C_m2,
            "eps33_F_m": float(self.eps33_F_m),
            "c_open_Pa": self.c_open_Pa.tolist(),
            "young_modulus_y_Pa": self.young_modulus_Pa(1),
        }


_INPLANE = (0, 1, 5)  # Voigt indices of S1, S2, S6


def plane_stress(material: PiezoMaterial) -> PlaneStressConstants:
    """Plane-stress reduction for a plate poled along 3 with thickness electrodes.

    Assumes ``T3 = T4 = T5 = 0`` (free faces, in-plane motion), ``E1 = E2 = 0`` (electrodes on
    the faces of a thin plate). Eliminating ``S3`` from ``T3 = 0`` gives (``P`` = {1, 2, 6})::

        c*_PQ = c_PQ - c_P3 c_3Q / c_33
        e*_3P = e_3P - e_33 c_3P / c_33
        eps*_33 = eps^S_33 + e_33^2 / c_33

    (derivation in ``docs/fem.md``).
    """
    c = material.cE_Pa
    e3 = material.e_C_m2[2]
    idx = np.array(_INPLANE)
    c33 = c[2, 2]
    c_star = c[np.ix_(idx, idx)] - np.outer(c[idx, 2], c[2, idx]) / c33
    e_star = e3[idx] - e3[2] * c[2, idx] / c33
    eps_star = material.epsS_F_m[2, 2] + e3[2] ** 2 / c33
    c_star = 0.5 * (c_star + c_star.T)
    c_open = c_star + np.outer(e_star, e_star) / eps_star
    for arr in (c_star, e_star, c_open):
        arr.setflags(write=False)
    return PlaneStressConstants(
        c_Pa=c_star, e_C_m2=e_star, eps33_F_m=float(eps_star), c_open_Pa=c_open
    )
