"""``lusm report``: the default motor end to end, in tables, figures and one JSON file.

Sections: (1) the three parameter sets side by side with the FE modal table, (2) the paper's
contact figures reproduced on each set with a verdict per claim, (3) speed against error of
the contact integrators and of the FE meshes, (4) numerically hard cases with their energy
balance. Every number comes from the same library calls that ``lusm simulate`` and
``lusm modes`` make; nothing is copied, with one labelled exception: the SfePy peer check of
the 2D-vs-3D section is quoted from ``docs/fem3d.md`` (:func:`peer_check_summary`), because it
needs the optional SfePy and minutes of 3D solves (``python benchmarks/fem_peer_sfepy.py``).
"""

from __future__ import annotations

import math
import os
import platform
import re
import time
from dataclasses import asdict
from pathlib import Path

import numpy as np

from fem.mesh_settings import MeshSettings
from validation import figures
from validation.report_html import to_html
from validation.summaries import signed_percent

ROOT = Path(__file__).resolve().parents[1]
"""The source checkout (where ``examples/`` lives)."""

SECTIONS = ("parameter_sets", "paper_reproduction", "speed_vs_error", "hard_cases",
            "motor_characteristics")


def _fmt(x, digits: int = 4) -> str:
    if isinstance(x, bool) or x is None:
        return str(x)
    if isinstance(x, (int, np.integer)):
        return str(int(x))
    if isinstance(x, float):
        if math.isnan(x):
            return "-"
        if 1e3 <= abs(x) < 1e6:  # frequencies: keep 0.1 Hz
            return f"{x:.1f}"
        return f"{x:.{digits}g}"
    return str(x)


def markdown_table(header: list[str], rows: list[list]) -> list[str]:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        out.append("| " + " | ".join(_fmt(c).replace("|", "/") for c in r) + " |")
    return out


class _Stage:
    """A tqdm progress bar for one report stage; ``say(msg)`` advances it."""

    def __init__(self, name: str, total: int, enabled: bool):
        from tqdm import tqdm

        self.bar = tqdm(total=total, desc=name, unit="step", disable=not enabled, leave=True)

    def say(self, msg: str) -> None:
        from lusm.interrupts import checkpoint

        checkpoint()  # a Ctrl-C / SIGTERM that Python swallowed: stop at the next step
        self.bar.set_postfix_str(msg[:40])
        self.bar.update()

    def close(self) -> None:
        # the steps a stage takes vary (quick runs, sets): the bar ends full, not at 4/5
        self.bar.total = self.bar.n
        self.bar.refresh()
        self.bar.close()


def _parameter_sets(out: Path, quick: bool, progress: bool) -> tuple[list[str], dict, dict]:
    from fem.geometry import PlateStator
    from fem.material import get_material
    from fem.meshing.mesh import DEFAULT_REFINE
    from fem.modes import plate_modes
    from rom.compare import compare_sources
    from rom.sources import get_params

    st = _Stage("1/5 parameter sets", 4, progress)  # the 3D solves take most of it
    comp = compare_sources(("table2", "beam", "fem"))
    st.say("compare")
    modes = plate_modes(PlateStator(), get_material("pzt8"), MeshSettings(2, DEFAULT_REFINE))
    st.say("FE modes")
    params = {s: get_params(s) for s in ("table2", "beam", "fem")}
    st.say("sets")
    md = ["## 1. Parameter sets", "",
          "Published Table 2, the beam theory of Appendix A (`docs/beam.md`) and the modal "
          "reduction of the 2D piezoelastic FE model (`docs/fem.md`), same dataclass. Relative "
          "differences are to Table 2. Damping ratios of beam and FE are Table 2's.", ""]
    rows = []
    for name, unit in comp.quantities:
        row = [f"{name} ({unit})"]
        for s in comp.sources:
            v = comp.values[s].get(name, float("nan"))
            d = comp.relative_difference[s].get(name, float("nan"))
            row.append(_fmt(v) if s == comp.reference else f"{_fmt(v)} ({signed_percent(d, 1)})")
        rows.append(row)
    md += markdown_table(["quantity"] + list(comp.sources), rows)
    md += ["", "FE modal analysis of the default plate (PZT-8, order 2, refine "
           f"{DEFAULT_REFINE}, {modes.dofs} DOFs, {modes.wall_time_s:.3f} s; the same call as "
           "`lusm modes`):", ""]
    md += markdown_table(["mode", "f_short (Hz)", "f_open (Hz)", "k_eff"],
                 [[m.name, m.f_short_Hz, m.f_open_Hz, m.k_eff] for m in (modes.L1, modes.B2)])
    md += ["", "The paper's ANSYS gives L1 39 841 Hz and B2 40 257 Hz; Table 2 implies "
           f"{comp.values['table2']['f_L1_Hz']:.0f} Hz and {comp.values['table2']['f_B2_Hz']:.0f}"
           " Hz (L1 above B2). Neither is reachable with a 30 mm PZT-8 plate "
           "(its L1 is near c/2l, about 56 kHz); see `docs/fem.md`.", ""]
    data = {"comparison": comp.to_dict(),
            "fe_modes": {"L1": modes.L1.to_dict(), "B2": modes.B2.to_dict(),
                         "dofs": modes.dofs, "wall_time_s": modes.wall_time_s}}
    md_3d, data["plane_stress_vs_3d"] = _plane_stress_vs_3d(1 if quick else 2)
    st.say("2D vs 3D")
    st.close()
    md += md_3d
    return md, data, params


EXAMPLES = Path(__file__).resolve().parents[1] / "examples"
"""Example stators shipped with a source checkout (absent from a wheel install)."""
FEM3D_DOC = Path(__file__).resolve().parents[1] / "docs" / "fem3d.md"
"""The 3D model's documentation (source checkout only), source of the peer-check summary."""
PEER_START, PEER_END = "<!-- peer-summary:start -->", "<!-- peer-summary:end -->"
"""Markers around the SfePy peer-check summary in ``docs/fem3d.md``."""


def peer_check_summary(doc: Path = FEM3D_DOC) -> list[str]:
    """Markdown lines quoting the SfePy peer-check summary of ``docs/fem3d.md``.

    Static: the block between :data:`PEER_START` and :data:`PEER_END` is copied as written
    (measured by ``python benchmarks/fem_peer_sfepy.py``, which needs the optional extra
    ``peer``); SfePy is neither imported nor run. Empty when the document or the block is
    missing (e.g. a wheel install without ``docs/``).
    """
    if not doc.is_file():
        return []
    text = doc.read_text(encoding="utf-8")
    i, j = text.find(PEER_START), text.find(PEER_END)
    if i < 0 or j < i:
        return []
    # without the docs' number markers (<!--input-->, <!--n:key-->), which HTML would show
    block = re.sub(r"<!--.*?-->", "", text[i + len(PEER_START):j]).strip("\n").splitlines()
    return ["", "Peer check against SfePy, an independent FE code: quoted from `docs/fem3d.md` "
            "(\"Peer check with SfePy\"), not re-run by the report; measured by "
            "`benchmarks/fem_peer_sfepy.py` (`pip install -e .[peer]`).", "",
            *block]


def _plane_stress_vs_3d(example_layers: int) -> tuple[list[str], dict]:
    """2D plane stress against the 3D piezoelastic model, and the example stators (2D)."""
    from fem.plane_stress_error import plane_stress_error

    e = plane_stress_error()
    md = ["2D plane stress against the 3D piezoelastic reference (`docs/fem3d.md`; PZT-8, "
          f"2D {e.dofs_2d} DOFs in {e.wall_time_2d_s:.2f} s, 3D quadratic bricks "
          f"{e.dofs_3d} DOFs in {e.wall_time_3d_s:.2f} s; the same calls as "
          "`lusm modes --model 2d|3d`):", ""]
    rows = [[key.replace("_", " "), e.f2d_Hz[key], e.f3d_Hz[key],
             signed_percent(e.f2d_Hz[key] / e.f3d_Hz[key] - 1, 2)] for key in e.f2d_Hz]
    rows += [[f"{m} k_eff", e.k_eff_2d[m], e.k_eff_3d[m],
              signed_percent(e.k_eff_2d[m] / e.k_eff_3d[m] - 1, 1)] for m in e.k_eff_2d]
    md += markdown_table(["quantity", "2D (Hz or -)", "3D (Hz or -)", "2D/3D - 1"], rows)
    # the default 3D mesh is not graded towards the electrode edges, where the potential is
    # singular: its B2 open and k_eff are that mesh's own error, which the peer-check
    # summary below (graded meshes) does not carry
    md += ["", "The 3D column is the default 3D mesh, not graded towards the electrode edges: "
           "B2 open and B2 k_eff carry its own discretization error there (graded three "
           "times, `lusm modes --model 3d --edge-grading 3`, B2 k_eff moves by about 6 % "
           "towards the 2D value; `docs/fem3d.md` section 2 has both columns)."]
    data = {"f2d_Hz": e.f2d_Hz, "f3d_Hz": e.f3d_Hz, "k_eff_2d": e.k_eff_2d,
            "k_eff_3d": e.k_eff_3d, "examples": {}}
    tomls = sorted(EXAMPLES.glob("*/stator.toml")) if EXAMPLES.is_dir() else []
    if tomls:
        from fem.stator_file import load_stator

        ex_rows = []
        for path in tomls:
            design = load_stator(path)
            if design.mesh_path is None:  # plain plates (the 2D/3D above) and parametric ones
                continue
            ex = plane_stress_error(stator=design.stator, material=design.material,
                                    layers=example_layers)
            for key in ex.f2d_Hz:
                ex_rows.append([path.parent.name, key.replace("_", " "), ex.f2d_Hz[key],
                                ex.f3d_Hz[key],
                                signed_percent(ex.f2d_Hz[key] / ex.f3d_Hz[key] - 1, 2)])
            data["examples"][path.parent.name] = {
                "f2d_Hz": ex.f2d_Hz, "f3d_Hz": ex.f3d_Hz, "k_eff_2d": ex.k_eff_2d,
                "k_eff_3d": ex.k_eff_3d, "layers": example_layers, "dofs_3d": ex.dofs_3d}
        md += ["", "Example stators of `examples/` (planform meshes; 3D = the planform "
               f"extruded in {example_layers} layer(s) of quadratic bricks; "
               "`lusm modes --geometry examples/<name>/stator.toml [--model 3d --layers N]`):",
               ""]
        md += markdown_table(["stator", "frequency", "2D (Hz)", "3D (Hz)", "2D/3D - 1"], ex_rows)
    md += peer_check_summary()
    md.append("")
    return md, data


def _damping(name: str, p) -> str:
    """The damping line of one of the default report's sets (Table 2's ratios in all three)."""
    from validation.summaries import borrowed_damping, damping_line, table2_damping

    return damping_line(p, table2_damping() if name == "table2" else borrowed_damping(name))


def _reproduction(params: dict, out: Path, quick: bool, progress: bool):
    from contact.drive import auto_frequency
    from rom.table2 import PAPER_DRIVE_HZ
    from validation.paper_repro import ReproSettings, reproduce

    settings = ReproSettings.quick() if quick else ReproSettings()
    md = ["## 2. Paper reproduction", "",
          "Each of the paper's claims on the contact model, judged on each parameter set. "
          "Table 2 is driven at the paper's 40 kHz; beam theory and FE, whose modes lie far "
          "above 40 kHz, at their own operating point (`--frequency auto`: the frequency "
          "maximizing the product of the free tip's L1 and B2 amplitudes, "
          "`contact.drive.auto_frequency`). "
          + ("The judged numbers (velocities, motion classes, mu_d, the maps) are settled "
             "values: the steady state a start from rest reaches, found by the steady engine "
             "(`contact.steady`, exact level; section 5). The time traces and phase planes "
             f"are runs of {settings.duration_s * 1e3:g} ms from rest at dt = 1e-7 s."
             if settings.method == "steady" else
             f"Every number comes from runs of {settings.duration_s * 1e3:g} ms from rest at "
             "dt = 1e-7 s, judged as they end (not settled; `--quick`).")
          + " Every set runs here with the paper's coupling (eta_T F_T on B2, Eq. 5 as "
          "printed), the model whose claims are judged; section 5 runs the beam and FE sets "
          "with the work-consistent one, as `--coupling auto` does, so their speeds differ "
          "from this section's (`lusm simulate --steady --source fem --frequency auto "
          "--coupling paper` gives this section's).", ""]
    data = {}
    for name, p in params.items():
        freq = PAPER_DRIVE_HZ if name == "table2" else auto_frequency(p)
        st = _Stage(f"2/5 reproduction ({name})", 4, progress)
        rep = reproduce(p, freq, out / "figures", f"{name}_", settings, st.say)
        st.close()
        agree = sum(r.agrees for r in rep.rows)
        md += [f"### {name}, driven at {freq / 1e3:.4g} kHz with the paper's coupling", "",
               f"Parameter set: {p.source}.", "",
               f"{agree} of {len(rep.rows)} claims agree. The {_damping(name, p)}.", ""]
        md += markdown_table(["figure", "the paper says", "we get", "agrees?", "why not"],
                     [[r.figure, r.paper_says, r.we_get, "yes" if r.agrees else "no", r.reason]
                      for r in rep.rows])
        md += [""] + [f"![{k}](figures/{Path(v).name})" for k, v in rep.figures.items()] + [""]
        data[name] = {"frequency_Hz": freq, "coupling": "paper",
                      "rows": [asdict(r) for r in rep.rows],
                      "figures": {k: f"figures/{Path(v).name}" for k, v in rep.figures.items()},
                      "numbers": rep.numbers}
    return md, data


def _work_precision_figure(points, out: Path) -> Path:
    plt = figures.pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2))
    methods = sorted({p.method for p in points})
    cases = sorted({p.case for p in points})
    markers = "osd^v<>"
    for k, (ax, attr, label) in enumerate(
        zip(axes, ("velocity_error", "stick_error"),
            ("relative error, steady velocity (-)", "error, stick fraction (-)"), strict=True)
    ):
        for i, m in enumerate(methods):
            for j, c in enumerate(cases):
                sel = [p for p in points if p.method == m and p.case == c]
                x = [p.wall_time_s for p in sel]
                y = [max(getattr(p, attr), 1e-12) for p in sel]
                ax.loglog(x, y, marker=markers[i % len(markers)], ls="-" if j == 0 else "--",
                          label=f"{m}, {c}" if k == 0 else None)
        ax.set_xlabel("wall time (s)")
        ax.set_ylabel(label)
        ax.grid(True, which="both", alpha=0.3)
    fig.legend(fontsize=7, loc="lower center", ncol=2, bbox_to_anchor=(0.5, 0.0))
    fig.suptitle("error against the event-driven solve_ivp reference (a zero error is drawn "
                 "at 1e-12)", fontsize=9)
    fig.subplots_adjust(left=0.07, right=0.98, top=0.92, bottom=0.3, wspace=0.25)
    return figures.save(fig, out, tight=False)


def _fe_figure(points, out: Path) -> Path:
    plt = figures.pyplot()
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for order in sorted({p.order for p in points}):
        sel = [p for p in points if p.order == order]
        for attr, ls in (("error_L1", "-"), ("error_B2", "--")):
            ax.loglog([p.wall_time_s for p in sel], [max(getattr(p, attr), 1e-9) for p in sel],
                      marker="o", ls=ls, label=f"order {order}, {attr[-2:]}")
    ax.axhline(5e-4, color="k", lw=0.6, ls=":", label="0.05 % target")
    ax.set_xlabel("wall time: mesh + assembly + eigensolutions (s)")
    ax.set_ylabel("relative frequency error (-)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    return figures.save(fig, out)


def _speed(params: dict, out: Path, quick: bool, progress: bool):
    from contact.simulate import simulate
    from validation.work_precision import contact_work_precision, fe_work_precision

    p = params["table2"]
    st = _Stage("3/5 speed vs error", 10, progress)
    if quick:
        pts, refs = contact_work_precision(
            p, cases=((200.0, 14.0),), dts=(5e-7, 1e-7, 5e-8), literal_dts=(1e-7, 5e-8),
            rtols=(1e-6,), duration_s=0.01, progress=st.say)
        fe_pts, fe_ref = fe_work_precision({1: (4, 8, 16), 2: (2, 3, 4)}, (4, 6))
    else:
        pts, refs = contact_work_precision(p, progress=st.say)
        fe_pts, fe_ref = fe_work_precision()
    st.say("FE meshes")
    # one default run against the reference, timed in this process after JIT
    dur = 0.01 if quick else 0.05
    simulate(p, 200.0, 14.0, duration_s=0.001)
    times = [simulate(p, 200.0, 14.0, duration_s=dur).wall_time_s for _ in range(5)]
    t_kernel = float(np.median(times))
    r = simulate(p, 200.0, 14.0, duration_s=dur)
    ref = simulate(p, 200.0, 14.0, duration_s=dur, method="reference")
    st.say("timing")
    st.close()
    wp_png = _work_precision_figure(pts, out / "figures" / "work_precision_contact.png")
    fe_png = _fe_figure(fe_pts, out / "figures" / "work_precision_fe.png")
    md = ["## 3. Speed against error", "",
          f"Machine: {os.cpu_count()} CPUs, {platform.machine()}, Python "
          f"{platform.python_version()}. All times measured in this run, after JIT.", "",
          "### 3a. Contact", "",
          f"One {dur * 1e3:g} ms run at 200 V / 14 N, dt = 1e-7 s, Table 2 parameters "
          f"({_damping('table2', p)}; {r.steps} steps, {r.events} switches): "
          f"**{t_kernel * 1e3:.1f} ms** (median of 5, "
          f"A_N included); the event-driven `solve_ivp` reference (DOP853, rtol 1e-10): "
          f"**{ref.wall_time_s:.2f} s** ({ref.steps} steps, {ref.nfev} evaluations), i.e. "
          f"**{ref.wall_time_s / t_kernel:.0f}x** slower; velocities "
          f"{r.steady.velocity_m_s:.8g} vs {ref.steady.velocity_m_s:.8g} m/s.", "",
          "Errors against `solve_ivp` with events at rtol 1e-11 (reference figures in "
          "`report.json`). The paper's literal scheme (RK4, mode fixed per step from the stick "
          "band) is shown for contrast: with eps = 1e-10 it never enters stick.", ""]
    md += markdown_table(["method", "case", "setting", "velocity error", "stick error", "wall (s)"],
                 [[q.method, q.case, q.setting, q.velocity_error, q.stick_error, q.wall_time_s]
                  for q in pts])
    md += ["", f"![contact work-precision](figures/{wp_png.name})", "",
           "### 3b. FE", "", f"Reference: {fe_ref['reference']}: L1 "
           f"{fe_ref['f_L1_Hz']:.2f} Hz, B2 {fe_ref['f_B2_Hz']:.2f} Hz (PZT-8, default plate). "
           "Order-1 quadrilaterals lock in bending: their B2 error stays large.", ""]
    md += markdown_table(["order", "refine", "DOFs", "L1 (Hz)", "B2 (Hz)", "L1 error", "B2 error",
                  "wall (s)"],
                 [[q.order, q.refine, q.dofs, q.f_L1_Hz, q.f_B2_Hz, q.error_L1, q.error_B2,
                   q.wall_time_s] for q in fe_pts])
    md += ["", f"![FE work-precision](figures/{fe_png.name})", ""]
    data = {"contact": {"points": [asdict(q) for q in pts], "references": refs,
                        "kernel_wall_time_s": t_kernel, "kernel_steps": r.steps,
                        "reference_wall_time_s": ref.wall_time_s,
                        "speed_ratio": ref.wall_time_s / t_kernel,
                        "figure": f"figures/{wp_png.name}"},
            "fe": {"points": [asdict(q) for q in fe_pts], "reference": fe_ref,
                   "figure": f"figures/{fe_png.name}"}}
    return md, data


def _hard_cases(params: dict, quick: bool, progress: bool):
    from validation.hard_cases import run_hard_cases

    st = _Stage("4/5 hard cases", 20, progress)
    rows = run_hard_cases(params["table2"], quick=quick, progress=st.say)
    st.close()
    md = ["## 4. Hard cases", "",
          f"Table 2 parameters, 40 kHz ({_damping('table2', params['table2'])}). "
          "Energy residual: |ΔE − (input − damping + interface and "
          "guide work)| / input over the steady window, E = kinetic + modal strain + contact "
          "spring energy. Non-conservative: the work the paper's coupling eta_T F_T adds beyond "
          "the tip reaction −phi_B(l) F_T, over the input (`docs/contact.md` §2.3).", ""]
    md += markdown_table(["case", "setting", "status", "motion", "velocity (m/s)", "settled",
                  "energy residual", "non-conservative", "switches", "wall (s)"],
                 [[h.name, h.setting, h.status if h.status == "stable" else
                   ("clear error (expected): " if h.expected_error else "ERROR: ")
                   + h.status[7:], h.motion,
                   # a held slider's window mean is roundoff (-1.6e-28 m/s for the heavy one)
                   "0" if abs(h.velocity_m_s) < 1e-15 else h.velocity_m_s,
                   h.settled, h.energy_residual,
                   h.non_conservative_share, h.events, h.wall_time_s] for h in rows])
    md.append("")
    return md, [asdict(h) for h in rows]


TUNED_EXAMPLES = {"tuned_40k": "examples/tuned_40k/stator.toml",
                  "tuned_40k_fitted": "examples/tuned_40k/identified.toml"}
"""The 40 kHz stator (``lusm tune`` at the paper's thickness and gap) that the motor section
puts beside Table 2: the plate a designer would build for the paper's drive frequency, with
Table 2's damping ratios and with its damping fitted, as the paper fitted Table 2's, to the
paper's free tip amplitudes (``[damping] source = "paper_amplitudes"``, :mod:`rom.damping`)."""


def _motor(params: dict, d2: dict, out: Path, quick: bool, progress: bool):
    from contact.drive import auto_frequency
    from rom.from_fem import fem_params_from_file
    from validation.report_motor import motor_section
    from validation.summaries import borrowed_damping, table2_damping

    freqs = {name: d2[name]["frequency_Hz"] for name in params}
    origins = {"table2": table2_damping(), "beam": borrowed_damping("beam"),
               "fem": borrowed_damping("fem")}
    from fem.stator_file import load_stator

    sets = dict(params)
    for name, rel in TUNED_EXAMPLES.items():
        if not (ROOT / rel).exists():  # an installed package has no examples/
            continue
        sets[name] = fem_params_from_file(ROOT / rel)
        freqs[name] = auto_frequency(sets[name])
        origins[name] = f"{rel} {load_stator(ROOT / rel).damping_origin}"
    # the options that name each set on a command line (Table 2 at 40 kHz is the default;
    # the beam and FE sets borrow Table 2's damping here, where the commands' default is
    # the material's)
    cites = {"table2": "", "beam": "--source beam --frequency auto --damping table2",
             "fem": "--source fem --frequency auto --damping table2"}
    cites.update({name: f"--geometry {rel} --frequency auto"
                  for name, rel in TUNED_EXAMPLES.items()})
    st = _Stage("5/5 motor characteristics", 2 * len(sets) + 1, progress)
    md, data = motor_section(sets, freqs, out, quick, st.say, markdown_table, origins,
                             cites=cites)
    st.close()
    return md, data


def write_report(out_dir: Path, quick: bool = False, progress: bool = True) -> dict:
    """Write ``index.md``, ``index.html``, ``report.json`` and the figures into ``out_dir``,
    an existing folder (the command builds it aside and moves it in complete,
    :mod:`lusm.commands.report`). Returns the JSON document."""
    return _build(Path(out_dir), quick, progress)


def _build(out: Path, quick: bool, progress: bool) -> dict:
    (out / "figures").mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    md1, d1, params = _parameter_sets(out, quick, progress)
    md2, d2 = _reproduction(params, out, quick, progress)
    md3, d3 = _speed(params, out, quick, progress)
    md4, d4 = _hard_cases(params, quick, progress)
    md5, d5 = _motor(params, d2, out, quick, progress)
    wall = time.perf_counter() - t0
    head = ["# LUSM report: the default motor end to end", "",
            f"Generated by `lusm report{' --quick' if quick else ''}` on "
            f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} in {wall:.0f} s. Model: Li, "
            "Yao & Wu, Int. J. Mech. Sci. 107 (2016) 215-224; 30 x 7.5 x 3 mm PZT-8 stator. "
            "Every number here is also in `report.json`.", ""]
    md = "\n".join(head + md1 + md2 + md3 + md4 + md5)
    doc = {"quick": quick, "wall_time_s": wall, "parameter_sets": d1,
           "paper_reproduction": d2, "speed_vs_error": d3, "hard_cases": d4,
           "motor_characteristics": d5}
    return write_report_files(out, md, doc, "LUSM report")


def write_report_files(out: Path, md: str, doc: dict, title: str) -> dict:
    """Write a report's ``index.md``, its self-contained ``index.html`` and ``report.json``
    (UTF-8; a path that is not, as ``st\udcfe.toml`` from a Latin-1 name, is written with
    backslash escapes rather than failing the whole report at its end)."""
    text = {"encoding": "utf-8", "errors": "backslashreplace"}
    (out / "index.md").write_text(md, **text)
    (out / "index.html").write_text(to_html(md, title), **text)
    from validation.summaries import json_text

    (out / "report.json").write_text(json_text(doc, indent=1), **text)  # NaN as null
    return doc
