r"""Electrical admittance of the driven electrodes by modal superposition (2D plate model).

What an impedance analyzer measures between the driven electrodes (wired in parallel, with
signs ``polarity``) and ground, the other electrodes grounded, and what an ANSYS harmonic
analysis with an imposed voltage gives.

Derivation
----------
The FE model (:mod:`fem.model`) gives, for a port voltage ``V`` applied to the driven
electrodes (electrode ``e`` at ``p_e V``, ``p_e = +-1``) with the others grounded::

    M u'' + D u' + K u = g V,        Q = g^T u + C0 V,
    g = sum_e p_e G_e (N/V),         C0 = sum_ef p_e p_f C_ef (F, clamped, p_e = +-1),

``K`` being the short-circuit stiffness and ``Q`` the port charge (``sum_e p_e Q_e``). In
harmonic steady state (``e^{j w t}``) ``u = H(w) g V`` with the receptance
``H = (K - w^2 M + j w D)^{-1}``, and the current is ``I = j w Q``::

    Y(w) = I / V = j w [C0 + g^T H(w) g].

With the mass-normalized modes (``K phi_r = w_r^2 M phi_r``, ``phi_r^T M phi_s = delta_rs``)
and modal damping (``phi_r^T D phi_s = 2 zeta_r w_r delta_rs``),
``H = sum_r phi_r phi_r^T / (w_r^2 - w^2 + 2 j zeta_r w_r w)`` over *all* modes. The
rigid-body modes do not appear: ``g`` is a self-equilibrated internal force, ``g^T phi = 0``
for a rigid motion. Keeping the modes ``r in R`` (up to ``cutoff_factor * f_max``) and
writing the others quasi-statically::

    sum_{r not in R} a_r^2 / (w_r^2 - w^2 + ...) ~ sum_{r not in R} a_r^2 / w_r^2
                                                  = g^T K^+ g - sum_{r in R} a_r^2 / w_r^2

(``a_r = g^T phi_r``, ``K^+`` the flexibility on the elastic subspace): the static
correction ``C_res = g^T K^+ g - sum_{r in R} a_r^2 / w_r^2``. Its error in the band is
``O((w / w_{R+1})^2) C_res`` (0.1-1.5 % of ``Y`` at 20-62 kHz with ``cutoff_factor = 3``,
measured on the paper's plate), and it would leave ``Y / (j w) -> C0 + C_res`` instead of
the clamped ``C0`` as ``w -> inf``.
Both are fixed by lumping the unretained modes into one undamped *residual mode* that matches
their first two moments::

    sum_{r not in R} a_r^2 / w_r^2 = C_res,     sum_{r not in R} a_r^2 / w_r^4 = C_res2,
    sum_{r not in R} a_r^2 / (w_r^2 - w^2) ~ A_res / (W_res^2 - w^2),
    W_res^2 = C_res / C_res2,  A_res = C_res^2 / C_res2,

so that the admittance used is

    Y(w) = j w [C0 + A_res / (W_res^2 - w^2)
                + sum_{r in R} a_r^2 / (w_r^2 - w^2 + 2 j zeta_r w_r w)].

``W_res^2`` is a weighted mean of the unretained ``w_r^2`` (weights ``a_r^2 / w_r^4``), hence
above ``w_{R+1}``: no spurious resonance in the band. Both moments come from one static solve
``x = (K - s M)^{-1} g`` at a small negative shift ``s`` (exact identities
``g^T x = sum_r a_r^2 / (w_r^2 - s)``, ``x^T M x = sum_r a_r^2 / (w_r^2 - s)^2``, minus the
retained and rigid-body terms). Asymptotes:

* ``w -> 0``: ``Y / (j w) -> C0 + g^T K^+ g = C_free``, the free static capacitance (exact);
* ``w -> inf``: ``Y / (j w) -> C0``, the clamped capacitance (exact);
* in the band the truncation error is ``O((w / w_{R+1})^4)`` of ``C_res``.

Series resonance ``f_s`` (max of the conductance ``Re Y``) and parallel resonance ``f_p``
(max of the resistance ``Re 1/Y``) pair up at each strongly coupled mode, found between a
maximum of ``|Y|`` and the next minimum; ``k_eff^2 = (f_p^2 - f_s^2) / f_p^2`` is the
coupling of the port (open port: ``K + g g^T / C0``). ``f_s`` is the mode's undamped
frequency for an isolated mode; the ``|Y|`` extrema are not: they part by about
``zeta^2 f^2 / (f_p - f_s)``, which doubled B2's k_eff at ``zeta = 0.01``.

``C_ef`` is the clamped 4x4 capacitance matrix of :mod:`fem.model` (its negative
off-diagonal terms couple neighbours across the gap strips). The inertia coupling of the
thickness motion to the voltages (``M_uV``, ``M_VV`` of :mod:`fem.model`) is left out of the
forced response: it moves the L1 antiresonance by ~2e-4 (11 Hz on the paper's plate).

Sign conventions follow :mod:`fem.model` (``E3 = V/h``); ``Y`` only involves ``g`` squared.
"""

from __future__ import annotations

import math
import numbers
from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
import scipy.sparse.linalg as sla

from bounds import ParameterError
from fem.frozen import freeze_arrays
from fem.geometry import ELECTRODES, PlateStator
from fem.limits import work_factor
from fem.material import PiezoMaterial
from fem.mesh_settings import MeshSettings

RIGID_BODY_LIMIT_HZ = 1.0
"""Modes below this frequency (Hz) are rigid-body modes."""
MAX_FREQUENCY_POINTS = 1_000_000
"""Frequencies of one :func:`plate_admittance` call, times ``LUSM_MAX_WORK``: its admittance
is an array of points x retained modes (0.7 GB at 45 modes; ``lusm admittance`` allows
200 000)."""
DEFAULT_ZETA_OTHER = 0.01
"""Damping ratio of the retained modes other than L1 and B2 (-)."""


@dataclass(frozen=True, eq=False)
class ModalPort:
    """Modal data of one electrical port of the plate.

    Attributes
    ----------
    electrodes : tuple of int
        Driven electrodes.
    polarity : tuple of float
        Sign (+1/-1) of each driven electrode's voltage.
    frequencies_Hz : numpy.ndarray
        Retained elastic short-circuit natural frequencies (Hz), ascending.
    shapes : numpy.ndarray
        Mass-normalized shapes of the retained modes (n_dofs, n_modes).
    a_N_V : numpy.ndarray
        Modal force factors ``a_r = g^T phi_r`` (N/V per sqrt(kg)).
    zeta : numpy.ndarray
        Modal damping ratios (-).
    C0_F : float
        Clamped capacitance of the port (F).
    C_res_F : float
        Static residual ``sum_{r not in R} a_r^2 / w_r^2`` of the unretained modes (F).
    f_res_Hz : float
        Frequency of the residual mode ``W_res / 2 pi`` (Hz), above the retained band.
    C_free_F : float
        Free static capacitance ``C0 + g^T K^+ g`` (F).
    g_N_V : numpy.ndarray
        Port coupling vector (N/V).
    mode_names : tuple of str
        ``'L1'``, ``'B2'`` or ``''`` for each retained mode.
    """

    electrodes: tuple
    polarity: tuple
    frequencies_Hz: np.ndarray
    shapes: np.ndarray
    a_N_V: np.ndarray
    zeta: np.ndarray
    C0_F: float
    C_res_F: float
    f_res_Hz: float
    C_free_F: float
    g_N_V: np.ndarray
    mode_names: tuple

    def coupling(self) -> np.ndarray:
        """Each retained mode's coupling to the port, ``k_r = sqrt(m_r / C_free)`` with its
        motional capacitance ``m_r = a_r^2 / w_r^2`` (-): the k_eff of an isolated mode's
        resonance pair (L1 on an 8.5 mm plate: 0.2657 against 0.2640 from f_s, f_p), 0 for
        a mode the port cannot drive by symmetry (B2 under four electrodes in phase)."""
        w = 2.0 * np.pi * np.asarray(self.frequencies_Hz, dtype=float)
        m = np.asarray(self.a_N_V, dtype=float) ** 2 / w**2
        return np.sqrt(m / self.C_free_F)

    def admittance_S(self, f_Hz: np.ndarray, residual: bool = True) -> np.ndarray:
        """Complex admittance ``Y(f)`` (S) by modal superposition (see the module docstring)."""
        f = np.asarray(f_Hz, dtype=float)
        w = 2.0 * math.pi * f[..., None]
        wr = 2.0 * math.pi * self.frequencies_Hz
        terms = self.a_N_V**2 / (wr**2 - w**2 + 2j * self.zeta * wr * w)
        c = self.C0_F + terms.sum(axis=-1)
        if residual and self.C_res_F > 0.0:
            if math.isinf(self.f_res_Hz):
                c = c + self.C_res_F  # a static remainder
            else:
                w_res2 = (2.0 * math.pi * self.f_res_Hz) ** 2
                c = c + self.C_res_F * w_res2 / (w_res2 - w[..., 0] ** 2)
        return 1j * w[..., 0] * c


@dataclass(frozen=True, eq=False)
class ResonancePair:
    """A resonance/antiresonance pair of the port, as IEEE Std 176 defines them.

    Attributes
    ----------
    f_resonance_Hz : float
        Series resonance ``f_s`` (Hz): the maximum of the conductance ``Re Y``. For an
        isolated mode with modal damping it is the mode's undamped short-circuit frequency
        exactly (``Re Y`` of ``j w a^2 / (w_r^2 - w^2 + 2 j zeta w_r w)`` peaks at ``w_r``).
    f_antiresonance_Hz : float
        Parallel resonance ``f_p`` (Hz): the maximum of the resistance ``Re (1 / Y)``.
    k_eff : float
        ``sqrt((f_p^2 - f_s^2) / f_p^2)`` (-), unbiased by the damping to first order.
    mode : str
        The identified mode behind the peak (``'L1'``, ``'B2'``), ``'B2+L1 (merged)'`` when
        both make one peak (heavy damping or coincident modes), ``'B2 (overlaps L1)'`` when
        they make separate peaks closer than their bandwidths (each ``k_eff`` biased by the
        other mode), or ``''``.
    f_max_abs_Hz, f_min_abs_Hz : float
        The maximum of ``|Y|`` and the following minimum (``f_m``, ``f_n``; Hz), where the
        peak is found. They part from ``f_s``, ``f_p`` by about ``zeta^2 f^2 / (f_p - f_s)``:
        at ``zeta = 0.01`` B2's k_eff from them is 0.175 against 0.092 from ``f_s``, ``f_p``.
    """

    f_resonance_Hz: float
    f_antiresonance_Hz: float
    k_eff: float
    mode: str
    f_max_abs_Hz: float = math.nan
    f_min_abs_Hz: float = math.nan

    def to_dict(self) -> dict[str, object]:
        """JSON-ready dictionary."""
        return {
            "mode": self.mode,
            "f_resonance_Hz": self.f_resonance_Hz,
            "f_antiresonance_Hz": self.f_antiresonance_Hz,
            "k_eff": self.k_eff,
            "f_max_abs_Y_Hz": self.f_max_abs_Hz,
            "f_min_abs_Y_Hz": self.f_min_abs_Hz,
        }


@dataclass(frozen=True, eq=False)
class AdmittanceResult:
    """Admittance of a port over a band.

    Attributes
    ----------
    f_Hz : numpy.ndarray
        Frequencies (Hz).
    Y_S : numpy.ndarray
        Complex admittance (S).
    pairs : tuple of ResonancePair
        Resonance/antiresonance pairs found in the band.
    port : ModalPort
    """

    f_Hz: np.ndarray
    Y_S: np.ndarray
    pairs: tuple
    port: ModalPort

    def __post_init__(self) -> None:
        freeze_arrays(self)  # read-only, as its port's arrays are

    def unpaired_modes(self) -> list[tuple[str, float]]:
        """``(name, f_short_Hz)`` of the identified modes (L1, B2) inside the band that no
        resonance pair found on the grid belongs to although they have one at this damping:
        the grid is too coarse for them (a 5 kHz step over 1 Hz-10 MHz listed neither).
        Modes whose damping leaves no peak on any grid are :meth:`peakless_modes`."""
        return [(name, f) for name, f, state, _ in self._missed if state == "grid"]

    def band_cut_modes(self) -> list[tuple[str, float, tuple[float, float]]]:
        """``(name, f_short_Hz, (f_m_Hz, f_n_Hz))`` of the identified modes inside the band
        whose pair reaches beyond it: the maximum of ``|Y|`` ``f_m`` or the minimum after it
        ``f_n`` (Hz, the pair's ``f_max_abs_Hz``, ``f_min_abs_Hz``) lies outside, and no grid
        inside the band finds it (B2 at 54 137 Hz in a 54 000-54 300 Hz band: its minimum is
        at 54 381 Hz). The band must be widened to include both, not the grid refined."""
        return [(name, f, need) for name, f, state, need in self._missed if state == "band"]

    def peakless_modes(self) -> list[tuple[str, float]]:
        """``(name, f_short_Hz)`` of the identified modes inside the band that the port
        drives but that have no resonance pair on any grid at this damping: their coupling
        is too weak for it (roughly ``k_r^2`` below ``zeta``; one quadrant of the paper's
        plate with Table 2's damping: B2 ``k_r^2`` 0.0056 against ``zeta`` 0.071). A finer
        grid cannot find them; lighter damping can."""
        return [(name, f) for name, f, state, _ in self._missed if state == "peakless"]

    @cached_property
    def _missed(self) -> list[tuple[str, float, str, tuple[float, float]]]:
        """Identified, driven modes in the band without a pair on the grid, each with why:
        ``"grid"`` (a pair of theirs lies in the band: the grid is too coarse), ``"band"``
        (their pair reaches beyond the band; with the span it needs, Hz) or ``"peakless"``
        (no pair at this damping). The pairs are those on a local grid across ten half-power
        bandwidths each side of the mode and its antiresonance, 100 points per bandwidth
        (4 001 to 20 001 points; where the cap binds the coupling far exceeds the damping and
        the peak is the grid's to find), searched as on the user's grid. Kept: the command
        and the report ask for the lists, and the no-pair line again."""
        seen = "+".join(q.mode for q in self.pairs)
        lo, hi = float(self.f_Hz[0]), float(self.f_Hz[-1])
        port = self.port
        out = []
        for name, f, z, k in zip(port.mode_names, port.frequencies_Hz, port.zeta,
                                 port.coupling(), strict=True):
            # a mode the port does not drive has no pair to find on any grid
            if not name or not lo <= f <= hi or name in seen or k < MIN_PORT_COUPLING:
                continue
            half = 10.0 * z * f + 0.5 * k * k * f
            width = 2.0 * half + k * k * f
            local = np.linspace(max(f - half, 0.5 * f), f + half + k * k * f,
                                int(min(20001, max(4001, 50.0 * width / max(z * f, 1e-300)))))
            own = [q for q in resonance_pairs(port, local, check_merges=False)
                   if name in q.mode.split(" ")[0].split("+")]
            inside = [q for q in own if lo <= q.f_max_abs_Hz and q.f_min_abs_Hz <= hi]
            state = "grid" if inside else "band" if own else "peakless"
            need = (own[0].f_max_abs_Hz, own[0].f_min_abs_Hz) if own else (lo, hi)
            out.append((name, float(f), state, need))
        return out

    def to_dict(self) -> dict[str, object]:
        """JSON-ready summary (no arrays of the sweep)."""
        p = self.port
        return {
            "electrodes": list(p.electrodes),
            "polarity": list(p.polarity),
            "f_min_Hz": float(self.f_Hz[0]),
            "f_max_Hz": float(self.f_Hz[-1]),
            "n_points": int(self.f_Hz.size),
            "C0_F": p.C0_F,
            "C_res_F": p.C_res_F,
            "f_residual_mode_Hz": p.f_res_Hz,
            "C_free_F": p.C_free_F,
            "retained_modes": int(p.frequencies_Hz.size),
            "zeta_L1": _zeta_of(p, "L1"),
            "zeta_B2": _zeta_of(p, "B2"),
            "pairs": [q.to_dict() for q in self.pairs],
        }


class TooManyModesError(ValueError):
    """The band asks for more retained modes than the caller allowed (``max_modes``).

    Attributes
    ----------
    f_cut_Hz : float
        The retained band's top, ``cutoff_factor * f_max_Hz`` (Hz).
    n_modes : int
        Modes below ``f_cut_Hz`` (rigid-body modes included).
    max_modes : int
        The limit.
    """

    def __init__(self, f_cut_Hz: float, n_modes: int, max_modes: int) -> None:
        super().__init__(f"{n_modes} modes lie below {f_cut_Hz:.6g} Hz, above the limit of "
                         f"{max_modes}")
        self.f_cut_Hz, self.n_modes, self.max_modes = f_cut_Hz, n_modes, max_modes


def check_mode_count(model, f_max_Hz: float, cutoff_factor: float = 6.0,
                     max_modes: int | None = None) -> int | None:
    """The modes of ``model`` below ``cutoff_factor * f_max_Hz`` (:func:`modes_below`, one
    sparse factorization), or None when the count is not available.

    Raises
    ------
    TooManyModesError
        More than ``max_modes`` of them: before any eigensolve (``lusm admittance`` checks
        it before the design's own modes are solved for its band).
    """
    f_cut = cutoff_factor * f_max_Hz
    count = modes_below(model.K, model.M, f_cut)  # known before any eigensolve: bounded work
    if count is not None and max_modes is not None and count > max_modes:
        raise TooManyModesError(f_cut, count, int(max_modes))
    return count


def modes_below(K, M, f_Hz: float) -> int | None:
    """How many eigenvalues of ``K x = w^2 M x`` lie below ``(2 pi f_Hz)^2``, or None.

    Sylvester's law of inertia: the count is the number of negative pivots of an
    ``L D L^T`` factorization of ``K - (2 pi f)^2 M``. SuperLU gives one when it keeps the
    symmetric ordering and does not pivot (``SymmetricMode``, no diagonal threshold); where it
    pivots anyway, None (the caller falls back to growing the eigensolve). One sparse
    factorization: milliseconds where the eigensolve it replaces takes a minute.
    """
    shift = (2.0 * math.pi * float(f_Hz)) ** 2
    try:
        lu = sla.splu((K - shift * M).tocsc(), permc_spec="MMD_AT_PLUS_A",
                      diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    except RuntimeError:  # exactly singular: the shift sits on an eigenvalue
        return None
    if not np.array_equal(lu.perm_r, lu.perm_c):
        return None
    return int(np.count_nonzero(lu.U.diagonal() < 0.0))


def _zeta_of(port: ModalPort, name: str) -> float | None:
    idx = [i for i, n in enumerate(port.mode_names) if n == name]
    return float(port.zeta[idx[0]]) if idx else None


def _port_vectors(model, electrodes, polarity) -> tuple[np.ndarray, float, tuple, tuple]:
    electrodes = tuple(int(e) for e in electrodes)
    if not electrodes or any(e not in ELECTRODES for e in electrodes) or len(
        set(electrodes)
    ) != len(electrodes):
        raise ValueError(f"electrodes must be distinct numbers in 1..4, got {electrodes!r}")
    pol = (1.0,) * len(electrodes) if polarity is None else tuple(float(p) for p in polarity)
    if len(pol) != len(electrodes) or any(p not in (1.0, -1.0) for p in pol):
        raise ValueError(f"polarity must hold one +1/-1 per electrode, got {polarity!r}")
    model.check_wiring(dict(zip(electrodes, pol, strict=True)))
    g = sum(p * model.G[:, e - 1] for p, e in zip(pol, electrodes, strict=True))
    # clamped port capacitance p^T C p over the driven electrodes (the others grounded): the
    # inter-electrode terms count when neighbours are wired with opposite polarity
    idx = [e - 1 for e in electrodes]
    p = np.asarray(pol, dtype=float)
    c0 = float(p @ model.capacitance_matrix_F[np.ix_(idx, idx)] @ p)
    return np.asarray(g, dtype=float), c0, electrodes, pol


def modal_port(
    model,
    f_max_Hz: float,
    electrodes: tuple[int, ...] | None = None,
    polarity: tuple[float, ...] | None = None,
    zeta_L1: float | None = None,
    zeta_B2: float | None = None,
    zeta_other: float = DEFAULT_ZETA_OTHER,
    cutoff_factor: float = 6.0,
    max_modes: int | None = None,
) -> ModalPort:
    """Retained modes, modal force factors and residual capacitance of a port.

    Parameters
    ----------
    model : fem.model.PiezoPlateModel
        2D plate model (``K``, ``M``, ``G``, ``capacitance_matrix_F``).
    f_max_Hz : float
        Top of the band of interest (Hz); modes up to ``cutoff_factor * f_max_Hz`` are kept.
    electrodes : tuple of int, optional
        Driven electrodes (default: ``model.stator.drive_electrodes``); the others grounded.
    polarity : tuple of float, optional
        +1/-1 per driven electrode (default all +1).
    zeta_L1, zeta_B2 : float
        Damping ratios of L1 and B2 (-), required: the motor's damping is a property of the
        parameter set (``rom``), which ``fem`` does not import; the CLI passes Table 2's.
    zeta_other : float
        Damping ratio of the other retained modes.
    cutoff_factor : float
        Retained band relative to ``f_max_Hz`` (>= 1).
    max_modes : int, optional
        Most modes to compute (ARPACK's work grows as the square of their number: a band
        reaching the top of a fine mesh's spectrum asks for thousands and minutes).

    Raises
    ------
    TooManyModesError
        More than ``max_modes`` modes lie below ``cutoff_factor * f_max_Hz``.
    """
    from fem.modes import identify_modes

    _check_port_options(f_max_Hz, cutoff_factor, zeta_L1, zeta_B2, zeta_other)
    electrodes = model.stator.drive_electrodes if electrodes is None else electrodes
    g, c0, electrodes, pol = _port_vectors(model, electrodes, polarity)
    f_cut = cutoff_factor * f_max_Hz
    count = check_mode_count(model, f_max_Hz, cutoff_factor, max_modes)
    w, v, f, lu, sigma = _band_modes(model, f_cut, count, max_modes)
    v = v / np.sqrt(np.einsum("ir,ir->r", v, model.M @ v))
    a_all = v.T @ g
    c_res, f_res = _residual_mode(model.M, lu, sigma, g, a_all, w, f <= f_cut, f_cut)
    keep = (f >= RIGID_BODY_LIMIT_HZ) & (f <= f_cut)
    fr, vr, ar = f[keep], v[:, keep], a_all[keep]
    names = [""] * fr.size
    try:
        ids = identify_modes(model, fr, vr)
        for name, (i, _, _) in ids.items():
            names[i] = name
    except Exception:  # noqa: BLE001 - a port without L1/B2 in band is still valid
        pass
    zeta = np.array([zeta_L1 if nm == "L1" else zeta_B2 if nm == "B2" else zeta_other
                     for nm in names])
    c_free = c0 + float(np.sum(ar**2 / (2 * math.pi * fr) ** 2)) + c_res
    for arr in (fr, vr, ar, zeta, g):
        arr.setflags(write=False)
    return ModalPort(
        electrodes=electrodes, polarity=pol, frequencies_Hz=fr, shapes=vr, a_N_V=ar, zeta=zeta,
        C0_F=c0, C_res_F=c_res, f_res_Hz=f_res, C_free_F=c_free, g_N_V=g, mode_names=tuple(names),
    )


def _check_port_options(f_max_Hz: float, cutoff_factor: float, zeta_L1: float | None,
                        zeta_B2: float | None, zeta_other: float) -> None:
    """Refuse a band or damping ratio :func:`modal_port` cannot use, naming it."""
    if not (math.isfinite(f_max_Hz) and f_max_Hz > 0):
        raise ValueError(f"f_max_Hz must be > 0, got {f_max_Hz!r}")
    if not cutoff_factor >= 1.0:
        raise ValueError(f"cutoff_factor must be >= 1, got {cutoff_factor!r}")
    if zeta_L1 is None or zeta_B2 is None:
        raise ValueError("zeta_L1 and zeta_B2 are required (damping ratios of L1 and B2)")
    for name, z in (("zeta_L1", zeta_L1), ("zeta_B2", zeta_B2), ("zeta_other", zeta_other)):
        # 0 is refused as the CLI's --zeta refuses it: undamped, the admittance is infinite
        # at each resonance and the grid's peaks (plate_admittance(zeta=0) pairs B2's
        # antiresonance as its resonance, k_eff 0.020 against 0.092) are not the modes'
        if not (math.isfinite(z) and 0.0 < z < 1.0):
            raise ValueError(f"{name} must lie in (0, 1) (an undamped admittance is infinite "
                             f"at resonance), got {z!r}")


def _band_modes(model, f_cut: float, count: int | None, max_modes: int | None):
    """Eigenpairs of ``(K, M)`` up to one mode above ``f_cut`` (Hz), by shift-invert below
    the rigid-body modes; ``count`` modes below the cut when known, else from 24 doubling.

    Returns ``(w, v, f, lu, sigma)``: eigenvalues (rad^2/s^2) by increasing value, their
    vectors, frequencies (Hz, signed), the factorization of ``K - sigma M`` and the shift.

    Raises
    ------
    TooManyModesError
        The band holds more than ``max_modes`` modes.
    """
    K, M = model.K, model.M
    n = K.shape[0]
    sigma = -((2.0 * math.pi * 100.0) ** 2)
    lu = sla.splu((K - sigma * M).tocsc())
    opinv = sla.LinearOperator((n, n), matvec=lu.solve, dtype=float)
    top = n - 2 if max_modes is None else min(n - 2, max(int(max_modes), 1))
    # one mode above the cut shows the band is complete; without a count, grow from 24
    k = min(count + 1, n - 2) if count is not None else min(24, top)
    v0 = np.random.default_rng(0).standard_normal(n)  # fixed start: bit-identical runs
    while True:
        w, v = sla.eigsh(K, k=max(k, 1), M=M, sigma=sigma, OPinv=opinv, which="LM", v0=v0)
        order = np.argsort(w)
        w, v = w[order], v[:, order]
        f = np.sign(w) * np.sqrt(np.abs(w)) / (2.0 * math.pi)
        if f[-1] > f_cut or k >= n - 2:
            return w, v, f, lu, sigma
        if k >= top:
            raise TooManyModesError(f_cut, k + 1, top)
        k = min(2 * k, top)


def _residual_mode(M, lu, sigma: float, g: np.ndarray, a_all: np.ndarray, w: np.ndarray,
                   low: np.ndarray, f_cut: float) -> tuple[float, float]:
    """The modes above the cut as one residual mode: ``(C_res, f_res)`` (F, Hz), from the
    first two moments of the port's static response left by the modes below the cut
    (``low``; ``a_all`` the port's modal force factors of mass-normalized modes)."""
    x = lu.solve(g)
    moment1 = float(g @ x) - float(np.sum(a_all[low] ** 2 / (w[low] - sigma)))
    moment2 = float(x @ (M @ x)) - float(np.sum(a_all[low] ** 2 / (w[low] - sigma) ** 2))
    w_res2 = sigma + moment1 / moment2 if moment1 > 0.0 and moment2 > 0.0 else -math.inf
    if w_res2 >= (2.0 * math.pi * f_cut) ** 2:
        c_res = moment1 * (w_res2 - sigma) / w_res2  # A_res / W_res^2 with A_res = m1^2/m2
        return c_res, math.sqrt(w_res2) / (2.0 * math.pi)
    # every mode retained (nothing left over), or the moments are the roundoff of two nearly
    # equal sums: the truncated modes all lie above the cut, so a residual mode below it is
    # not theirs (it would be a spurious resonance inside a wide band); what is left is at
    # most a static capacitance
    return max(moment1, 0.0), math.inf


def direct_admittance_S(model, port: ModalPort, f_Hz: np.ndarray) -> np.ndarray:
    """Reference admittance from direct harmonic solves (S), no modal truncation.

    At each frequency solves ``(K - w^2 M + j w D) u = g`` (1 V imposed on the port) and
    recovers the charge ``Q = g^T u + C0``; ``Y = j w Q``. ``D`` is the modal damping matrix
    of ``port``: ``D = (M Phi) diag(2 zeta_r w_r) (M Phi)^T`` over the retained modes (the
    unretained modes are undamped), applied through the Woodbury identity.
    """
    from fem.harmonic import modally_damped_solve

    K, M = model.K.tocsc(), model.M.tocsc()
    MPhi = M @ port.shapes
    d = 2.0 * port.zeta * 2.0 * math.pi * port.frequencies_Hz
    g = port.g_N_V
    out = []
    for f in np.atleast_1d(np.asarray(f_Hz, dtype=float)):
        w = 2.0 * math.pi * f
        u = modally_damped_solve(K, M, MPhi, d, g, w)
        out.append(1j * w * (g @ u + port.C0_F))
    return np.array(out)


def _refine_extremum(port: ModalPort, f_lo: float, f_hi: float, sign: float,
                     of=abs) -> float:
    """The minimum of ``sign * of(Y(f))`` on ``[f_lo, f_hi]`` (Hz), a bounded scalar search
    on the modal formula."""
    from scipy.optimize import minimize_scalar

    res = minimize_scalar(
        lambda f: sign * of(port.admittance_S(np.array([f]))[0]),
        bounds=(f_lo, f_hi),
        method="bounded",
        options={"xatol": 1e-9 * f_hi},
    )
    return float(res.x)


def _conductance(y: complex) -> float:
    return y.real


def _resistance(y: complex) -> float:
    return (1.0 / y).real


def resonance_pairs(port: ModalPort, f_Hz: np.ndarray,
                    check_merges: bool = True) -> tuple[ResonancePair, ...]:
    """Series / parallel resonance pairs (IEEE Std 176: maxima of ``Re Y`` and ``Re 1/Y``).

    A peak is a local maximum of ``|Y|`` on the grid followed by a local minimum; both are
    refined by a bounded scalar search on the modal formula, then ``f_s`` (max conductance)
    is searched between the grid point before the ``|Y|`` maximum and the ``|Y|`` minimum,
    ``f_p`` (max resistance) between ``f_s`` and the grid point after the minimum
    (``f_m <= f_s < f_p <= f_n``).

    A peak whose named modes make one peak on this grid but not on a fine grid across them
    (``check_merges``, :func:`_merged_by_the_grid`) is left out: a grid step wider than
    their peaks pairs one mode's resonance with the other's antiresonance
    (``--f-max 1e7 --zeta 0.001``: "B2+L1 (merged)", k_eff 0.306, where B2 has 0.092 and L1
    0.155); the modes are then the grid's to find (:meth:`AdmittanceResult.unpaired_modes`).
    """
    found = _pairs_on(port, f_Hz)
    # one fine-grid check per merged label (two peaks can carry the same one)
    by_grid = {q.mode: _merged_by_the_grid(port, q.mode) for q in found
               if check_merges and q.mode.endswith("(merged)")}
    return _overlapping(port, [q for q in found if not by_grid.get(q.mode, False)])


def _pairs_on(port: ModalPort, f_Hz: np.ndarray) -> list[ResonancePair]:
    """The pairs of :func:`resonance_pairs` on the grid ``f_Hz`` as found, each labelled by
    :func:`_pair_label` alone."""
    f = np.asarray(f_Hz, dtype=float)
    mag = np.abs(port.admittance_S(f))
    maxima = [i for i in range(1, f.size - 1) if mag[i] >= mag[i - 1] and mag[i] > mag[i + 1]]
    minima = [i for i in range(1, f.size - 1) if mag[i] <= mag[i - 1] and mag[i] < mag[i + 1]]
    pairs = []
    for i in maxima:
        after = [j for j in minima if j > i]
        if not after:
            continue
        j = after[0]
        if any(i < m < j for m in maxima):
            continue
        fm = _refine_extremum(port, f[i - 1], f[i + 1], -1.0)
        fn = _refine_extremum(port, f[j - 1], f[j + 1], +1.0)
        fs = _refine_extremum(port, f[i - 1], fn, -1.0, _conductance)
        fp = _refine_extremum(port, fs, f[j + 1], -1.0, _resistance)
        k2 = max((fp**2 - fs**2) / fp**2, 0.0)
        pairs.append(ResonancePair(fs, fp, math.sqrt(k2), _pair_label(port, fs, fp), fm, fn))
    return pairs


def _overlapping(port: ModalPort, pairs: list[ResonancePair]) -> tuple[ResonancePair, ...]:
    """Pairs with one ``"B2+L1 (merged)"`` label on several peaks relabelled: the modes make
    separate peaks closer than their bandwidths, not one. Each is named by its nearer mode,
    ``"B2 (overlaps L1)"`` (``--zeta 0.022`` would show two rows "B2+L1 (merged)" under a
    line saying the modes make one peak)."""
    labels = [q.mode for q in pairs]
    freq = dict(zip(port.mode_names, port.frequencies_Hz, strict=True))
    out = []
    for q in pairs:
        if q.mode.endswith("(merged)") and labels.count(q.mode) > 1:
            names = q.mode.split(" ")[0].split("+")
            near = min(names, key=lambda n: abs(freq[n] - q.f_resonance_Hz))
            others = "+".join(n for n in names if n != near)
            q = replace(q, mode=f"{near} (overlaps {others})")
        out.append(q)
    return tuple(out)


def _merged_by_the_grid(port: ModalPort, label: str) -> bool:
    """Whether the modes of a ``"B2+L1 (merged)"`` peak make separate peaks on a fine grid:
    ten half-power bandwidths beyond the lowest and the highest of them and their coupling
    widths, at least 100 points per narrowest bandwidth (4 001 to 20 001 points), searched
    as any grid is."""
    names = set(label.split(" ")[0].split("+"))
    modes = [(f, z, k) for n, f, z, k in zip(port.mode_names, port.frequencies_Hz, port.zeta,
                                             port.coupling(), strict=True) if n in names]
    if len(modes) < 2:
        return False
    lo = min(f - 10.0 * z * f for f, z, _ in modes)
    hi = max(f + 10.0 * z * f + k * k * f for f, z, k in modes)
    narrowest = min(z * f for f, z, _ in modes)
    n = int(min(20001, max(4001, 100.0 * (hi - lo) / max(narrowest, 1e-300))))
    fine = np.linspace(max(lo, 0.5 * min(f for f, _, _ in modes)), hi, n)
    return not any(q.mode == label for q in _pairs_on(port, fine))


def _pair_label(port: ModalPort, fr: float, fa: float) -> str:
    """Name of the identified mode(s) behind a peak; ``"L1+B2 (merged)"`` when both lie in it.

    A named mode belongs to the peak when its frequency lies within two half-power
    bandwidths (``2 zeta f``) of the resonance-antiresonance interval: with heavy damping or
    coincident frequencies the two modes make one peak, and labelling it with the nearer one
    alone would hide the other.
    """
    inside = []
    for name, fk, zk, kk in zip(port.mode_names, port.frequencies_Hz, port.zeta,
                                port.coupling(), strict=True):
        # a mode the port does not drive makes no part of the peak (B2 at 57.2 kHz lay in
        # the window of L1's peak under four electrodes in phase: "B2+L1 (merged)")
        if name and kk >= MIN_PORT_COUPLING and fr - 2.0 * zk * fk <= fk <= fa + 2.0 * zk * fk:
            inside.append(name)
    named = sorted(set(inside))
    if len(named) > 1:
        return "+".join(named) + " (merged)"
    if named:
        return named[0]
    near = int(np.argmin(np.abs(port.frequencies_Hz - fr)))
    return port.mode_names[near]


MIN_PORT_COUPLING = 1e-3
"""Coupling ``k_r`` (:meth:`ModalPort.coupling`) below which a mode counts as not driven by
the port: its resonance and antiresonance lie 5e-7 apart, no peak. A mode the drive cannot
excite by symmetry has ``k_r`` of roundoff (1e-9 and less)."""

BAND_HALF_WIDTH = 0.15
"""Default admittance band: the design's L1 and B2 (short and open) widened by this fraction
of their mean frequency on each side."""


def design_band_Hz(modes, half_width: float = BAND_HALF_WIDTH) -> tuple[float, float]:
    """A frequency band (Hz) centred on a design's L1 and B2, short and open circuit.

    Parameters
    ----------
    modes : fem.modes.PlateModes
    half_width : float
        Margin on each side as a fraction of the mean of the four frequencies (-).
    """
    fs = [modes.L1.f_short_Hz, modes.L1.f_open_Hz, modes.B2.f_short_Hz, modes.B2.f_open_Hz]
    pad = half_width * float(np.mean(fs))
    return max(min(fs) - pad, 0.5 * min(fs)), max(fs) + pad


def plate_admittance(
    stator: PlateStator | None = None,
    material: PiezoMaterial | str = "pzt8",
    f_min_Hz: float = 45e3,
    f_max_Hz: float = 65e3,
    n_points: int = 2001,
    electrodes: tuple[int, ...] | None = None,
    polarity: tuple[float, ...] | None = None,
    zeta: float | None = None,
    zeta_L1: float | None = None,
    zeta_B2: float | None = None,
    mesh: MeshSettings | None = None,
    cutoff_factor: float = 6.0,
    max_modes: int | None = None,
) -> AdmittanceResult:
    """Admittance ``Y(f)`` of the driven electrodes of a plate over ``[f_min, f_max]``.

    Parameters
    ----------
    stator : PlateStator, optional
        Default: the paper's plate, driven through electrodes 1 and 4.
    material : PiezoMaterial or str
    f_min_Hz, f_max_Hz : float
        Band (Hz), ``0 < f_min < f_max``.
    n_points : int
        Grid points (>= 3).
    electrodes, polarity : tuple, optional
        Port definition (default: ``stator.drive_electrodes``, all +1).
    zeta : float, optional
        One damping ratio for every mode; otherwise ``zeta_L1`` and ``zeta_B2`` for L1 and B2
        and :data:`DEFAULT_ZETA_OTHER` for the others.
    zeta_L1, zeta_B2 : float, optional
        Damping ratios of L1 and B2 (-), required unless ``zeta`` is given.
    mesh : MeshSettings, optional
        The 2D model's mesh (see :func:`fem.model.plate_model`).
    cutoff_factor : float
        Modes up to ``cutoff_factor * f_max`` are superposed; the rest enters the residual.
    max_modes : int, optional
        Most modes to compute (:func:`modal_port`; :class:`TooManyModesError` above it).
    """
    from fem.model import plate_model

    if not (math.isfinite(f_min_Hz) and math.isfinite(f_max_Hz) and 0 < f_min_Hz < f_max_Hz):
        raise ParameterError("f_min_Hz", f_min_Hz, 0.0, f_max_Hz, "Hz", low_open=True,
                             high_open=True, message=f"need 0 < f_min_Hz < f_max_Hz, got "
                             f"{f_min_Hz!r}, {f_max_Hz!r}")
    if isinstance(n_points, bool) or not isinstance(n_points, (int, np.integer)) or n_points < 3:
        raise ParameterError("n_points", n_points, 3, None,
                             message=f"n_points must be an integer >= 3, got {n_points!r}")

    top = MAX_FREQUENCY_POINTS * work_factor()
    if n_points > top:  # an array of points x modes: 1e7 take 56 s and about 7 GB
        raise ParameterError("n_points", n_points, 3, top,
                             reason="the work bound of a library call (LUSM_MAX_WORK=N allows N "
                             "times more)",
                             message=f"n_points must be at most {top:.0f} in a library call, got "
                         f"{n_points} (set LUSM_MAX_WORK=N to allow N times more)")
    # before the model is built
    if zeta is not None and not (isinstance(zeta, numbers.Real) and not isinstance(zeta, bool)
                                 and math.isfinite(zeta) and 0.0 < zeta < 1.0):
        raise ParameterError("zeta", zeta, 0.0, 1.0, low_open=True, high_open=True,
                             reason="an undamped admittance is infinite at resonance",
                             message=f"zeta must lie in (0, 1) (an undamped admittance is "
                             f"infinite at resonance), got {zeta!r}")
    model = plate_model(stator, material, mesh)
    kw = ({"zeta_L1": zeta_L1, "zeta_B2": zeta_B2} if zeta is None
          else {"zeta_L1": zeta, "zeta_B2": zeta, "zeta_other": zeta})
    port = modal_port(model, f_max_Hz, electrodes, polarity, cutoff_factor=cutoff_factor,
                      max_modes=max_modes, **kw)
    f = np.linspace(f_min_Hz, f_max_Hz, int(n_points))
    return AdmittanceResult(f_Hz=f, Y_S=port.admittance_S(f), pairs=resonance_pairs(port, f),
                            port=port)
