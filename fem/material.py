"""Piezoelectric material constants (IEEE stress-charge form) and their plane-stress reduction.

Voigt order everywhere: ``1..6 = 11, 22, 33, 23, 13, 12``; engineering shear strains
(``S6 = 2 S12``). Axis 3 is the poling direction (the plate thickness); axes 1 and 2 lie in
the plate (1: across the width, x; 2: along the length, y).

Constitutive law (IEEE Std 176, e-form)::

    T = c^E S - e^T E
    D = e S + eps^S E
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np

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

MATERIAL_NAMES = ("pzt8", "paper")
"""Names accepted by :func:`get_material`."""


def _frozen(a: np.ndarray, shape: tuple[int, int], name: str) -> np.ndarray:
    arr = np.array(a, dtype=float)
    if arr.shape != shape:
        raise ValueError(f"PiezoMaterial.{name} must have shape {shape}, got {arr.shape}")
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"PiezoMaterial.{name} must be finite")
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

    def __post_init__(self) -> None:
        object.__setattr__(self, "cE_Pa", _frozen(self.cE_Pa, (6, 6), "cE_Pa"))
        object.__setattr__(self, "e_C_m2", _frozen(self.e_C_m2, (3, 6), "e_C_m2"))
        object.__setattr__(self, "epsS_F_m", _frozen(self.epsS_F_m, (3, 3), "epsS_F_m"))
        if not np.allclose(self.cE_Pa, self.cE_Pa.T, rtol=1e-12, atol=0.0):
            raise ValueError("PiezoMaterial.cE_Pa must be symmetric")
        if np.any(np.linalg.eigvalsh(self.cE_Pa) <= 0.0):
            raise ValueError("PiezoMaterial.cE_Pa must be positive definite")
        if np.any(np.linalg.eigvalsh(self.epsS_F_m) <= 0.0):
            raise ValueError("PiezoMaterial.epsS_F_m must be positive definite")
        if not (np.isfinite(self.rho_kg_m3) and self.rho_kg_m3 > 0.0):
            raise ValueError(f"PiezoMaterial.rho_kg_m3 must be > 0, got {self.rho_kg_m3!r}")

    def _key(self) -> tuple:
        return (
            self.name,
            self.cE_Pa.tobytes(),
            self.e_C_m2.tobytes(),
            self.epsS_F_m.tobytes(),
            float(self.rho_kg_m3),
            self.source,
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


def pzt8() -> PiezoMaterial:
    """PZT-8 in stress-charge form, derived from the published compliance-form constants.

    Returns
    -------
    PiezoMaterial
        ``c^E = (s^E)^-1``, ``e = d c^E``, ``eps^S = eps^T - d c^E d^T`` (see
        :data:`PZT8_SOURCE` for the numbers and the reference).
    """
    s_e = _transversely_isotropic_s(11.5e-12, -3.7e-12, -4.8e-12, 13.5e-12, 31.9e-12)
    d = np.zeros((3, 6))
    d[2, 0] = d[2, 1] = -97e-12
    d[2, 2] = 225e-12
    d[0, 4] = d[1, 3] = 330e-12
    eps_t = np.diag([1290.0, 1290.0, 1000.0]) * EPS0_F_M
    c_e = np.linalg.inv(s_e)
    c_e = 0.5 * (c_e + c_e.T)
    e = d @ c_e
    eps_s = eps_t - d @ c_e @ d.T
    return PiezoMaterial(
        name="pzt8",
        cE_Pa=c_e,
        e_C_m2=e,
        epsS_F_m=0.5 * (eps_s + eps_s.T),
        rho_kg_m3=7600.0,
        source=PZT8_SOURCE,
    )


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
        source=(
            "Li, Yao & Wu (2016) Table 1: cE11=cE22=12.6e10 Pa, cE66=3.46e10 Pa, "
            "e31=e32=-5.2 C/m^2, rho=7600 kg/m^3; cE12=cE11-2cE66 (transverse isotropy); "
            "cE13, cE33, cE44, e33, e15 and eps^S from pzt8(): " + PZT8_SOURCE
        ),
    )


def get_material(name: str | PiezoMaterial) -> PiezoMaterial:
    """Material by name (``'pzt8'`` or ``'paper'``); a :class:`PiezoMaterial` passes through.

    Raises
    ------
    ValueError
        If ``name`` is not one of :data:`MATERIAL_NAMES`.
    """
    if isinstance(name, PiezoMaterial):
        return name
    key = str(name).strip().lower().replace("-", "")
    if key == "pzt8":
        return pzt8()
    if key == "paper":
        return paper_material()
    raise ValueError(f"material must be one of {', '.join(MATERIAL_NAMES)}; got {name!r}")


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
