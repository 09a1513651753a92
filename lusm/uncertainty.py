"""``--uncertainty [N]`` of ``simulate --steady``, ``characteristic`` and ``map``: the option,
the calibrated file's fit it needs, and how its bands are said (:mod:`calibration.bands`
computes them; docs/calibration.md)."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from contextlib import contextmanager

from lusm import limits
from lusm.errors import LusmError
from lusm.options import integer

DEFAULT_SAMPLES = 64
"""Draws of ``--uncertainty`` without a number (:data:`calibration.uncertainty.
DEFAULT_SAMPLES`, repeated here: ``--help`` imports no NumPy)."""


def add_uncertainty_option(p: argparse.ArgumentParser, what: str) -> None:
    """``--uncertainty [N]``; ``what`` says which predictions get a band."""
    p.add_argument("--uncertainty", nargs="?", const=DEFAULT_SAMPLES, default=None,
                   metavar="N", type=integer("--uncertainty", 2, limits.MAX_UNCERTAINTY_SAMPLES,
                                             work=True),
                   help=f"Monte Carlo on the covariance of a calibrated file (--geometry or "
                   f"--params written by lusm calibrate): N parameter sets drawn (default "
                   f"{DEFAULT_SAMPLES}, seed 0; parameters not identifiable held at their "
                   f"values), giving the mean, standard deviation and 2.5/97.5 %% quantiles "
                   f"of {what}")


def calibration_of(args: argparse.Namespace, motor=None):
    """The fit stored in the ``--params`` or ``--geometry`` file
    (:func:`calibration.uncertainty.read_calibration`), refused in one line naming
    ``--uncertainty`` when there is none; a warning where ``motor`` (a
    :class:`lusm.options.Motor`) runs another coupling than the fit did."""
    from calibration.uncertainty import CalibrationFileError, read_calibration

    path = getattr(args, "params", None) or getattr(args, "geometry", None)
    if not path:
        raise LusmError("--uncertainty needs a calibrated file: --geometry STATOR.toml or "
                        "--params PARAMS.json written by lusm calibrate (it carries the fit's "
                        "covariance)", "--uncertainty")
    try:
        cal = read_calibration(path)
    except CalibrationFileError as exc:
        raise LusmError(f"--uncertainty: {exc}", "--uncertainty") from None
    except (OSError, ValueError) as exc:  # the set itself was read already: seldom here
        raise LusmError(f"--uncertainty: cannot read {path} ({exc})", "--uncertainty") from None
    if cal is None:
        raise LusmError(f"--uncertainty: {path} carries no fit's covariance (no [calibration] "
                        "table; lusm calibrate writes one)", "--uncertainty")
    if motor is not None and cal.coupling and cal.coupling != motor.coupling:
        from lusm.messages import warn

        warn(f"--uncertainty: the fit in {path} ran the steady engine with --coupling "
             f"{cal.coupling}, this run with {motor.coupling}: the band carries the fit's "
             f"uncertainty to another model (pass --coupling {cal.coupling})")
    return cal


@contextmanager
def progress_bar(samples: int):
    """A callable ``(done, total)`` that moves a tqdm bar on stderr (shown after a second)."""
    from tqdm import tqdm

    bar = tqdm(total=samples, desc="uncertainty", unit="draw", delay=1.0, leave=False)
    try:
        def step(done: int, _total: int) -> None:
            bar.update(done - bar.n)

        yield step
    finally:
        bar.close()


def band_json(band, **quantities) -> dict:
    """``--json``'s ``uncertainty`` object: how the band was drawn, then each named
    quantity's band (:meth:`calibration.uncertainty.Band.summary`)."""
    return {**band.header(), **{k: b.summary() for k, b in quantities.items()}}


def band_text(summary: dict, scale: float = 1.0, fmt: str = ".4g") -> str:
    """``mean +/- std, 95 % [q2.5, q97.5]`` of one band value (``scale`` times the SI
    value)."""
    def f(x) -> str:
        return "nan" if x is None else format(x * scale, fmt)

    text = (f"{f(summary['mean'])} +/- {f(summary['std'])}, 95 % [{f(summary['q2.5'])}, "
            f"{f(summary['q97.5'])}]")
    missing = summary.get("missing")
    return text + (f" ({missing} draws without a steady speed)" if missing else "")


def drawn_line(header: dict) -> str:
    """What the bands rest on: the draws, the parameters drawn and those held."""
    held = header["held"]
    return (f"uncertainty: {header['samples']} parameter sets drawn (seed {header['seed']}) "
            f"from the calibration's covariance of {', '.join(header['sampled']) or 'nothing'}"
            + (f"; held at their values (not identifiable): {', '.join(held)}" if held else "")
            + (f"; {header['refused_draws']} invalid draws redrawn"
               if header["refused_draws"] else ""))


def check_work(args: argparse.Namespace, solves: int, motor, what: str) -> None:
    """Refuse, before any work, ``--uncertainty`` draws times ``solves`` steady solves above
    the steady engine's bound (:func:`lusm.options.check_steady_work`)."""
    from lusm.options import check_steady_work

    check_steady_work(args.uncertainty * solves, motor.params, motor.frequency_Hz,
                      motor.coupling, f"draws x {what}", "--uncertainty")


def run_band(args: argparse.Namespace, compute: Callable):
    """``compute(progress)`` with a progress bar over the draws."""
    with progress_bar(args.uncertainty) as step:
        return compute(step)
