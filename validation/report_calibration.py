"""The "Calibration" section of a design report on a calibrated stator file (one that
``lusm calibrate`` wrote: its ``[calibration]`` table, :mod:`calibration.uncertainty`)."""

from __future__ import annotations

import math

from calibration.parameters import PARAMETERS


def calibration_section(cal, stator: str, number: int) -> tuple[list[str], dict]:
    """Markdown and JSON of the section: each fitted parameter's value, standard error and
    identifiability, the fit's chi-square per degree of freedom, and the commands that carry
    the covariance to a prediction.

    Parameters
    ----------
    cal : calibration.uncertainty.Calibration
        The stored fit.
    stator : str
        The options that name the stator (``--geometry FILE``), for the commands cited.
    number : int
        The section's number in the report.
    """
    fit = ""
    if cal.chi2 is not None and cal.dof:
        fit = (f" The fit: chi-square {cal.chi2:.4g} for {cal.dof} degrees of freedom "
               f"({cal.chi2 / cal.dof:.3g} per degree of freedom"
               + (f", {cal.points} measured values" if cal.points else "") + ").")
    coupling = (f" It ran the steady engine with `--coupling {cal.coupling}`; run the set "
                "with it." if cal.coupling else "")
    md = [f"## {number}. Calibration", "",
          f"This stator file was written by `lusm calibrate`: its motor tables hold fitted "
          f"values, and its `[calibration]` table the fit's covariance.{fit}{coupling} A "
          "parameter the data cannot fix is named not identifiable and is held at its value "
          "by `--uncertainty` (e.g. "
          f"`lusm simulate --steady {stator} --voltage 300 --preload 14 --uncertainty`, "
          "a band on the speed; `lusm characteristic ... --uncertainty`, on the stall force; "
          "docs/calibration.md).", "",
          "| parameter | value | standard error | unit | identifiable |",
          "|---|---|---|---|---|"]
    rows = []
    for i, name in enumerate(cal.names):
        unit = PARAMETERS[name][0]
        se = float(cal.stderr[i])
        ok = cal.identifiable[i]
        md.append(f"| {name} | {cal.values[i]:.6g} | "
                  f"{f'{se:.3g}' if ok and math.isfinite(se) else '-'} | {unit} | "
                  f"{'yes' if ok else 'no: ' + cal.reasons[i]} |")
        rows.append({"name": name, "value": float(cal.values[i]), "unit": unit,
                     "stderr": se if ok and math.isfinite(se) else None,
                     "identifiable": ok, "reason": cal.reasons[i] or None})
    md.append("")
    data = {"parameters": rows, "chi2": cal.chi2, "dof": cal.dof, "points": cal.points,
            "reduced_chi2": cal.chi2 / cal.dof if cal.chi2 is not None and cal.dof else None,
            "coupling": cal.coupling, "held": list(cal.held)}
    return md, data
