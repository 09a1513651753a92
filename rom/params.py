"""The reduced-order parameter set of a motor: one frozen dataclass shared by every source.

The contact model (Li, Yao & Wu 2016, Eqs. 4-19) needs, for the stator's L1 and B2 modes,
the modal mass, damping, stiffness and force factor, the mode-shape values at the two ends
of the stator (``y = 0``: preload end, ``y = l``: contact tip), and the contact and slider
constants. Whatever produced them (the paper's Table 2, beam theory, an FE model), they
arrive here in the same shape and are validated once.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, fields, replace

from bounds import ParameterError, ParameterTypeError
from rom.shape_data import ShapeData

GRAVITY_M_S2 = 9.81
"""Gravitational acceleration used for the slider weight on the linear guide (m/s^2)."""

PARAM_UNITS = {
    "M_l": "kg", "C_l": "N s/m", "K_l": "N/m", "A_l": "N/V", "phi_L0": "-", "phi_Ll": "-",
    "M_b": "kg", "C_b": "N s/m", "K_b": "N/m", "A_b": "N/V", "phi_B0": "-", "phi_Bl": "-",
    "k_contact": "N/m", "M_slider": "kg", "mu_s": "-", "mu_d": "-", "mu_sd": "-", "a_mu": "-",
    "b_mu": "1/m", "eta_N": "-", "eta_T": "-", "f_L1_Hz": "Hz", "f_B2_Hz": "Hz",
    "zeta_L1": "-", "zeta_B2": "-",
}
"""SI unit of every key of :meth:`MotorParams.to_dict` (``source`` is text)."""

# Fields that must be strictly positive; all others must merely be finite.
_POSITIVE = (
    "M_l", "C_l", "K_l", "M_b", "C_b", "K_b", "k_contact", "M_slider", "mu_s", "mu_d",
)
_NON_NEGATIVE = ("mu_sd", "a_mu", "b_mu")


def _refused(name: str, value: object, cls: type[ParameterError] = ParameterError,
             **range_: object) -> ParameterError:
    """The refusal of field ``name`` of :class:`MotorParams` in its :data:`PARAM_UNITS` unit
    (``'-'``: none), its message naming ``MotorParams.<name>``."""
    unit = PARAM_UNITS.get(name, "")
    return cls(name, value, unit="" if unit == "-" else unit, label=f"MotorParams.{name}",
               **range_)


DERIVED_KEYS = ("eta_N", "eta_T", "f_L1_Hz", "f_B2_Hz", "zeta_L1", "zeta_B2")
"""Keys of :meth:`MotorParams.to_dict` computed from the stored fields, not stored."""


@dataclass(frozen=True)
class MotorParams:
    """Reduced-order parameters of a two-mode (L1 + B2) linear ultrasonic motor.

    Attributes
    ----------
    M_l, C_l, K_l : float
        Modal mass (kg), damping (N s/m) and stiffness (N/m) of the L1 mode, Eq. 4.
    A_l : float
        L1 force factor (N/V): the modal force is ``A_l * V0 * sin(omega t)``.
    phi_L0, phi_Ll : float
        L1 mode shape at the preload end ``y = 0`` and at the contact tip ``y = l`` (-).
    M_b, C_b, K_b : float
        Modal mass (kg), damping (N s/m) and stiffness (N/m) of the B2 mode, Eq. 5.
    A_b : float
        B2 force factor (N/V). Its sign sets the direction of motion.
    phi_B0, phi_Bl : float
        B2 mode shape at ``y = 0`` and at the contact tip ``y = l`` (-).
    k_contact : float
        Equivalent normal contact stiffness k between tip and slider (N/m), Eq. 7.
    M_slider : float
        Slider mass M (kg), Eq. 6.
    mu_s, mu_d : float
        Static and (vibration-free) dynamic friction coefficients of the tip/slider interface.
    mu_sd : float
        Dynamic friction coefficient of the linear guide.
    a_mu : float
        Residual dynamic friction coefficient at large normal vibration amplitude, Eq. 11.
    b_mu : float
        Attenuation factor of Eq. 11 (1/m).
    source : str
        Where the numbers came from (free text, shown in reports).
    shape : rom.shape_data.ShapeData or None
        Per-unit-amplitude velocity and stress of the two shapes, the ceramic's thickness,
        volume and limits (:mod:`contact.operating_limits`); None when unknown (a set
        written without it). Not a model constant: it does not enter the dynamics.

    Notes
    -----
    The load coefficients of the paper are derived, not stored:
    ``eta_N = phi_L0 - phi_Ll`` and ``eta_T = phi_B0 - phi_Bl`` (Eqs. A.7-A.8).
    """

    M_l: float
    C_l: float
    K_l: float
    A_l: float
    phi_L0: float
    phi_Ll: float
    M_b: float
    C_b: float
    K_b: float
    A_b: float
    phi_B0: float
    phi_Bl: float
    k_contact: float
    M_slider: float
    mu_s: float
    mu_d: float
    mu_sd: float
    a_mu: float
    b_mu: float
    source: str = "unspecified"
    shape: ShapeData | None = None

    def __post_init__(self) -> None:
        """Check every field: a :class:`bounds.ParameterError` (``ParameterTypeError`` for a
        value of the wrong kind) names the field, its value and its allowed range."""
        if self.shape is not None and not isinstance(self.shape, ShapeData):
            raise TypeError(f"MotorParams.shape must be a rom.shape_data.ShapeData or None, "
                            f"got {type(self.shape).__name__}")
        for f in fields(self):
            if f.name == "shape":
                continue
            if f.name == "source":
                if not isinstance(self.source, str):  # not 5 or None
                    raise _refused("source", self.source, ParameterTypeError, kind="text")
                continue
            value = getattr(self, f.name)
            # NumPy scalars are real numbers too (np.float32(0.2)); bool is not
            if isinstance(value, bool) or not isinstance(value, numbers.Real):
                raise _refused(f.name, value, ParameterTypeError, kind="a real number")
            value = float(value)
            object.__setattr__(self, f.name, value)
            if not math.isfinite(value):
                raise _refused(f.name, value)
        for name in _POSITIVE:
            if getattr(self, name) <= 0.0:
                raise _refused(name, getattr(self, name), low=0.0, low_open=True)
        for name in _NON_NEGATIVE:
            if getattr(self, name) < 0.0:
                raise _refused(name, getattr(self, name), low=0.0)
        self._check_relations()

    def _check_relations(self) -> None:
        """The checks between fields: the friction law's order and the modes' coupling."""
        if self.mu_d > self.mu_s:
            raise _refused("mu_d", self.mu_d, high=self.mu_s, bound_by="mu_s",
                           reason="kinetic friction cannot exceed static")
        if self.a_mu > self.mu_d:
            raise _refused("a_mu", self.a_mu, low=0.0, high=self.mu_d, bound_by="mu_d",
                           reason="Eq. 11 decays from mu_d to a_mu")
        if self.phi_Ll == self.phi_L0:
            raise _refused("phi_Ll", self.phi_Ll, kind=f"different from phi_L0 = {self.phi_L0:g}",
                           reason="the L1 mode must stretch the stator: eta_N = phi_L0 - "
                                  "phi_Ll = 0 leaves no normal coupling")
        if self.phi_Bl == 0.0:
            raise _refused("phi_Bl", self.phi_Bl, kind="non-zero",
                           reason="the B2 mode must move the contact tip")

    @property
    def eta_N(self) -> float:
        """Normal load coefficient ``phi_L(0) - phi_L(l)`` (-), Eq. A.7."""
        return self.phi_L0 - self.phi_Ll

    @property
    def eta_T(self) -> float:
        """Tangential load coefficient ``phi_B(0) - phi_B(l)`` (-), Eq. A.8."""
        return self.phi_B0 - self.phi_Bl

    @property
    def f_L1_Hz(self) -> float:
        """Undamped L1 natural frequency ``sqrt(K_l/M_l)/(2 pi)`` (Hz)."""
        return math.sqrt(self.K_l / self.M_l) / (2.0 * math.pi)

    @property
    def f_B2_Hz(self) -> float:
        """Undamped B2 natural frequency ``sqrt(K_b/M_b)/(2 pi)`` (Hz)."""
        return math.sqrt(self.K_b / self.M_b) / (2.0 * math.pi)

    @property
    def zeta_L1(self) -> float:
        """L1 modal damping ratio ``C_l / (2 sqrt(K_l M_l))`` (-)."""
        return self.C_l / (2.0 * math.sqrt(self.K_l * self.M_l))

    @property
    def zeta_B2(self) -> float:
        """B2 modal damping ratio ``C_b / (2 sqrt(K_b M_b))`` (-)."""
        return self.C_b / (2.0 * math.sqrt(self.K_b * self.M_b))

    @classmethod
    def from_modal(
        cls,
        *,
        M_l: float,
        K_l: float,
        A_l: float,
        phi_L0: float,
        phi_Ll: float,
        M_b: float,
        K_b: float,
        A_b: float,
        phi_B0: float,
        phi_Bl: float,
        damping_ratios: tuple[float, float],
        base: MotorParams,
        source: str,
        shape: ShapeData | None = None,
    ) -> MotorParams:
        """A stator's modal constants with viscous damping ``C = 2 zeta sqrt(K M)`` from
        ``damping_ratios = (zeta_L1, zeta_B2)`` and the contact, slider and friction
        constants of ``base`` (a modal model of the stator alone cannot give those)."""
        zeta_l, zeta_b = damping_ratios
        return cls(
            M_l=M_l, C_l=2.0 * zeta_l * math.sqrt(K_l * M_l), K_l=K_l, A_l=A_l,
            phi_L0=phi_L0, phi_Ll=phi_Ll,
            M_b=M_b, C_b=2.0 * zeta_b * math.sqrt(K_b * M_b), K_b=K_b, A_b=A_b,
            phi_B0=phi_B0, phi_Bl=phi_Bl,
            k_contact=base.k_contact, M_slider=base.M_slider, mu_s=base.mu_s,
            mu_d=base.mu_d, mu_sd=base.mu_sd, a_mu=base.a_mu, b_mu=base.b_mu,
            source=source, shape=shape,
        )

    def with_(self, **changes: float | str) -> MotorParams:
        """Return a copy with some fields replaced (validated again)."""
        return replace(self, **changes)

    def to_dict(self) -> dict[str, float | str]:
        """All stored fields plus the derived ``eta_N``, ``eta_T``, frequencies and ratios;
        ``shape`` as an object (:meth:`rom.shape_data.ShapeData.to_dict`) or None."""
        d: dict = {f.name: getattr(self, f.name) for f in fields(self) if f.name != "shape"}
        d["shape"] = None if self.shape is None else self.shape.to_dict()
        d.update(
            eta_N=self.eta_N,
            eta_T=self.eta_T,
            f_L1_Hz=self.f_L1_Hz,
            f_B2_Hz=self.f_B2_Hz,
            zeta_L1=self.zeta_L1,
            zeta_B2=self.zeta_B2,
        )
        return d

    @classmethod
    def from_dict(cls, d: dict) -> MotorParams:
        """The parameter set of a :meth:`to_dict` dictionary (``lusm params --json``).

        The derived keys (``eta_N``, ``eta_T``, ``f_L1_Hz``, ``f_B2_Hz``, ``zeta_L1``,
        ``zeta_B2``) may be present; they must then agree with the stored fields to the
        rounding of single precision (:func:`derived_tolerance`: a set written from float32
        data, as a study's dataset may hold it, misses 1e-9 relative), so an
        edit of a derived value is refused instead of silently ignored. So
        may ``units`` (each key's unit, as ``lusm params --json`` writes it), which must be
        :data:`PARAM_UNITS`' own: an edited unit is refused, not converted. A
        ``calibration`` object (the fit of ``lusm calibrate``) is not part of the set and is
        passed over.

        Raises
        ------
        ValueError
            Unknown or missing keys, or a derived value that disagrees (the message names it).
        """
        if not isinstance(d, dict):
            raise ValueError(f"a parameter set must be a JSON object, got {type(d).__name__}")
        stored = [f.name for f in fields(cls)]
        derived = DERIVED_KEYS
        if any(not isinstance(k, str) for k in d):  # named here, not failing in str.join
            raise ValueError(f"a parameter set's keys are names, got "
                             f"{[k for k in d if not isinstance(k, str)]!r}")
        # a calibrated file's fit (``lusm calibrate``), read by calibration.uncertainty
        d = {k: v for k, v in d.items() if k != "calibration"}
        units = d.get("units")
        if "units" in d:  # lusm params --json says each key's unit; SI, not a choice
            if not isinstance(units, dict):
                raise ValueError(f"units must be an object of each key's SI unit, got {units!r}")
            for key, unit in units.items():
                if key not in PARAM_UNITS or unit != PARAM_UNITS[key]:
                    want = (f"{key} is in {PARAM_UNITS[key]}" if key in PARAM_UNITS
                            else f"a parameter set has no key {key}")
                    raise ValueError(f"units.{key} = {unit!r}: a parameter set is in SI units "
                                     f"({want}); convert the value instead")
            d = {k: v for k, v in d.items() if k != "units"}
        unknown = sorted(set(d) - set(stored) - set(derived))
        if unknown:
            raise ValueError(f"unknown key(s) {', '.join(unknown)}; a parameter set has "
                             f"{', '.join(stored)}")
        missing = [k for k in stored if k not in d and k not in ("source", "shape")]
        if missing:
            raise ValueError(f"missing key(s) {', '.join(missing)}")
        shape = d.get("shape")
        params = cls(**{k: d[k] for k in stored if k in d and k != "shape"},
                     shape=None if shape is None else ShapeData.from_dict(shape))
        for key in derived:
            if key in d:
                want = getattr(params, key)
                got = d[key]
                if derived_disagrees(params, key, got):
                    raise ValueError(
                        f"{key} = {got!r} disagrees with the stored fields ({want:.10g}); it is "
                        "derived: edit the modal mass, damping, stiffness or mode shapes instead")
        return params


STORAGE_ROUNDOFF = 2.0**-24
"""Unit roundoff of IEEE single precision (float32), the coarsest format a parameter set is
written in (a float32 array, a study's dataset): each stored and each derived value of such a
set carries a relative rounding error of up to this much."""

_ROUNDINGS = 6.0
"""Worst-case roundings, in :data:`STORAGE_ROUNDOFF`, of a frequency or damping ratio written
from single-precision data: ``f = sqrt(K / M) / (2 pi)`` takes half of K's and half of M's
(1), four single-precision operations if it was computed in float32 (the quotient, the square
root, 2 pi and the division by it) and its own storage (1); ``zeta = C / (2 sqrt(K M))`` takes
C's and half of K's and M's (2), three operations and its storage. Doubled in
:func:`derived_tolerance` for the second-order terms and for safety."""


def derived_tolerance(params: MotorParams, key: str) -> float:
    """Largest difference, in the key's SI unit, between a derived key of a written parameter
    set and its value recomputed from the stored fields of ``params``, that rounding alone can
    make (:data:`STORAGE_ROUNDOFF`).

    ``f_L1_Hz``, ``f_B2_Hz``, ``zeta_L1`` and ``zeta_B2`` are products and powers of the stored
    fields: a relative bound, ``2 x 6`` roundings (:data:`_ROUNDINGS`). ``eta_N = phi_L0 -
    phi_Ll`` and ``eta_T = phi_B0 - phi_Bl`` are differences, whose rounding follows the size
    of the shapes, not of the difference (cancellation): ``2 u (|a| + |b| + 2 |a - b|)``, the
    two shapes' roundings, the subtraction's and the storage's.
    """
    u = STORAGE_ROUNDOFF
    if key in ("eta_N", "eta_T"):
        a, b = ((params.phi_L0, params.phi_Ll) if key == "eta_N"
                else (params.phi_B0, params.phi_Bl))
        return 2.0 * u * (abs(a) + abs(b) + 2.0 * abs(a - b))
    if key not in DERIVED_KEYS:
        raise ValueError(f"{key!r} is not a derived key ({', '.join(DERIVED_KEYS)})")
    return 2.0 * _ROUNDINGS * u * abs(getattr(params, key))


def derived_disagrees(params: MotorParams, key: str, value: object) -> bool:
    """Whether ``value``, given for the derived ``key`` of a written set, is not what the
    stored fields of ``params`` give, beyond rounding (:func:`derived_tolerance`): an edit.
    Not a real number (text, a bool) disagrees; NumPy scalars are numbers (an ``np.float32``
    derived value is compared like any other)."""
    # bool is an int, NumPy's bool no number at all
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        return True
    got = float(value)
    want = getattr(params, key)
    return not (math.isfinite(got) and abs(got - want) <= derived_tolerance(params, key))


def require_params(params: object) -> MotorParams:
    """``params`` if it is a :class:`MotorParams`, else a TypeError saying how to make one (a
    dict or None reached the kernels' set-up as an AttributeError on ``K_l``)."""
    if not isinstance(params, MotorParams):
        raise TypeError(f"params must be a rom.params.MotorParams (rom.table2(), "
                        f"rom.sources.get_params(...) or MotorParams.from_dict(d)), got "
                        f"{type(params).__name__}")
    return params

