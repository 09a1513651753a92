"""Can a fixed-length plate meet a target frequency by its width *and* thickness? (not a test)

With the length held, :func:`fem.tuning.tune_plate` tunes the width until L1 = B2 and reports
the common frequency instead of meeting a target, because the thickness is the only other
dimension and it hardly moves the modes. This study measures how much, on the 3D model
(:mod:`fem.solid3d.model`, default mesh), where the thickness is a real dimension: for each
thickness it runs ``tune_plate(fix="length", model="3d")`` at the given length and prints the
degenerate width, the common frequency, the L1/B2 split and the FE solves; the same on the
2D model for comparison. The spread of the common frequency over the thicknesses is the
window of targets that a free thickness could reach at that length.

Run: ``python benchmarks/tune_fixed_length_3d.py [--length-mm 35] [--thickness-mm 1 2 3 4 5]
[--no-2d] [--json]`` (``--json``: the spans as a last line of JSON, for
``python -m tools.doc_numbers --update 'tune_fixlen35_h_*'``)
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from fem.geometry import PlateStator  # noqa: E402
from fem.tuning import tune_plate  # noqa: E402


def study(length_mm: float, thicknesses_mm: list[float], models: tuple[str, ...]) -> dict:
    """``{(model, h_mm): TunedDesign}`` of the fixed-length tuning at each thickness."""
    out = {}
    for model in models:
        for h in thicknesses_mm:
            start = PlateStator(length_m=length_mm * 1e-3, width_m=0.27 * length_mm * 1e-3,
                                thickness_m=h * 1e-3)
            t0 = time.perf_counter()
            d = tune_plate(fix="length", start=start, model=model)
            dt = time.perf_counter() - t0
            out[(model, h)] = d
            print(f"{model:<3} h {h:5.2f} mm  W {d.stator.width_m * 1e3:8.4f} mm  "
                  f"f {d.frequency_Hz:10.1f} Hz  L1 {d.L1.f_short_Hz:10.1f}  "
                  f"B2 {d.B2.f_short_Hz:10.1f}  split {d.relative_mismatch:.1e}  "
                  f"solves {d.fe_solves:2d}  ({dt:.0f} s)", flush=True)
    for model in models:
        fs = [out[(model, h)].frequency_Hz for h in thicknesses_mm]
        ws = [out[(model, h)].stator.width_m for h in thicknesses_mm]
        print(f"{model}: over h = {min(thicknesses_mm):g}..{max(thicknesses_mm):g} mm the common "
              f"frequency spans {min(fs):.1f}..{max(fs):.1f} Hz "
              f"({(max(fs) - min(fs)) / min(fs) * 100:.3f} %), the width "
              f"{min(ws) * 1e3:.4f}..{max(ws) * 1e3:.4f} mm")
    return out


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--length-mm", type=float, default=35.0)
    p.add_argument("--thickness-mm", type=float, nargs="+", default=[1.0, 2.0, 3.0, 4.0, 5.0])
    p.add_argument("--no-2d", action="store_true", help="3D only")
    p.add_argument("--json", action="store_true", help="end with the spans as JSON")
    a = p.parse_args(argv)
    models = ("3d",) if a.no_2d else ("2d", "3d")
    out = study(a.length_mm, a.thickness_mm, models)
    if a.json:
        spans = {}
        for model in models:
            fs = [out[(model, h)].frequency_Hz for h in a.thickness_mm]
            ws = [out[(model, h)].stator.width_m for h in a.thickness_mm]
            spans[model] = {"frequency_span": (max(fs) - min(fs)) / min(fs),
                            "width_span": (max(ws) - min(ws)) / min(ws),
                            "max_split": max(out[(model, h)].relative_mismatch
                                             for h in a.thickness_mm)}
        print(json.dumps(spans))


if __name__ == "__main__":
    main()
