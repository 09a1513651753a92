"""Work-precision of the steady engine against transients of several lengths (issue 9).

For a few operating points of Table 2's set (stick-slip, pure slip, slip-separation) the
reference is a long settled transient (``--reference`` seconds from rest, averaged over its
last 400 periods). Against it the benchmark times and scores

* transients from rest of ``--durations`` seconds (the old ``lusm map`` answer), and
* the steady engine at its two levels, ``fast`` (averaged, slider mass -> infinity) and
  ``exact`` (finite-mass correction),

and prints, per method and setting, the median wall time over the points as a multiple of
the median steady ``exact`` time (same run) and the median and worst relative velocity error.
``--plot FILE`` draws the work-precision diagram (error against time, log-log).

Run: ``python benchmarks/steady_work_precision.py [--plot steady_wp.png]``; ``python -m
tools.doc_tables --update steady_work_precision`` pastes the table into docs/steady.md.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from contact.steady.engine import steady_state  # noqa: E402
from contact.steady.settled import transient_reference
from rom import table2  # noqa: E402

POINTS = ((200.0, 14.0), (250.0, 14.0), (400.0, 14.0), (300.0, 10.0))
"""(V, N): stick-slip, pure slip, slip-separation and a lighter preload."""


def _timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--reference", type=float, default=1.5, help="reference length (s)")
    ap.add_argument("--durations", type=float, nargs="+", default=[0.025, 0.05, 0.1, 0.2, 0.4])
    ap.add_argument("--plot", type=Path, default=None, help="write the diagram (PNG)")
    args = ap.parse_args(argv)
    p = table2()
    steady_state(p, 200, 14, accuracy="exact")  # compile / load the kernels before timing
    transient_reference(p, 200, 14, duration_s=0.01, steady_periods=20)
    refs = {pt: transient_reference(p, *pt, duration_s=args.reference)[0] for pt in POINTS}
    rows: dict[str, list[tuple[float, float]]] = {}
    for acc in ("fast", "exact"):
        rows[f"steady {acc}"] = []
        for pt in POINTS:
            r, t = _timed(lambda pt=pt, acc=acc: steady_state(p, *pt, accuracy=acc))
            rows[f"steady {acc}"].append((t, abs(r.velocity_m_s / refs[pt] - 1)))
    for d in args.durations:
        rows[f"transient {d:g} s"] = []
        for pt in POINTS:
            (v, _), t = _timed(lambda pt=pt, d=d: transient_reference(p, *pt, duration_s=d))
            rows[f"transient {d:g} s"].append((t, abs(v / refs[pt] - 1)))
    unit = statistics.median(t for t, _ in rows["steady exact"])
    print(f"Table 2's set at {', '.join(f'{v:g} V / {f:g} N' for v, f in POINTS)}; reference: "
          f"{args.reference:g} s transients from rest, averaged over their last 400 periods. "
          "Time: median over the points as a multiple of the steady engine's exact level "
          "(same run).")
    print()
    print("| method | median time / steady exact | median error | worst error |")
    print("|---|---|---|---|")
    for name, vals in rows.items():
        ts, es = zip(*vals, strict=True)
        print(f"| {name} | {statistics.median(ts) / unit:.3g} | {statistics.median(es):.1e} | "
              f"{max(es):.1e} |")
    if args.plot is not None:
        import matplotlib

        matplotlib.use("Agg")  # a script, not library code
        import matplotlib.pyplot as plt

        from validation.plotting import save

        fig, ax = plt.subplots(figsize=(6, 4.2))
        for name, vals in rows.items():
            ts, es = zip(*vals, strict=True)
            ax.loglog([t / unit for t in ts], [max(e, 1e-12) for e in es],
                      "o" if name.startswith("steady") else ".", label=name)
        ax.set_xlabel("wall time / median steady-exact time (-)")
        ax.set_ylabel("relative velocity error against the settled transient (-)")
        ax.set_title("Work-precision, Table 2's set")
        ax.legend(fontsize=7)
        print(f"\nwrote {save(fig, args.plot)}")


if __name__ == "__main__":
    main()
