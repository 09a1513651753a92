"""The 2D plate model against the 3D model: the tables of docs/fem3d.md section 2 (not a test).

``--part plate`` (default): the paper's plate (30 x 7.5 x 3 mm, PZT-8, gap 0.5 mm), one
row per quantity (four frequencies, two k_eff) and one column per model: ``2D old`` (the
model before issue 8: ``gap_model="open"``, no thickness inertia), ``2D`` (the default),
the 3D default mesh, 3D refine = layers = 6 and the default 3D mesh graded three times
towards the electrode edges, then 2D/3D - 1 against the default and the graded 3D.

``--part stators``: the example stators with their own planform mesh
(``examples/*/stator.toml``) beside the plain plate, 2D on the planform mesh and 3D on its
extrusion (3 layers), with 2D/3D - 1 and each stator's shift from the plain plate.

Wall times are multiples of the default 2D model's, measured in the same run. Run:
``python benchmarks/fem_2d_vs_3d.py [--part plate|stators]``; ``python -m
tools.doc_tables --update 'fe_2d_vs_3d*'`` stores both for the docs.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.geometry import PlateStator  # noqa: E402
from fem.mesh_settings import MeshSettings  # noqa: E402
from fem.meshing.mesh import DEFAULT_REFINE  # noqa: E402
from fem.model import plate_model  # noqa: E402
from fem.modes import modes_of_model  # noqa: E402
from fem.solid3d.model import build_solid_model, modes_of_solid_model  # noqa: E402
from fem.stator_file import load_stator  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
QUANTITIES = (("L1 f_short (Hz)", "L1", "f_short_Hz"), ("L1 f_open (Hz)", "L1", "f_open_Hz"),
              ("B2 f_short (Hz)", "B2", "f_short_Hz"), ("B2 f_open (Hz)", "B2", "f_open_Hz"),
              ("L1 k_eff", "L1", "k_eff"), ("B2 k_eff", "B2", "k_eff"))
EXAMPLES = ("tip_protrusion", "chamfered")


def _timed(fn):
    t0 = time.perf_counter()
    res = fn()
    return res, time.perf_counter() - t0


def _value(res, mode: str, attr: str) -> float:
    return getattr(getattr(res, mode), attr)


def _fmt(v: float, attr: str) -> str:
    return f"{v:.3f}" if attr == "k_eff" else f"{v:,.1f}".replace(",", " ")


def _pct(x: float, digits: int) -> str:
    return f"{100 * x:+.{digits}f} %".replace("-", "−")


def plate() -> str:
    """The default plate against the 3D meshes."""
    st = PlateStator()
    runs = {
        "2D old": _timed(lambda: modes_of_model(plate_model(
            st, "pzt8", MeshSettings(2, DEFAULT_REFINE, gap_model="open",
                                     thickness_inertia=False)))),
        "2D": _timed(lambda: modes_of_model(plate_model(st, "pzt8", MeshSettings(2)))),
        "3D default": _timed(lambda: modes_of_solid_model(build_solid_model(st, "pzt8",
                                                                            MeshSettings(2)))),
        "3D 6×6": _timed(lambda: modes_of_solid_model(build_solid_model(st, "pzt8",
                                                                        MeshSettings(2, 6, 6)))),
        "3D graded 3": _timed(lambda: modes_of_solid_model(
            build_solid_model(st, "pzt8", MeshSettings(2, edge_grading=3)))),
    }
    t2d = runs["2D"][1]
    head = list(runs) + ["2D/3D − 1 (default)", "2D/3D − 1 (graded)"]
    out = ["| quantity | " + " | ".join(head) + " |", "|---|" + "---|" * len(head)]
    for label, mode, attr in QUANTITIES:
        vals = [_value(r, mode, attr) for r, _ in runs.values()]
        d = 1 if attr == "k_eff" else 3
        rel = [_pct(vals[1] / vals[2] - 1, d), _pct(vals[1] / vals[4] - 1, d)]
        out.append(f"| {label} | " + " | ".join([_fmt(v, attr) for v in vals] + rel) + " |")
    out.append("| dofs | " + " | ".join(str(r.dofs) for r, _ in runs.values()) + " | | |")
    out.append("| wall / 2D | " + " | ".join(f"{w / t2d:.2g}" for _, w in runs.values())
               + " | | |")
    return "\n".join(out)


def stators() -> str:
    """The example stators with their own planform mesh, beside the plain plate."""
    cases = {"plain plate": (PlateStator(), "pzt8")}
    for name in EXAMPLES:
        d = load_stator(ROOT / "examples" / name / "stator.toml")
        cases[name] = (d.stator, d.material)
    rows, res = [], {}
    t2d = None
    for name, (st, mat) in cases.items():
        r2, w2 = _timed(lambda st=st, mat=mat: modes_of_model(plate_model(st, mat,
                                                                          MeshSettings(2))))
        r3, w3 = _timed(lambda st=st, mat=mat: modes_of_solid_model(
            build_solid_model(st, mat, MeshSettings(2, layers=3))))
        t2d = t2d or w2
        res[name] = (r2, r3)
        for model, r, w in (("2D", r2, w2), ("3D", r3, w3)):
            rows.append(
                f"| {name} | {model} | {r.dofs} | {_fmt(r.L1.f_short_Hz, '')} / "
                f"{_fmt(r.L1.f_open_Hz, '')} | {_fmt(r.B2.f_short_Hz, '')} / "
                f"{_fmt(r.B2.f_open_Hz, '')} | {r.L1.k_eff:.3f} / {r.B2.k_eff:.3f} | "
                f"{w / t2d:.2g} |")
        rel = [_value(r2, m, a) / _value(r3, m, a) - 1 for _, m, a in QUANTITIES[:4]]
        rows.append(f"| {name} | 2D/3D − 1 | | {_pct(rel[0], 3)} / {_pct(rel[1], 3)} | "
                    f"{_pct(rel[2], 3)} / {_pct(rel[3], 3)} | | |")
    out = ["| stator | model | dofs | L1 f_short / f_open (Hz) | B2 f_short / f_open (Hz) | "
           "k_eff L1 / B2 | wall / plain 2D |", "|---|---|---|---|---|---|---|", *rows, "",
           "Shift of the short-circuit frequencies from the plain plate (2D against 2D, 3D "
           "against 3D):", "", "| stator | L1 2D | L1 3D | B2 2D | B2 3D |",
           "|---|---|---|---|---|"]
    p2, p3 = res["plain plate"]
    for name in EXAMPLES:
        r2, r3 = res[name]
        cells = [_pct(_value(a, m, "f_short_Hz") / _value(b, m, "f_short_Hz") - 1, 3)
                 for m in ("L1", "B2") for a, b in ((r2, p2), (r3, p3))]
        out.append(f"| {name} | " + " | ".join(cells) + " |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", choices=("plate", "stators"), default="plate")
    args = ap.parse_args(argv)
    print(plate() if args.part == "plate" else stators())


if __name__ == "__main__":
    main()
