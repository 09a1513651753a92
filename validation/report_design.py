"""``lusm report --geometry``: the report on a designer's own stator, end to end.

Sections: the stator and its modes in 2D and 3D (L1-B2 split, pictures of both modes), the
reduced parameter set, the admittance around the design's modes, the steady speed against
voltage, and the motor characteristics (speed-thrust, efficiency, steady map) of
:mod:`validation.report_motor`. Built aside and moved in complete like the default report.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, fields
from pathlib import Path

import numpy as np

from fem.mesh_settings import MeshSettings
from rom.params import PARAM_UNITS
from validation.summaries import (
    damping_line,
    damping_summary,
    plate_text,
    signed_percent,
    unexcited_modes,
)

SPEED_PRELOAD_N = 14.0
"""Default preload of the speed-against-voltage table and the speed-thrust curves (N), the
paper's Fig. 20 (``lusm report --preload``)."""


@dataclass(frozen=True)
class ReportDrive:
    """The operating points a design report computes at (``lusm report --voltages
    --preload --frequency``).

    Attributes
    ----------
    voltages_V : tuple of float
        Drive amplitudes of the speed-thrust curves (V).
    preload_N : float
        Preload of the speed-against-voltage table and the speed-thrust curves (N).
    frequency : str
        ``"auto"`` (the set's own operating point, :func:`contact.drive.auto_frequency`) or
        a drive frequency in Hz, as typed.
    """

    voltages_V: tuple[float, ...] = (200.0, 300.0, 400.0)
    preload_N: float = SPEED_PRELOAD_N
    frequency: str = "auto"

    @property
    def auto(self) -> bool:
        """Whether the drive frequency is the set's own operating point."""
        return self.frequency.strip().lower() == "auto"

    def frequency_Hz(self, params) -> float:
        """The drive frequency (Hz) of ``params`` this drive names."""
        from contact.drive import auto_frequency

        return float(auto_frequency(params)) if self.auto else float(self.frequency)

    def options_text(self) -> str:
        """The ``lusm report`` options that give this drive, the defaults left out."""
        words = []
        if self.voltages_V != ReportDrive.voltages_V:
            words.append("--voltages " + ",".join(f"{v:g}" for v in self.voltages_V))
        if self.preload_N != SPEED_PRELOAD_N:
            words.append(f"--preload {self.preload_N:g}")
        if not self.auto:
            words.append(self.frequency_option())
        return " ".join(words)

    def frequency_option(self) -> str:
        """``--frequency auto`` or ``--frequency F`` as the cited commands take it."""
        return "--frequency auto" if self.auto else f"--frequency {float(self.frequency):g}"


def _describe(stator, material, label: str) -> str:
    mm = 1e3
    shape = plate_text(stator)
    mesh_file = getattr(stator, "mesh_file", "")
    if mesh_file:
        shape += f", planform mesh {Path(mesh_file).name}"
    elif hasattr(stator, "element_size_m"):
        shape += (f", electrode gap {stator.electrode_gap_m * mm:g} mm, gmsh mesh of element "
                  f"size {stator.element_size_m * mm:g} mm")
    else:
        shape += f", electrode gap {stator.electrode_gap_m * mm:g} mm"
    # a stator without a name is its plate: said once, not "plate: plate 30 x ..."
    return f"{shape}, {material.name}" if label == "plate" else f"{label}: {shape}, {material.name}"


def _lusm(command: str, stator: str, rest: str = "") -> str:
    """``lusm COMMAND STATOR REST``, without the empty parts (the paper's plate has no stator
    options)."""
    return " ".join(w for w in ("lusm", command, stator, rest) if w)


def _modes_section(choice, out: Path, quick: bool, say, stator: str):
    from fem.meshing.mesh import DEFAULT_REFINE
    from fem.model import plate_model
    from fem.modes import plate_modes
    from fem.render import render_modes
    from fem.solid3d.model import DEFAULT_LAYERS, DEFAULT_REFINE_3D, solid_modes

    st, mat = choice.stator, choice.material
    m2 = plate_modes(st, mat, MeshSettings(2, DEFAULT_REFINE))
    say("2D modes")
    refine3 = max(DEFAULT_REFINE_3D - (1 if quick else 0), 1)
    m3 = solid_modes(st, mat, MeshSettings(2, refine3, DEFAULT_LAYERS))
    say("3D modes")
    from contact.deferred_signals import deferred_signals

    with deferred_signals():  # not interrupted half-way: a signal there crashes VTK
        import pyvista  # noqa: F401
    model = plate_model(st, mat, MeshSettings(2, DEFAULT_REFINE))
    with deferred_signals():  # about a second; a SIGTERM inside VTK's rendering crashes the
        # report (exit 139, 2 of about 90 tries) and leaves its staging folder
        pictures = render_modes(model, m2, out / "figures", prefix="design_")
        pictures_3d = _pictures_3d(choice, m3, refine3, out)
    say("mode pictures")
    rows, data = [], {"2d": {}, "3d": {}}
    for name in ("L1", "B2"):
        a, b = getattr(m2, name), getattr(m3, name)
        rows.append([name, a.f_short_Hz, b.f_short_Hz, a.f_short_Hz / b.f_short_Hz - 1,
                     a.f_open_Hz, b.f_open_Hz, a.k_eff, b.k_eff])
        data["2d"][name], data["3d"][name] = a.to_dict(), b.to_dict()
    split2 = m2.B2.f_short_Hz / m2.L1.f_short_Hz - 1
    split3 = m3.B2.f_short_Hz / m3.L1.f_short_Hz - 1
    data.update(split_2d=split2, split_3d=split3, dofs_2d=m2.dofs, dofs_3d=m3.dofs,
                pictures=[f"figures/{p.name}" for p in pictures],
                pictures_3d=[f"figures/{p.name}" for p in pictures_3d])
    from fem.meshing.meshed_stator import MeshedStator
    from fem.meshing.parametric import ParametricStator

    # a stator meshed by gmsh or by its own file has no refine (lusm modes --json says null)
    mesh_text = ("the stator file's own mesh" if isinstance(st, MeshedStator) else
                 "gmsh at the stator file's [mesh] size_mm" if isinstance(st, ParametricStator)
                 else f"refine {DEFAULT_REFINE}")
    md = ["## 1. Modes", "",
          f"2D plane-stress model (order 2, {mesh_text}, {m2.dofs} DOFs; "
          f"`{_lusm('modes', stator)}`) and 3D piezoelectric solid ({m3.dofs} DOFs; "
          f"`{_command_3d(st, refine3, stator)}`). Short circuit: all electrodes grounded; "
          "open: all four electrodes floating.", ""]
    md += ["| mode | 2D short (Hz) | 3D short (Hz) | 2D/3D - 1 | 2D open (Hz) | 3D open (Hz) | "
           "k_eff 2D | k_eff 3D |", "|---|---|---|---|---|---|---|---|"]
    md += ["| " + " | ".join([r[0], f"{r[1]:.1f}", f"{r[2]:.1f}", signed_percent(r[3], 2),
                              f"{r[4]:.1f}", f"{r[5]:.1f}", f"{r[6]:.4f}", f"{r[7]:.4f}"])
           + " |" for r in rows]
    md += ["", "L1-B2 split f_B2/f_L1 - 1 (short circuit): "
           f"**{signed_percent(split2, 3)}** in 2D, **{signed_percent(split3, 3)}** in 3D. "
           "A motor wants the two modes degenerate (`lusm tune`).", ""]
    data["gap_validity"], note = _validity_note(st)
    md += note
    md += [f"![{p.stem}](figures/{p.name})" for p in pictures] + [""]
    md += ["The same modes in the 3D solid (deformed surface coloured by the displacement "
           "magnitude; `lusm render --model 3d` draws any mode of the band table below, and "
           "`--color potential` the electric potential):", ""]
    md += [f"![{p.stem}](figures/{p.name})" for p in pictures_3d] + [""]
    band_md, data["band_modes"] = _band_section(choice, m3, refine3, stator)
    say("band modes")
    return md + band_md, data, m2


def _pictures_3d(choice, m3, refine3: int, out: Path) -> list[Path]:
    """The 3D pictures of L1 and B2 (:func:`fem.render3d.render_modes3d`) on the model of
    the modes table's 3D column."""
    from fem.render3d import render_modes3d
    from fem.solid3d.model import DEFAULT_LAYERS, solid_model

    model = solid_model(choice.stator, choice.material, MeshSettings(2, refine3, DEFAULT_LAYERS))
    return render_modes3d(model, (m3.L1, m3.B2), out / "figures", prefix="design_3d_")


def _band_section(choice, m3, refine3: int, stator: str) -> tuple[list[str], dict]:
    """Every mode of the 3D model within the L1/B2 pair +- 20 % (:func:`fem.band.band_modes`
    on the full 3D model of the modes table), as ``lusm modes --model 3d --band`` lists it:
    the out-of-plane and torsion modes beside the pair, which the 2D model does not have."""
    from fem.band import band_modes, default_band_Hz
    from fem.solid3d.model import DEFAULT_LAYERS, solid_model

    ops = {"L1": m3.L1.f_short_Hz, "B2": m3.B2.f_short_Hz}
    band = band_modes(solid_model(choice.stator, choice.material,
                                  MeshSettings(2, refine3, DEFAULT_LAYERS)),
                      *default_band_Hz(ops), ops)
    md = [f"Every mode of the 3D model within the L1/B2 pair +/- 20 % "
          f"({band.f_min_Hz:.0f}-{band.f_max_Hz:.0f} Hz; "
          f"`{_command_3d(choice.stator, refine3, stator)} --band`), named by its shape "
          "(Ln longitudinal, Bn in-plane bending, OBn out-of-plane bending, Tn torsion; n from "
          f"the nodes along the length). A mode within {band.risk_pct:g} % of L1 or B2 is a "
          "risk to the drive.", "",
          "| mode | family | f_short (Hz) | f_open (Hz) | k_eff | from the pair | drive |",
          "|---|---|---|---|---|---|---|"]
    for m in band.modes:
        f_open = f"{m.f_open_Hz:.1f}" if math.isfinite(m.f_open_Hz) else "-"
        k_eff = f"{m.k_eff:.4f}" if math.isfinite(m.k_eff) else "-"
        flag = "operating" if m.operating else "**risk**" if m.risk else ""
        md.append(f"| {m.name} | {m.family} | {m.f_short_Hz:.1f} | {f_open} | {k_eff} | "
                  f"{'-' if m.operating else signed_percent(m.offset, 1)} | {flag} |")
    risks = ", ".join(f"{m.name} at {m.f_short_Hz:.0f} Hz" for m in band.risks)
    md += ["", f"Risks to the drive: {risks}." if risks else
           f"No other mode within {band.risk_pct:g} % of the pair.", ""]
    return md, band.to_dict()


def _command_3d(stator, refine3: int, options: str) -> str:
    """The ``lusm modes`` call that gives the report's 3D column: its layers, its refine where
    it is not the command's default (``--quick``'s coarser mesh is another call: its split
    can be 15 times the command's on a tuned plate) and the work bound it
    needs where the mesh is above ``lusm modes``' own (a chamfered example: 2 988 bricks).
    ``options`` are the stator options the report was given
    (:func:`lusm.options.stator_options_text`)."""
    from fem.cell_count import fe_cell_count
    from fem.meshing.meshed_stator import planform_mesh
    from fem.solid3d.model import DEFAULT_LAYERS, DEFAULT_REFINE_3D
    from lusm import limits

    cmd = _lusm("modes --model 3d", options, f"--layers {DEFAULT_LAYERS}")
    if planform_mesh(stator) is None and refine3 != DEFAULT_REFINE_3D:
        cmd += f" --refine {refine3}"
    bricks, top = fe_cell_count(stator, refine3, DEFAULT_LAYERS), limits.MAX_FE_CELLS_3D
    if bricks > limits.work_bound(top):
        cmd = f"{limits.WORK_ENV}={math.ceil(bricks / top)} {cmd}"
    return cmd


def _validity_note(stator) -> tuple[str | None, list[str]]:
    """The 2D model's gap-validity warning (:func:`fem.model.stator_gap_validity`) and
    its paragraph for section 1: said on stderr during the run, and in the report, which
    outlives the run, so that its reader sees when its 2D rows are out of range."""
    from fem.model import stator_gap_validity
    from lusm.messages import in_file_terms

    validity = stator_gap_validity(stator)
    if validity is None:
        return None, []
    return str(validity), [f"**The 2D model is outside its validity for this stator**: "
                      f"{in_file_terms(validity)}. The 2D rows, and the reduced set and motor "
                      "sections built on them, carry that error; the 3D columns are the "
                      "reference.", ""]


def _params_section(params, label: str, damping_from: str, stator: str):
    rows = [f"| {f.name} | {getattr(params, f.name):.6g} | {PARAM_UNITS.get(f.name, '')} |"
            for f in fields(params) if f.name not in ("source", "shape")]
    md = ["## 2. Reduced parameters", "",
          f"`{_lusm('params', stator)}` ({params.source}). Modal frequencies "
          f"f_L1 = {params.f_L1_Hz:.1f} Hz, f_B2 = {params.f_B2_Hz:.1f} Hz; damping ratios "
          f"zeta_L1 = {params.zeta_L1:.4g}, zeta_B2 = {params.zeta_B2:.4g}, from "
          f"{damping_from} (the damping in use: every speed below depends on it; a stator "
          "file's `[damping]` table sets it, `docs/designer.md`).", "",
          "| parameter | value | unit |", "|---|---|---|"]
    md += rows + [""]
    data = {f.name: getattr(params, f.name) for f in fields(params) if f.name != "shape"}
    data["shape"] = None if params.shape is None else params.shape.to_dict()
    data["damping"] = damping_summary(params, damping_from)
    return md, data


def _admittance_section(choice, params, modes2d, out: Path, quick: bool, stator: str):
    from fem.admittance import design_band_Hz, plate_admittance
    from fem.equivalent_circuit import equivalent_circuit
    from validation.fem_figures import admittance_figure

    f_lo, f_hi = design_band_Hz(modes2d)
    points = 801 if quick else 4001
    band = f"--f-min {float(f_lo)!r} --f-max {float(f_hi)!r} --points {points}"
    res = plate_admittance(choice.stator, choice.material, f_lo, f_hi, points,
                           zeta_L1=params.zeta_L1, zeta_B2=params.zeta_B2)
    try:
        circuit = equivalent_circuit(res)
    except ValueError:  # no mode the port drives in the band
        circuit = None
    png = admittance_figure(res, out / "figures" / "design_admittance.png", circuit)
    md = ["## 3. Admittance", "",
          f"Driven electrodes {res.port.electrodes}, band {f_lo / 1e3:.2f}-{f_hi / 1e3:.2f} kHz "
          "(the design's modes +/- 15 %), the parameter set's damping "
          # the points too: the command's default 2001 moved f_s/f_p in the 8th digit
          f"(`{_lusm('admittance', stator, band)}`).", ""]
    if res.pairs:
        md += ["| mode | series resonance f_s (Hz) | parallel resonance f_p (Hz) | k_eff |",
               "|---|---|---|---|"]
        md += [f"| {p.mode or 'unidentified'} | {p.f_resonance_Hz:.1f} | "
               f"{p.f_antiresonance_Hz:.1f} | {p.k_eff:.4f} |" for p in res.pairs]
        md += ["", "These k_eff are the driven port's, from f_s (max Re Y) and f_p (max "
               "Re 1/Y) with the other "
               "electrodes grounded and each mode's damping and its neighbours' in the way; "
               "the modes table's are the stator's own, from its natural frequencies with all "
               "four electrodes shorted and all open. The two differ by definition"
               + _k_eff_comparison(res.pairs, modes2d) + "."]
    else:
        md += ["No resonance/antiresonance pair is resolved in this band."]
    missed = res.unpaired_modes()  # as lusm admittance warns
    if missed:
        md += ["", " and ".join(f"{n} ({f:.0f} Hz)" for n, f in missed)
               + " lie in the band, but no resonance pair on this grid is "
               + ("its" if len(missed) == 1 else "theirs")
               + ": the grid is too coarse for them "
               "(`lusm admittance --points` with more points)."]
    flat = res.peakless_modes()
    if flat:
        md += ["", " and ".join(f"{n} ({f:.0f} Hz)" for n, f in flat)
               + (" has" if len(flat) == 1 else " have") + " no resonance peak through this "
               "port at this damping, on any grid: the coupling is too weak against the "
               "damping (`lusm admittance --zeta` with lighter damping resolves it)."]
    md += _circuit_lines(circuit)
    md += ["", f"![admittance](figures/{png.name})", ""]
    data = {"band_Hz": [f_lo, f_hi], "pairs": [
        {"mode": p.mode, "f_resonance_Hz": p.f_resonance_Hz,
         "f_antiresonance_Hz": p.f_antiresonance_Hz, "k_eff": p.k_eff} for p in res.pairs],
        "figure": f"figures/{png.name}",
        "equivalent_circuit": None if circuit is None else circuit.to_dict()}
    return md, data


def _k_eff_comparison(pairs, modes2d) -> str:
    """`` (on this stator: L1 0.155 here against 0.267 in section 1's 2D column, ...)``:
    each identified pair's port k_eff beside the modes table's 2D one; empty without one."""
    own = [f"{p.mode} {p.k_eff:.3g} here against {getattr(modes2d, p.mode).k_eff:.3g}"
           for p in pairs if p.mode in ("L1", "B2")]
    return f" (on this stator: {', '.join(own)} in section 1's 2D column)" if own else ""


def _circuit_lines(circuit) -> list[str]:
    """The fitted Butterworth-Van Dyke circuit as a table (``lusm admittance`` prints it)."""
    if circuit is None:
        return ["", "No mode the port drives lies in the band: no equivalent circuit."]
    md = ["", f"Butterworth-Van Dyke equivalent circuit fitted to this admittance: C0 = "
          f"{circuit.C0_F:.4e} F in parallel with one R1-L1-C1 branch per driven mode "
          f"(the circuit reproduces the computed admittance to {circuit.rms_rel:.1e} rms of "
          "|Y|); Q_m, f_s, f_p and k_eff as IEEE Std 176 / IEC 60483 define them.", "",
          "| mode | R1 (ohm) | L1 (H) | C1 (F) | f_s (Hz) | f_p (Hz) | Q_m | k_eff |",
          "|---|---|---|---|---|---|---|---|"]
    md += [f"| {b.mode or 'unidentified'} | {b.R_ohm:.4g} | {b.L_H:.4g} | {b.C_F:.4e} | "
           f"{b.f_s_Hz:.1f} | {b.f_p_Hz(circuit.C0_F):.1f} | {b.Q_m:.4g} | "
           f"{b.k_eff(circuit.C0_F):.4f} |" for b in circuit.branches]
    return md


def _speed_section(params, frequency_Hz: float, out: Path, quick: bool, say, stator: str,
                   damping_from: str = "", drive: ReportDrive = ReportDrive()):
    from contact.model import default_coupling
    from contact.steady.engine import steady_state
    from validation.figures import curve
    from validation.summaries import coupling_line, motion_class

    coupling, coupling_why = default_coupling(params)
    volts = np.arange(100.0, 451.0, 100.0 if quick else 50.0)
    rows, vel = [], []
    for v in volts:
        r = steady_state(params, float(v), drive.preload_N, frequency_Hz=frequency_Hz,
                         accuracy="exact", coupling=coupling)
        # simulate --steady's class of the same state (a held slider is "pure-stick"; the
        # steady engine's branch says "dead-zone")
        rows.append(f"| {v:g} | {r.velocity_m_s * 1e3:.4g} | "
                    f"{motion_class(r.from_rest, r.velocity_m_s)} | "
                    f"{sum(x.stable for x in r.branches)} |")
        vel.append(r.velocity_m_s * 1e3)
    say("speed vs voltage")
    png = curve(volts, {"steady velocity from rest": vel}, "drive voltage V0 (V)",
                "slider velocity (mm/s)", out / "figures" / "design_speed_voltage.png",
                f"F_P = {drive.preload_N:g} N, {frequency_Hz / 1e3:.4g} kHz")
    md = ["## 4. Speed against voltage", "",
          f"Steady velocity reached from rest at {drive.preload_N:g} N and "
          f"{frequency_Hz / 1e3:.5g} kHz ("
          + ("the set's operating point, `--frequency auto`" if drive.auto else
             f"`{drive.frequency_option()}`, as the report was asked") + "), "
          # the voltage and preload too: the command requires both
          "exact level of the steady engine (`"
          + _lusm("simulate --steady", stator,
                  f"--voltage V0 --preload {drive.preload_N:g} {drive.frequency_option()}")
          + f"`, V0 each row's). The {damping_line(params, damping_from)}; the "
          f"{coupling_line(coupling, coupling_why)}.", "",
          "| V0 (V) | velocity (mm/s) | motion | stable steady states |", "|---|---|---|---|"]
    md += rows + ["", f"![speed against voltage](figures/{png.name})", ""]
    return md, {"voltages_V": volts.tolist(), "velocity_mm_s": vel,
                "preload_N": drive.preload_N,
                "damping": damping_summary(params, damping_from),
                "coupling": coupling, "coupling_from": coupling_why,
                "figure": f"figures/{png.name}"}


def write_design_report(out_dir: Path, choice, params, stator_options: str,
                        quick: bool = False,
                        progress: bool = True,
                        damping_from: str = "the parameter set",
                        drive: ReportDrive = ReportDrive(), calibration=None) -> dict:
    """Write the report on one stator (``index.md``, ``index.html``, ``report.json``, figures).

    Parameters
    ----------
    out_dir : Path
        An existing folder (the command builds it aside and moves it in complete,
        :mod:`lusm.commands.report`).
    choice : lusm.options.StatorChoice
        The stator and material the user named.
    params : rom.params.MotorParams
        The FE reduction of that stator (with the stator file's motor tables, if any).
    stator_options : str
        The options that named the stator, as typed (``--geometry FILE``, ``--length-mm 60``;
        :func:`lusm.options.stator_options_text`): every command the report cites
        carries them, so that it reproduces the report's numbers.
    quick : bool
        Coarser grids, same sections.
    progress : bool
        Show a progress bar on stderr.
    damping_from : str
        Where the damping ratios of ``params`` came from, printed beside every speed.
    drive : ReportDrive
        The speed-thrust voltages, the preload and the drive frequency (``lusm report
        --voltages --preload --frequency``).
    calibration : calibration.uncertainty.Calibration, optional
        The fit a calibrated stator file carries: a "Calibration" section
        (:func:`validation.report_calibration.calibration_section`).
    """
    return _build(Path(out_dir), choice, params, stator_options, quick, progress, damping_from,
                  drive, calibration)


def _build(out: Path, choice, params, stator: str, quick: bool, progress: bool,
           damping_from: str, drive: ReportDrive, calibration=None) -> dict:
    from tqdm import tqdm

    from validation.report import markdown_table, write_report_files
    from validation.report_motor import motor_section

    (out / "figures").mkdir(parents=True, exist_ok=True)
    bar = tqdm(total=11, desc="design report", unit="step", disable=not progress)

    def say(msg: str) -> None:
        bar.set_postfix_str(msg[:40])
        bar.update()

    t0 = time.perf_counter()
    label = choice.design.name if getattr(choice, "design", None) is not None else "plate"
    md1, d1, modes2d = _modes_section(choice, out, quick, say, stator)
    md2, d2 = _params_section(params, label, damping_from, stator)
    md3, d3 = _admittance_section(choice, params, modes2d, out, quick, stator)
    say("admittance")
    freq = drive.frequency_Hz(params)
    md4, d4 = _speed_section(params, freq, out, quick, say, stator, damping_from, drive)
    md5, d5 = motor_section({"design": params}, {"design": freq}, out, quick, say, markdown_table,
                            damping_from={"design": damping_from},
                            cites={"design": f"{stator} {drive.frequency_option()}".strip()},
                            voltages_V=drive.voltages_V, preload_N=drive.preload_N)
    md5[0] = "## 5. Motor characteristics"
    md6, d6 = [], None
    if calibration is not None:
        from validation.report_calibration import calibration_section

        md6, d6 = calibration_section(calibration, stator, 6)
    bar.close()
    wall = time.perf_counter() - t0
    command = _lusm("report" + (" --quick" if quick else ""), stator, drive.options_text())
    head = [f"# LUSM report: {_describe(choice.stator, choice.material, label)}", "",
            f"Generated by `{command}` for "
            "the stator above on "
            f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} in {wall:.0f} s. Every "
            "number here is also in `report.json`; `lusm report` without a stator reports on "
            "the paper's motor.", ""]
    unexcited = unexcited_modes(params, choice.stator.drive_electrodes)
    head += _unexcited_note(unexcited)
    md = "\n".join(head + md1 + md2 + md3 + md4 + md5 + md6)
    doc = {"quick": quick, "wall_time_s": wall, "stator": _describe(choice.stator,
                                                                     choice.material, label),
           "drive": {"voltages_V": list(drive.voltages_V), "preload_N": drive.preload_N,
                     "frequency_Hz": freq, "frequency_from": drive.frequency},
           "modes": d1, "parameters": d2, "admittance": d3, "speed_vs_voltage": d4,
           "motor_characteristics": d5,
           "warnings": unexcited, **({"calibration": d6} if d6 is not None else {})}
    return write_report_files(out, md, doc, "LUSM design report")


def _unexcited_note(said: list[str]) -> list[str]:
    """A bold paragraph at the top of the report for each of ``said``, the drive's
    :func:`validation.summaries.unexcited_modes` (it excites no L1 or no B2): the speed
    tables below are then zeros, and the report, which outlives the run's stderr, says why."""
    return [f"**Warning: {text}.** The speeds and forces below are zero for that reason."
            for text in said] + ([""] if said else [])
