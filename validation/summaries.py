"""Plain-dict summaries of results: the one source of the numbers the CLI and report print.

:func:`damping_line` is the one sentence every speed printed by ``lusm`` carries: the modal
damping ratios in use and where they came from (Table 2, a stator file's ``[damping]``, a
``--params`` file).
"""

from __future__ import annotations

import json
import math
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:  # the contact stack is imported by the functions that need it
    from contact.maps import StickSlipMap
    from contact.simulate import SimulationResult
    from rom.params import MotorParams


def plate_text(stator, fmt: str = "g") -> str:
    """The stator's dimensions for headers: ``'plate 30 x 7.5 x 3 mm'``, and for a parametric
    stator its features after the plate, e.g. ``'plate 35 x 9.617 x 3 mm + tip 1 mm (2 mm
    wide), chamfers 1.5 mm'`` (the plate keeps its own length; the tip is added)."""
    dims = (stator.length_m * 1e3, stator.width_m * 1e3)
    text = (f"plate {dims[0]:{fmt}} x {dims[1]:{fmt}} x {stator.thickness_m * 1e3:.4g} mm"
            if fmt != "g" else
            f"plate {dims[0]:g} x {dims[1]:g} x {stator.thickness_m * 1e3:g} mm")
    features = getattr(stator, "features_text", None)
    return text + (features() if callable(features) else "")


def table2_damping() -> str:
    """Origin text of the paper's damping (the ``table2`` set)."""
    return "Table 2 (Li, Yao & Wu 2016)"


def borrowed_damping(source: str) -> str:
    """Origin text of the damping of a ``beam`` or ``fem`` set without its own ratios."""
    return f"Table 2's ratios, borrowed by the {source} set"


def plate_damping(material, what: str) -> tuple[tuple[float, float] | None, str]:
    """The damping of a stator given without damping ratios (plate options, ``--source fem``
    or ``beam``), as a stator file without ``[damping]`` gets it: the material's data-sheet
    ``Q_m`` combined with the default mount loss (:func:`fem.material.material_damping`), the
    same ratio in both modes; a material without ``Q_m`` (the paper's) keeps Table 2's
    ratios, borrowed. ``what`` names the set in the origin text (``"fem"``, ``"beam"``).

    Returns
    -------
    ratios : (float, float) or None
        ``(zeta_L1, zeta_B2)``; None for Table 2's.
    origin : str
        Where they come from (:func:`validation.summaries.damping_line`).
    """
    from fem.material import material_damping

    if material.mechanical_Q is None:
        return None, (f"{borrowed_damping(what)}; material {material.name} has no data-sheet "
                      "Q_m")
    z, origin = material_damping(material)
    return (z, z), f"{origin}; the {what} set has no damping ratios of its own"


UNEXCITED_FORCE_RATIO = 1e-6
"""|A_b| / |A_l| (or the inverse) below which the drive is said to excite no B2 (no L1)."""


def unexcited_modes(params: MotorParams, electrodes=None) -> list[str]:
    """What to say of a drive whose force factor of one mode is roundoff beside the other's
    (none: ``[]``): four electrodes in phase give A_b = 1.6e-15 N/V, a motor at 0 m/s with
    0.54 W of input and a 'stall force' of 0 N, and --frequency auto the maximum of a noise
    ellipse. The single-point commands warn it; a study keeps it in each geometry's
    ``warnings``. ``electrodes`` None: a parameter set of its own (``--params``), whose
    force factors are its A_l and A_b."""
    a_l, a_b = abs(params.A_l), abs(params.A_b)
    if electrodes is None and a_l == 0.0 and a_b == 0.0:
        return ["the parameter set's force factors are A_l = A_b = 0 N/V: the drive excites "
                "neither L1 nor B2, the tip does not move and the motor gives no thrust"]
    if electrodes is None:
        return [f"the parameter set's drive excites no {name} ({'A_b' if name == 'B2' else 'A_l'}"
                f" = {small:.3g} N/V against {big:.3g} N/V): the tip does not trace an "
                "ellipse and the motor gives no thrust"
                for name, small, big in (("B2", a_b, a_l), ("L1", a_l, a_b))
                if small <= UNEXCITED_FORCE_RATIO * big]
    wires = ", ".join(map(str, electrodes))
    said = []
    for name, small, big, other in (("B2", a_b, a_l, "L1"), ("L1", a_l, a_b, "B2")):
        if small <= UNEXCITED_FORCE_RATIO * big:
            # a diagonal pair that excites nothing (a material without piezoelectric
            # constants) is pointed at the material, not at the pair it drives
            diagonal = sorted(electrodes) in ([1, 4], [2, 3])
            fix = ("the material's piezoelectric constants (e_C_m2) are what couple it: check "
                   "them" if diagonal else
                   "drive a diagonal pair ([electrodes] drive = [1, 4] or [2, 3])")
            said.append(f"the drive through electrodes {wires} excites no {name} (A_"
                        f"{name[0].lower()} = {small:.3g} N/V against {big:.3g} N/V for "
                        f"{other}): the tip does not trace an ellipse and the motor gives no "
                        f"thrust; {fix}")
    return said


def damping_summary(params: MotorParams, origin: str) -> dict:
    """The damping in use: ``{"zeta_L1", "zeta_B2", "from"}`` (ratios, -)."""
    return {"zeta_L1": params.zeta_L1, "zeta_B2": params.zeta_B2, "from": origin}


def damping_line(params: MotorParams, origin: str) -> str:
    """One line naming the modal damping behind a printed speed and where it came from.

    The free tip amplitude at resonance goes as ``1/zeta``, so this choice sets the scale of
    every slider speed (``docs/designer.md``).
    """
    return (f"damping zeta_L1 = {params.zeta_L1:.4g}, zeta_B2 = {params.zeta_B2:.4g} "
            f"(from {origin})")


def coupling_line(coupling: str, why: str) -> str:
    """One line naming the tangential coupling behind a printed speed and why it was used."""
    return f"coupling {coupling} ({why})"


SIMULATION_KEYS = (
    "source", "voltage_V", "preload_N", "frequency_Hz", "load_N", "method", "duration_s",
    "dt_s", "coupling", "ultrasonic_friction", "steady_velocity_m_s",
    "previous_window_velocity_m_s", "settled", "motion", "stick_fraction", "slip_fraction",
    "separation_fraction", "driving_slip_fraction", "braking_slip_fraction", "mu_d_effective",
    "normal_amplitude_m", "y_tip_min_m", "y_tip_c_m", "steady_window_s", "steps", "events",
    "nfev", "wall_time_s", "branches", "runs_away",
)
"""The keys of every run's summary (:func:`simulation_summary`, :func:`runaway_summary`), in
their order: every run of one ``lusm simulate`` carries them all, ``None`` where it has no
such value (a voltage whose slider runs away has the keys of the others)."""


def _run_summary(**values) -> dict:
    """``values`` in the order of :data:`SIMULATION_KEYS`, ``None`` for the keys not given.

    Raises
    ------
    KeyError
        For a key that is not one of :data:`SIMULATION_KEYS` (one run's summary would then
        carry a key the others lack).
    """
    unknown = set(values) - set(SIMULATION_KEYS)
    if unknown:
        raise KeyError(f"not keys of a run's summary: {sorted(unknown)}")
    return {key: values.get(key) for key in SIMULATION_KEYS}


def runaway_summary(params: MotorParams, voltage_V: float, preload_N: float,
                    frequency_Hz: float, load_N: float, coupling: str,
                    ultrasonic_friction: bool, reason: str) -> dict:
    """The summary of a ``--steady`` run whose slider runs away under its load: the keys of
    :func:`simulation_summary`, with the operating point, the velocity NaN (``null`` in the
    JSON), ``settled`` False and ``runs_away`` the reason (the loads the motor holds), the
    rest ``None`` (no steady state to describe).

    Parameters
    ----------
    params : MotorParams
    voltage_V, preload_N, frequency_Hz, load_N : float
        The operating point (V, N, Hz, N).
    coupling : str
        The tangential coupling run.
    ultrasonic_friction : bool
    reason : str
        :attr:`contact.errors.RunawayError.reason`.
    """
    from contact.model import normal_force_zero_tip_displacement

    return _run_summary(
        source=params.source, voltage_V=voltage_V, preload_N=preload_N,
        frequency_Hz=frequency_Hz, load_N=load_N, method="steady", coupling=coupling,
        ultrasonic_friction=ultrasonic_friction, steady_velocity_m_s=math.nan, settled=False,
        y_tip_c_m=normal_force_zero_tip_displacement(params, preload_N), runs_away=reason)


def simulation_summary(r: SimulationResult, runs_away: str | None = None) -> dict:
    """JSON-ready summary of one contact run (SI units in the keys; ``None`` where the
    method has no such value: the steady engine's run length, step, windows, tip extremes
    and mode switches, a transient's ``branches``), the keys of :data:`SIMULATION_KEYS`
    (and ``energy`` with the energy balance).

    Parameters
    ----------
    r : SimulationResult
    runs_away : str, optional
        Why the slider runs away under the load (a transient's
        :class:`contact.steady.runaway.RunawayWarning`); None when it does not.
    """
    from contact.model import normal_force_zero_tip_displacement

    s = r.steady
    steady = r.method == "steady"
    d = _run_summary(**{
        "source": r.params.source,
        "voltage_V": r.op.voltage_V,
        "preload_N": r.op.preload_N,
        "frequency_Hz": r.op.frequency_Hz,
        "load_N": r.op.load_N,
        "method": r.method,
        # the steady engine takes its own step and length: none of the user's to report
        "duration_s": None if steady else r.options.duration_s,
        "dt_s": None if steady else r.options.dt_s,
        "coupling": r.options.coupling,
        "ultrasonic_friction": r.options.ultrasonic_friction,
        "steady_velocity_m_s": s.velocity_m_s,
        # the steady engine shoots an orbit: no windows to compare and no tip trace to take
        # the extremes of: None, not the run's default window and y_tip_min_m nan
        "previous_window_velocity_m_s": None if steady else s.previous_velocity_m_s,
        "settled": s.settled,
        "motion": s.motion,
        "stick_fraction": s.stick_fraction,
        "slip_fraction": s.slip_fraction,
        "separation_fraction": s.separation_fraction,
        "driving_slip_fraction": s.driving_slip_fraction,
        "braking_slip_fraction": s.braking_slip_fraction,
        "mu_d_effective": r.mu_d_eff,
        "normal_amplitude_m": r.normal_amplitude_m,
        "y_tip_min_m": None if steady else s.y_tip_min_m,
        "y_tip_c_m": normal_force_zero_tip_displacement(r.params, r.op.preload_N),
        "steady_window_s": None if steady else s.window_s,
        "steps": r.steps,
        "events": r.events,
        "nfev": r.nfev,
        "wall_time_s": r.wall_time_s,
        # every stable steady state, written as lusm map writes a point's, not only the one
        # reached from rest
        "branches": None if r.branches is None else steady_branches(r.branches),
        "runs_away": runs_away,
    })
    if r.energy is not None:
        e = asdict(r.energy)
        e["relative_residual"] = r.energy.relative_residual
        d["energy"] = e
    return d


def map_summary(m: StickSlipMap) -> dict:
    """JSON-ready summary of a stick-slip map (``"steady"`` maps add ``branches``: every stable
    steady state per point, and ``undecided``: the (V, N) points the engine could not decide,
    whose values come from a transient)."""
    d = {
        "voltages_V": m.voltages_V.tolist(),
        "preloads_N": m.preloads_N.tolist(),
        "motion": m.motion.tolist(),
        "steady_velocity_m_s": m.velocity_m_s.tolist(),
        "stick_fraction": m.stick_fraction.tolist(),
        "separation_fraction": m.separation_fraction.tolist(),
        "mu_d_effective": m.mu_d_eff.tolist(),
        "settled": m.settled.tolist(),
        "counts": m.counts(),
        "wall_time_s": m.wall_time_s,
        "method": m.method,
    }
    if m.method == "steady":
        d["branches"] = [[[branch_summary(b) for b in m.branches[i, j]]
                          for j in range(m.preloads_N.size)]
                         for i in range(m.voltages_V.size)]
        d["undecided"] = [[float(m.voltages_V[i]), float(m.preloads_N[j])]
                          for i, j in zip(*np.nonzero(m.fallback), strict=True)]
    if m.limits is not None:  # each point's {quantity: {value, limit, ratio, unit}}
        d["limits"] = [[None if m.limits[i, j] is None else m.limits[i, j].to_dict()
                        for j in range(m.preloads_N.size)]
                       for i in range(m.voltages_V.size)]
    return d


def branch_summary(row: tuple) -> dict:
    """One stable steady state as ``lusm map --json`` and ``lusm simulate --steady --json``
    write it.

    Parameters
    ----------
    row : tuple
        ``(velocity_m_s, k, motion, from_rest, held)``, :func:`contact.maps.branch_row`.

    Returns
    -------
    dict
        ``velocity_m_s`` (m/s), ``k`` (period multiplicity), ``motion`` (the motion class of
        the point's own ``motion``: ``"pure-stick"`` for a held slider, whose branch says
        ``"dead-zone"``), ``from_rest`` (whether a start from rest reaches it) and ``held``
        (the slider held: the dead zone).
    """
    velocity, k, motion, from_rest, held = row
    return {"velocity_m_s": velocity, "k": k, "motion": motion, "from_rest": from_rest,
            "held": held}


def steady_branches(branches) -> list[dict]:
    """The stable ones of the steady engine's ``branches``
    (:class:`contact.steady.branches.SteadyBranch`) as :func:`branch_summary` writes them, by
    increasing velocity: a map point's ``branches`` and ``lusm simulate --steady``'s."""
    from contact.maps import branch_row

    return [branch_summary(branch_row(b)) for b in branches if b.stable]


def signed_percent(x: float, decimals: int) -> str:
    """``x`` (a ratio) in per cent with its sign, in two significant figures where
    ``decimals`` would round it to zero: a 2D/3D difference of -3e-5 reads "-3.0e-03%", not
    "-0.00%"."""
    if x != 0 and abs(x) * 100 < 0.5 * 10.0 ** -decimals:
        return f"{x * 100:+.1e}%"
    return f"{x:+.{decimals}%}"


def motion_class(branch, velocity_m_s: float) -> str:
    """The motion class ``lusm simulate --steady`` gives the same steady state: that of
    :func:`contact.results.steady_metrics` from the phase fractions of the branch reached
    from rest (``"failed"`` when there is none). The branch's own ``motion`` says
    ``"dead-zone"`` for a held slider, where simulate says ``"pure-stick"`` (``"separated"``
    at 0 V and 0 N), so that a study, the report and the single-point command name one state
    one way."""
    from contact.results import steady_metrics

    if branch is None:
        return "failed"
    v = float(velocity_m_s)
    return steady_metrics(v, v, branch.phase_fraction, math.nan, math.nan, 1.0).motion


def _finite(obj: Any) -> Any:
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, dict):
        return {k: _finite(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite(v) for v in obj]
    if hasattr(obj, "tolist") and not isinstance(obj, (str, bytes)):  # numpy scalars, arrays
        return _finite(obj.tolist())
    if isinstance(obj, Path):
        return str(obj)
    return obj


def json_text(obj: Any, indent: int | None = None) -> str:
    """``obj`` as valid JSON text: NaN and infinities become ``null`` (Python's ``json``
    writes a bare ``NaN``, which no JSON reader accepts)."""
    return json.dumps(_finite(obj), indent=indent, allow_nan=False)
