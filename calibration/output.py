"""The calibrated file and the summary of a calibration.

A stator file (``--geometry``) is written as the user's own text with its motor tables
(``[damping]``, ``[contact]``, ``[slider]``, ``[friction]``, ``[force_factor]``) replaced by
the calibrated set's, each fitted value followed by its standard error and 95 % interval in a
comment; a set without a stator file (``--source``) is written as a parameter file, the
``lusm params --json`` form that ``--params`` reads, its ``source`` text naming the fit.
"""

from __future__ import annotations

import json
import math
import os
import re
from pathlib import Path

import numpy as np

from calibration.fit import CalibrationResult
from calibration.parameters import PARAMETERS
from calibration.uncertainty import TABLE, of_result
from rom.params import PARAM_UNITS, MotorParams

MOTOR_TABLES = ("damping", "contact", "slider", "friction", "force_factor")
"""Stator-file tables a calibrated file writes anew."""

KEY_OF: dict[str, tuple[str, str]] = {
    "C_l": ("damping", "zeta_L1"), "Q_L1": ("damping", "zeta_L1"),
    "C_b": ("damping", "zeta_B2"), "Q_B2": ("damping", "zeta_B2"),
    "k_contact": ("contact", "k_contact_N_m"), "mu_sd": ("slider", "mu_sd"),
    "mu_s": ("friction", "mu_s"), "mu_d": ("friction", "mu_d"), "a_mu": ("friction", "a_mu"),
    "b_mu": ("friction", "b_mu_per_m"),
    "A_l_scale": ("force_factor", "scale_L1"), "A_b_scale": ("force_factor", "scale_B2"),
}
"""Fitted parameter -> the ``[table] key`` of the stator file that carries it."""

_HEADER = re.compile(r"^\s*\[\[?\s*([A-Za-z_][\w.-]*)\s*\]\]?\s*(#.*)?$")


def _g(v: float) -> str:
    return f"{v:.6g}"


def fitted_text(result: CalibrationResult, i: int) -> str:
    """One line on parameter ``i``: its value, standard error and interval, or why the data
    cannot fix it."""
    p = result.parameters[i]
    unit = f" {p.unit}" if p.unit != "-" else ""
    if not result.identifiable[i]:
        kept = ("kept at its start" if "do not depend" in result.reasons[i]
                else "one of many values that fit as well")
        return (f"{p.name} NOT IDENTIFIABLE from these data ({result.reasons[i]}); "
                f"{_g(result.values[i])}{unit}: {kept}")
    text = f"{p.name} = {_g(result.values[i])} +/- {_g(result.stderr[i])}{unit}"
    prof = result.profiles.get(p.name)
    if prof is not None:
        lo = f"{'<= ' if prof.lower_open else ''}{_g(prof.lower)}"
        hi = f"{_g(prof.upper)}{' (bound)' if prof.upper_open else ''}"
        text += f", 95 % profile interval [{lo}, {hi}]"
    return text


def header_lines(result: CalibrationResult, meas_path: Path, name: str) -> list[str]:
    """What the file's header comment says about the fit."""
    out = [f"Calibrated by lusm calibrate from {meas_path} ({name}): {result.points} "
           f"measured values, chi-square {result.chi2:.4g} for {result.dof} degrees of freedom.",
           f"Steady engine: accuracy {result.accuracy}, coupling {result.coupling} (run this "
           f"set with --coupling {result.coupling}).",
           *(fitted_text(result, i) for i in range(len(result.parameters)))]
    if result.c0_F is not None:
        out.append("C0_F is not a key of this file: the FE model gives the capacitance")
    return out


def _tables(result: CalibrationResult, base_scales: tuple[float, float]) -> dict[str, dict]:
    """Table -> key -> value of the calibrated motor tables."""
    p = result.params
    fitted = dict(zip(result.names, result.values, strict=True))
    return {
        "damping": {"zeta_L1": p.zeta_L1, "zeta_B2": p.zeta_B2},
        "contact": {"k_contact_N_m": p.k_contact},
        "slider": {"M_slider_kg": p.M_slider, "mu_sd": p.mu_sd},
        "friction": {"mu_s": p.mu_s, "mu_d": p.mu_d, "a_mu": p.a_mu, "b_mu_per_m": p.b_mu},
        "force_factor": {"scale_L1": base_scales[0] * fitted.get("A_l_scale", 1.0),
                         "scale_B2": base_scales[1] * fitted.get("A_b_scale", 1.0)},
    }


def stator_text(original: str, result: CalibrationResult, meas_path: Path, name: str,
                base_scales: tuple[float, float] = (1.0, 1.0),
                mesh_file: str | None = None) -> str:
    """The stator file ``original`` with its motor tables replaced by the calibrated set's
    (module docstring); ``mesh_file`` replaces ``[mesh] file`` (the path as seen from the
    new file's folder)."""
    lines = original.splitlines()
    if lines and lines[0].startswith("# Calibrated by lusm calibrate"):  # an earlier fit's
        lines = lines[1:]
        while lines and lines[0].startswith("#   "):
            lines = lines[1:]
    kept, table = [], ""
    for line in lines:
        m = _HEADER.match(line)
        if m:
            table = m.group(1)
        if table in MOTOR_TABLES or table == TABLE:  # written anew below
            continue
        if table == "mesh" and mesh_file is not None and re.match(r"^\s*file\s*=", line):
            line = f"file = {json.dumps(mesh_file)}"
        kept.append(line)
    while kept and not kept[-1].strip():
        kept.pop()
    where = {KEY_OF[n]: i for i, n in enumerate(result.names) if n in KEY_OF}
    head = [f"# {line}" if k == 0 else f"#   {line}"
            for k, line in enumerate(header_lines(result, meas_path, name))]
    body = []
    for tname, keys in _tables(result, base_scales).items():
        body.append(f"\n[{tname}]")
        for key, value in keys.items():
            i = where.get((tname, key))
            note = f"  # {fitted_text(result, i)}" if i is not None else ""
            body.append(f"{key} = {float(value)!r}{note}")
    return "\n".join(head + kept + body + calibration_table(result)) + "\n"


def _toml_value(v) -> str:
    """A TOML value of a number (``inf`` and ``nan`` as TOML spells them), bool, string,
    None (as ``nan``: TOML has no null; only ``chi2`` of a fit without data could be one) or
    list of them."""
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if v is None:
        return "nan"
    return repr(v) if isinstance(v, float) else str(v)


def calibration_table(result: CalibrationResult) -> list[str]:
    """The ``[calibration]`` table of a stator file: the fit in machine-readable form
    (:mod:`calibration.uncertainty`), read by ``--uncertainty`` and the report."""
    table = of_result(result).to_table()
    return ["", f"[{TABLE}]  # the fit, read by --uncertainty and lusm report "
            "(docs/calibration.md)",
            *(f"{key} = {_toml_value(value)}" for key, value in table.items()
              if value is not None)]


def params_text(result: CalibrationResult, meas_path: Path, name: str) -> str:
    """The calibrated set as a ``lusm params --json`` file, its ``source`` naming the fit."""
    fits = "; ".join(fitted_text(result, i) for i in range(len(result.parameters)))
    params = result.params.with_(source=f"{result.params.source}, calibrated by lusm "
                                 f"calibrate from {meas_path} ({name}, coupling "
                                 f"{result.coupling}): {fits}")
    d = params.to_dict()
    return json.dumps({**d, "units": {k: PARAM_UNITS[k] for k in d if k in PARAM_UNITS},
                       TABLE: of_result(result).to_table(json_ready=True)},
                      indent=2) + "\n"


def same_set(a: MotorParams, b: MotorParams, rtol: float = 1e-12) -> bool:
    """Whether two sets hold the same numbers (``source`` and ``shape`` aside)."""
    from dataclasses import fields

    return all(math.isclose(getattr(a, f.name), getattr(b, f.name), rel_tol=rtol)
               for f in fields(a) if f.name not in ("source", "shape"))


def relative_mesh(mesh_path: Path | None, out: Path) -> str | None:
    """The stator's mesh file as seen from ``out``'s folder; None without a mesh."""
    if mesh_path is None:
        return None
    return os.path.relpath(mesh_path.resolve(), out.resolve().parent)


def summary(result: CalibrationResult, base_values: dict[str, float | None],
            out: str | None, meas=None) -> dict:
    """The calibration as a JSON-ready dictionary (``lusm calibrate --json``); with the
    measurements ``meas``, each data set's measured and fitted values (SI)."""
    params = []
    for i, p in enumerate(result.parameters):
        prof = result.profiles.get(p.name)
        ok = result.identifiable[i]
        params.append({
            "name": p.name, "unit": p.unit, "meaning": PARAMETERS[p.name][1],
            "value": float(result.values[i]) if ok else None,
            "fit_value": float(result.values[i]),
            "stderr": float(result.stderr[i]) if ok and np.isfinite(result.stderr[i]) else None,
            "interval_95": None if prof is None or not ok else [prof.lower, prof.upper],
            "interval_open": None if prof is None else [prof.lower_open, prof.upper_open],
            "identifiable": ok, "reason": result.reasons[i] or None,
            "start": p.start, "bounds": [p.lower, p.upper],
            "start_set_value": base_values.get(p.name)})
    corr = np.where(np.isfinite(result.correlation), result.correlation, np.nan)
    return {
        "parameters": params, "chi2": result.chi2, "points": result.points,
        "dof": result.dof, "reduced_chi2": result.chi2 / result.dof if result.dof > 0 else None,
        "correlation": {"names": list(result.names), "matrix": corr.tolist()},
        "starts": [{"start": s.tolist(), "end": e.tolist(), "chi2": c}
                   for s, e, c in result.starts],
        "coupling": result.coupling, "accuracy": result.accuracy,
        "evaluations": result.evaluations, "wall_time_s": result.wall_time_s,
        "profile_time_s": result.profile_time_s, "notes": list(result.notes), "out": out,
        "sets": [] if meas is None else [
            {"kind": d.kind, "file": str(d.path),
             "inputs": {q: v.tolist() for q, v in d.inputs.items()},
             "measured": {q: v.tolist() for q, v in d.observed.items()},
             "model": {q: pred[q].tolist() for q in d.observed}}
            for d, pred in zip(meas.sets, result.predictions, strict=True)],
    }
