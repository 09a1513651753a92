"""Option groups shared by the ``lusm`` commands, and the helpers that turn them into inputs.

* :func:`add_plate_options` - ``--geometry STATOR.toml`` and the plain-plate options
  ``--length-mm --width-mm --thickness-mm --gap-mm --material`` (every command that uses a
  stator); :func:`stator_from_args` builds the stator from them, in one place.
* :func:`add_drive_options` - ``--voltage --preload --frequency`` (contact commands);
  :func:`check_run_size` bounds the steps of a run before it starts.
* :func:`add_output_options` - ``--json``, ``--plot DIR`` / ``--out DIR``, ``--force``;
  :func:`print_json` writes valid JSON (no ``Infinity``), :func:`figure_set` builds an output
  set aside and moves it in complete (:mod:`lusm.output_set`).

Argument types (:func:`real`, :func:`integer`) check the value where it is typed, so the
message names the option and its range in the user's units. Only the standard library is
imported at module level: building the parser must stay fast (``lusm --help``).
"""

from __future__ import annotations

import argparse
import json
import math
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bounds import ParameterError
from lusm import limits
from lusm.errors import LusmError, design_error_text
from lusm.fe_errors import plate_refusal
from lusm.limits import MEASURED_THICK_RATIO
from lusm.messages import typed, warn, warn_unused

SOURCES = ("table2", "beam", "fem")
"""Parameter sources (:data:`rom.sources.SOURCES`, repeated so the parser needs no numpy)."""

MATERIALS = ("pzt8", "paper", "pzt4", "pzt5a", "pzt5h", "apc880")
"""Named materials (:data:`fem.material.MATERIAL_NAMES`)."""

PLATE_DEFAULTS_MM = {"--length-mm": 30.0, "--width-mm": 7.5, "--thickness-mm": 3.0,
                     "--gap-mm": 0.5}
"""The paper's plate (mm), used when neither --geometry nor a plate option is given."""

PLATE_OPTIONS = ("--length-mm", "--width-mm", "--thickness-mm", "--gap-mm")
GAP_RULE = "0, or at least 0.001 mm and below the plate's length and width"
"""The rest of ``--gap-mm``'s rule (docs/limits.md), said with its parse range."""
"""The plain-plate options every stator command takes."""


def _fmt(v: float) -> str:
    return f"{v:g}"


def _range_text(lo: float | None, hi: float | None, lo_open: bool, hi_open: bool,
                unit: str) -> str:
    left = "(" if lo_open or lo is None else "["
    right = ")" if hi_open or hi is None else "]"
    a = "-inf" if lo is None else _fmt(lo)
    b = "inf" if hi is None else _fmt(hi)
    return f"{left}{a}, {b}{right}" + (f" {unit}" if unit else "")


def real(option: str, unit: str = "", lo: float | None = None, hi: float | None = None,
         lo_open: bool = False, hi_open: bool = False, rule: str = ""):
    """An argparse ``type`` for a finite number in a range; messages name ``option``.

    Parameters
    ----------
    option : str
        The option (``'--voltage'``), for the message.
    unit : str
        Its unit as the user types it (``'V'``, ``'mm'``).
    lo, hi : float, optional
        Bounds; ``lo_open`` / ``hi_open`` make them exclusive.
    rule : str
        What else a value must satisfy, checked later against the other options (said with
        the range, so that one refusal names the whole rule).
    """
    allowed = _range_text(lo, hi, lo_open, hi_open, unit) + (f" ({rule})" if rule else "")

    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(
                f"{option} must be a number in {allowed}, got {text!r}") from None
        bad = (not math.isfinite(value)
               or (lo is not None and (value < lo or (lo_open and value == lo)))
               or (hi is not None and (value > hi or (hi_open and value == hi))))
        if bad:
            raise argparse.ArgumentTypeError(f"{option} must be a number in {allowed}, "
                                             f"got {text!r}")
        return value

    parse.__name__ = option  # argparse names the type in some messages
    return parse


def integer(option: str, lo: int, hi: int | None = None, work: bool = False,
            note: str = ""):
    """An argparse ``type`` for an integer in ``[lo, hi]``.

    ``work=True`` makes ``hi`` a work bound, multiplied by ``LUSM_MAX_WORK``; ``note`` follows
    the range in the message (another mode's narrower range, say).
    """

    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            value = None
        try:
            top = None if hi is None else (limits.work_bound(hi) if work else hi)
        except ValueError as exc:  # a bad LUSM_MAX_WORK
            raise argparse.ArgumentTypeError(str(exc)) from None
        if value is None or value < lo or (top is not None and value > top):
            rng = f"[{lo}, {top}]" if top is not None else f">= {lo}"
            hint = f" ({limits.more_work_hint()})" if work and value is not None and (
                value > (top or value)) else ""
            raise argparse.ArgumentTypeError(
                f"{option} must be an integer in {rng}{note}, got {text!r}{hint}")
        return value

    parse.__name__ = option
    return parse


# --- plate / geometry -------------------------------------------------------------------------

def add_plate_options(p: argparse.ArgumentParser, *, material: bool = True,
                      note: str = "") -> argparse._ArgumentGroup:
    """``--geometry`` and the plain-plate options; all default to None (the paper's plate)."""
    g = p.add_argument_group("stator", "the paper's 30 x 7.5 x 3 mm PZT-8 plate unless "
                             "--geometry or a plate option is given" + note)
    g.add_argument("--geometry", metavar="STATOR.toml", default=None,
                   help="stator file (fem.stator_file): dimensions, electrodes, material, "
                   "points, mesh; replaces the plate options")
    lo, hi = limits.PLATE_MM
    g.add_argument("--length-mm", type=real("--length-mm", "mm", lo, hi), default=None,
                   help="plate length l (mm), default 30")
    g.add_argument("--width-mm", type=real("--width-mm", "mm", lo, hi), default=None,
                   help="plate width b_s (mm), default 7.5")
    g.add_argument("--thickness-mm", type=real("--thickness-mm", "mm", lo, hi), default=None,
                   help="plate thickness h_s (mm), default 3")
    g.add_argument("--gap-mm", type=real("--gap-mm", "mm", 0.0, hi, rule=GAP_RULE),
                   default=None, help="electrode gap (mm), default 0.5")
    if material:
        g.add_argument("--material", choices=MATERIALS, default=None,
                       help="plate material, default pzt8")
    return g


def add_rest_option(p: argparse.ArgumentParser) -> None:
    """``--rest probe|transient``: how the steady engine's exact level decides the branch a
    start from rest reaches (:func:`contact.steady.engine.steady_state` ``rest=``)."""
    p.add_argument("--rest", choices=("probe", "transient"), default="probe",
                   help="how the exact steady engine decides the branch a start from rest "
                   "reaches: probe (default) runs the full model out of the slider's ripple "
                   "zone and follows the averaged sheet it is on, with a transient where it "
                   "cannot decide; transient runs a 2 000-period transient from rest at every "
                   "point, slower, the reference (docs/steady.md, 'The start from rest')")


def add_motor_options(p: argparse.ArgumentParser, *, friction_note: str = "") -> None:
    """The motor model: ``--no-ultrasonic-friction``, ``--coupling``, ``--source`` and the
    stator options of :func:`add_plate_options` (every command that runs the contact model)."""
    g = p.add_argument_group("motor model", "the parameter set and the contact model")
    g.add_argument("--no-ultrasonic-friction", action="store_true",
                   help="use the constant mu_d instead of Eq. 11" + friction_note)
    g.add_argument("--coupling", choices=("auto", "paper", "consistent"), default="auto",
                   help="tangential force on B2: eta_T F_T (paper) or -phi_B(l) F_T "
                   "(consistent); auto (default): paper for Table 2's set, consistent for "
                   "every other set (docs/contact.md 2.3)")
    g.add_argument("--source", choices=SOURCES, default=None,
                   help="parameter set (default table2; fem with --geometry or a plate option)")
    g.add_argument("--params", metavar="PARAMS.json", default=None,
                   help="a parameter set saved with 'lusm params --json' (edit its stored "
                   "fields, e.g. C_l for the damping); replaces --source and the stator")
    add_damping_option(g, "the fem and beam sets and the plate options")
    add_plate_options(p, note="; any of them selects --source fem")


def add_damping_option(g, what: str) -> None:
    """``--damping material|table2``: the modal damping of ``what`` (sets without damping
    ratios of their own; :func:`set_damping`)."""
    g.add_argument("--damping", choices=("material", "table2"), default="material",
                   help=f"modal damping of {what}: material (default), the material's "
                   "data-sheet Q_m with the mount's (docs/designer.md); table2, Table 2's "
                   "ratios, as the paper's comparisons take them. A stator file's [damping] "
                   "sets its own")


def check_damping_clash(args: argparse.Namespace, own: list[str]) -> None:
    """Refuse ``--damping table2`` beside an option that sets the damping itself (``own``:
    the options given, e.g. ``["--geometry"]``), naming the first."""
    if getattr(args, "damping", None) == "table2" and own:
        what = ("--zeta sets both ratios" if own[0] == "--zeta" else "the file sets the "
                "damping (a stator file's [damping] source = \"table2\" for Table 2's "
                "ratios)")
        raise LusmError(f"--damping cannot be combined with {own[0]}: {what}", "--damping")


def add_contact_options(p: argparse.ArgumentParser, *, folder_help: str,
                        friction_note: str = "") -> None:
    """The options of every command that runs the contact model, after its own and the
    drive's (:func:`add_drive_options`): ``--rest`` (:func:`add_rest_option`), the motor
    model (:func:`add_motor_options`) and the output (``--json``, ``--plot DIR``, ``--force``;
    ``folder_help`` says what goes into DIR)."""
    add_rest_option(p)
    add_motor_options(p, friction_note=friction_note)
    add_output_options(p, folder="--plot", folder_help=folder_help)


def coupling_of(args: argparse.Namespace, params) -> tuple[str, str]:
    """The coupling to run ``params`` with and where the choice came from: ``--coupling``
    as typed, or for ``auto`` :func:`contact.model.default_coupling`; refused, naming the
    option behind the set, where the set has no stick force under it
    (:func:`contact.model.gamma_T`)."""
    from contact.model import default_coupling, gamma_T
    from rom.table2 import table2

    if getattr(args, "coupling", "auto") != "auto":
        coupling, why = args.coupling, "--coupling"
    else:
        coupling, why = default_coupling(params)
    try:
        gamma_T(params, coupling)
    except ValueError as exc:
        option = next((o for o in ("--params", "--geometry") if typed(o)), "--coupling")
        given = getattr(args, option.lstrip("-"), None) if option != "--coupling" else None
        raise LusmError(f"{option}{f' {given}' if given else ''}: {exc}", option) from None
    if why == "--coupling":
        return coupling, why
    if coupling != "paper" and params.source.split(" [edited in ")[0] == table2().source:
        # an edited copy of Table 2 (a --params file): the rule switches the coupling, which
        # alone changes the speed several-fold; say so rather than let it pass for the edit
        warn("this set is an edited copy of Table 2's (its source is still Table 2's), so "
             "--coupling auto runs the work-consistent coupling, not the paper's that Table "
             "2's own runs use; add --coupling paper to see the effect of the edit alone "
             "(docs/contact.md 2.3.1)")
    return coupling, why


MAX_PARAMS_FILE_BYTES = 1_000_000
"""Largest ``--params`` file (bytes) read: a parameter set is about 1 kB."""


def params_from_file(path_text: str):
    """The :class:`rom.params.MotorParams` of a ``lusm params --json`` file (``--params``)."""
    from rom.params import MotorParams

    if not str(path_text).strip():
        raise LusmError("--params must name a file, got ''", "--params")
    from fem.small_file import FileTooLarge, NotRegularFile, read_small_text

    path = Path(path_text)
    if path.is_dir():
        raise LusmError(f"--params {path_text} is a folder; name a file saved with "
                        "'lusm params --json'", "--params")
    if not path.exists():
        from fem.small_file import link_loop

        loop = link_loop(path)
        raise LusmError(f"--params {path_text}: "
                        + (f"a loop of symbolic links ({loop})" if loop else "no such file"),
                        "--params")
    try:
        # bounded: a 512 MB file is not read whole (1.1 GB of memory), nor a FIFO waited on
        data = json.loads(read_small_text(path, MAX_PARAMS_FILE_BYTES))
    except (OSError, ValueError, RecursionError) as exc:  # NotRegularFile, FileTooLarge,
        # decoding: ValueError; arrays nested 100 000 deep: RecursionError
        if isinstance(exc, RecursionError):
            why = ": not a JSON parameter set (nested too deeply)"
        elif isinstance(exc, NotRegularFile):  # /dev/zero: not "no such file"
            why = f": not a regular file ({exc.what})"
        elif isinstance(exc, FileTooLarge):
            why = (f" has {exc.size} bytes, above {MAX_PARAMS_FILE_BYTES} for a parameter set "
                   "(about 1 kB)")
        elif isinstance(exc, OSError):  # unreadable, not "not a JSON parameter set"
            why = f": cannot read it ({exc.strerror or exc})"
        elif isinstance(exc, UnicodeDecodeError):
            why = (f": not UTF-8 text (byte {exc.start}: {exc.reason}); save it with "
                   "'lusm params --json'")
        else:
            why = f": not a JSON parameter set ({exc})"
        raise LusmError(f"--params {path_text}{why}", "--params") from None
    from rom.params import DERIVED_KEYS as derived
    from rom.params import derived_disagrees

    try:
        stored = {k: v for k, v in data.items() if k not in derived} \
            if isinstance(data, dict) else data
        params = MotorParams.from_dict(stored)
    except (TypeError, ValueError) as exc:  # the file's key, not the dataclass's field
        text = exc.said(f"key {exc.name}") if isinstance(exc, ParameterError) else str(exc)
        raise LusmError(f"--params {path_text}: {text}", "--params") from None
    # the derived keys follow the stored fields: an edit of C_l leaves a stale zeta_L1, which
    # is recomputed, and said so (the help says to edit C_l)
    edited = []
    for key in derived:
        got, want = data.get(key), getattr(params, key)
        # to single precision's rounding: a file written from float32 data keeps its
        # derived keys and its source text
        if isinstance(got, (int, float)) and derived_disagrees(params, key, got):
            warn(f"--params {path_text}: {key} = {got:.6g} in the file is derived; recomputed "
                 f"from the stored fields as {want:.6g} (to change it, edit "
                 f"{_SOURCES_OF[key]})")
            edited.append(f"{key} {want:.4g}")
    if edited:  # the source text still described the set before the edit ("damping 0.01")
        from dataclasses import replace

        params = replace(params, source=f"{params.source} [edited in {path_text}: "
                                        f"{', '.join(edited)}]")
    _check_params_ranges(params, path_text)
    return params


_SOURCES_OF = {"eta_N": "phi_L0, phi_Ll", "eta_T": "phi_B0, phi_Bl",
               "f_L1_Hz": "M_l, K_l", "zeta_L1": "M_l, K_l, C_l",
               "f_B2_Hz": "M_b, K_b", "zeta_B2": "M_b, K_b, C_b"}
"""The stored fields each derived key of a parameter file follows."""


def _check_params_ranges(params, path_text: str) -> None:
    """The ranges a stator file holds the same quantities to (``[contact]``, ``[slider]``,
    ``[friction]``, ``[damping]``), so that a --params file cannot run k_contact = 1e15 N/m
    or damping ratios of 7e-7."""
    from fem.stator_file import DAMPING_RATIO_RANGE, MOTOR_KEYS

    for table in MOTOR_KEYS.values():
        for field, lo, hi, lo_ok, unit in table.values():
            v = float(getattr(params, field))
            if not (v >= lo if lo_ok else v > lo) or v > hi:
                raise LusmError(f"--params {path_text}: {field} must lie in "
                                f"{'[' if lo_ok else '('}{lo:g}, {hi:g}] {unit}".rstrip()
                                + f", got {v:g}", "--params")
    lo, hi = DAMPING_RATIO_RANGE
    for field in ("zeta_L1", "zeta_B2"):
        v = float(getattr(params, field))
        if not lo <= v < hi:
            raise LusmError(f"--params {path_text}: {field} = {v:.3g} (from the masses, "
                            f"stiffnesses and dampings) must lie in [{lo:g}, {hi:g})",
                            "--params")


def plate_given(args: argparse.Namespace) -> list[str]:
    """The plate options the user typed (not their defaults)."""
    given = [o for o in PLATE_OPTIONS if getattr(args, o[2:].replace("-", "_"), None) is not None]
    if getattr(args, "material", None) is not None:
        given.append("--material")
    return given


def _number_text(value: float) -> str:
    """``value`` as short as it reads back exactly (``60`` for 60.0, ``7.35`` for 7.35)."""
    short = f"{value:g}"
    return short if float(short) == value else repr(float(value))


def stator_options_text(args: argparse.Namespace) -> str:
    """The stator options the user typed, as they go on a ``lusm`` command line:
    ``--geometry FILE`` (the path as given) or the typed plate options and ``--material``
    (empty for the paper's plate). A report cites its commands with these, so that each
    reproduces the report's numbers (``--length-mm 60``, not a ``--geometry ...`` that no
    file stands behind)."""
    import shlex

    if getattr(args, "geometry", None):
        return f"--geometry {shlex.quote(str(args.geometry))}"
    words = [f"{o} {_number_text(getattr(args, o[2:].replace('-', '_')))}"
             for o in plate_given(args) if o in PLATE_OPTIONS]
    if getattr(args, "material", None) is not None:
        words.append(f"--material {shlex.quote(args.material)}")
    return " ".join(words)


@dataclass(frozen=True)
class StatorChoice:
    """The stator the options name.

    Attributes
    ----------
    stator : fem.geometry.PlateStator
        A plain plate or, from a stator file, a ``MeshedStator`` (a mesh file) or a
        ``ParametricStator`` (feature tables, meshed by gmsh).
    material : fem.material.PiezoMaterial
    design : fem.stator_file.StatorDesign or None
        The loaded stator file, if ``--geometry`` was given.
    """

    stator: Any
    material: Any
    design: Any = None

    @property
    def meshed(self) -> bool:
        """True for a stator file with its own mesh."""
        return self.design is not None and self.design.mesh_path is not None

    @property
    def parametric(self) -> bool:
        """True for a stator file with features (``[tip]``, ...), meshed by gmsh."""
        return hasattr(self.stator, "features_text")


def check_plate_mm(length: float, width: float, thickness: float, gap: float,
                   gap_given: bool = True, three_d: bool = False,
                   file: str | None = None, thin_warning: bool = True) -> None:
    """Refuse an electrode gap that eats the plate or is too narrow to model; warn outside
    plane stress's validity (the 2D model's; ``three_d``: the 3D model, which needs a gap).
    With ``file`` (a ``--geometry`` stator file) the messages name its keys, not the plate
    options the user did not type."""
    from fem.geometry import MIN_GAP_M

    if file is None:
        where, option = "", "--gap-mm"
        gap_name, dims, thick = "--gap-mm", "--length-mm and --width-mm", "--thickness-mm"
    else:
        where, option = f"--geometry {file}: ", "--geometry"
        gap_name, dims, thick = ("[electrodes] gap_mm", "[plate] length_mm and width_mm",
                                 "[plate] thickness_mm")
    if three_d and gap == 0.0:
        raise LusmError(f"{where}{gap_name} must be at least {MIN_GAP_M * 1e3:g} mm with "
                        "--model 3d, got 0: with no gap the four quadrants touch and form one "
                        "conductor", option)
    if 0.0 < gap < MIN_GAP_M * 1e3:
        raise LusmError(f"{where}{gap_name} must be 0 (touching quadrants) or at least "
                        f"{MIN_GAP_M * 1e3:g} mm, got {gap:g}", option)
    if gap >= min(length, width):
        which = gap_name if gap_given else f"the default {gap_name} {gap:g}"
        raise LusmError(f"{where}{which} must be below the plate's {dims} "
                        f"(min {min(length, width):g} mm), got {gap:g}; give a smaller "
                        f"{gap_name}", option)
    if not three_d and thin_warning:
        # the default thickness is said to be one: a 1000 x 1 mm plate is warned about a
        # thickness the user did not type
        default = file is None and not typed("--thickness-mm")
        warn_thin_plate(f"{where}{'the default ' if default else ''}{thick} {thickness:g}",
                        thickness, min(length, width), "the plate's smaller in-plane dimension")


def warn_thin_plate(subject: str, thickness_mm: float, inplane_mm: float, against: str,
                    remedy: str = "check it with lusm modes --model 3d") -> None:
    """The 2D model's validity warning, for the plain plate, a stator file's mesh, a tuned
    plate and a study alike: ``subject`` is ``thickness / inplane`` times ``against``, above
    :data:`limits.PLANE_STRESS_RATIO`."""
    ratio = thickness_mm / inplane_mm
    if ratio > limits.PLANE_STRESS_RATIO:
        # at 133 x (--thickness-mm 1000) the measured 0.6 % is not the error to expect
        beyond = (f"; beyond {MEASURED_THICK_RATIO:g} x its error is not measured, and its "
                  "frequencies and force factors need not be a plate's at all"
                  if ratio > MEASURED_THICK_RATIO * 1.5 else "")
        warn(f"{subject} is {ratio:.3g} x {against}; the 2D plane-stress model assumes a thin "
             f"plate (thickness below {limits.PLANE_STRESS_RATIO:g} x min(length, width); its "
             f"B2 is 0.08 % below the 3D model's at 0.8 on a 25 x 5 mm plate, 0.6 % off with "
             f"its k_eff 9 % high at {MEASURED_THICK_RATIO:g}, the 3 mm plate tuned to 2e5 "
             f"Hz{beyond}); {remedy}")


HOLE_AREA_SHARE = 0.005
"""A through hole of diameter d in a plate of thickness h, length L and width W makes the 2D
model miss the 0.05 % goal against 3D where ``d h > HOLE_AREA_SHARE L W`` (measured,
docs/fem3d.md): plane stress misses the 3D boundary layer, about h wide, along
the hole's rim."""


def warn_holes(stator, subject: str) -> None:
    """The 2D model's warning for through holes: 2D is softer than 3D around a hole's rim
    (the 3D boundary layer there is about a thickness wide), by 0.08-0.11 % on L1 and B2 for
    a 1 mm hole at the centre of the paper's 3 mm plate and 0.2-0.4 % for a 3 mm one
    (``benchmarks/fem_holes_2d_3d.py``); a parametric stator with holes is warned too."""
    holes = getattr(stator, "holes_m", ())
    h = stator.thickness_m
    bound = HOLE_AREA_SHARE * stator.length_m * stator.width_m
    worst = max(holes, key=lambda hole: hole[2], default=None)
    if worst is not None and worst[2] * h > bound:
        warn(f"{subject}: a through hole of {worst[2] * 1e3:g} mm in a {h * 1e3:g} mm plate "
             f"(d h above {HOLE_AREA_SHARE:g} of the planform's area): the 2D plane-stress "
             "model is softer than 3D along the hole's rim (a 1 mm hole at the centre of "
             "the 3 mm plate: L1 and B2 0.08-0.11 % low, a 3 mm one 0.2-0.4 %; "
             "docs/fem3d.md); check it with lusm modes --model 3d")


def stator_from_args(args: argparse.Namespace, *, warn_thin: bool = True) -> StatorChoice:
    """The stator of ``--geometry`` or of the plate options (the paper's plate by default).

    Raises
    ------
    LusmError
        Plate options next to ``--geometry``, or an invalid plate, naming the option.
    """
    from fem.geometry import PlateStator
    from fem.material import get_material
    from fem.units import to_si

    given = plate_given(args)
    three_d = getattr(args, "model", None) == "3d"
    if getattr(args, "geometry", None):
        if given:
            raise LusmError(f"{', '.join(given)} cannot be combined with --geometry: the "
                            "stator file sets the plate, electrodes and material", given[0])
        design = load_design(args.geometry)
        st = design.stator
        if design.mesh_path is None:
            check_plate_mm(st.length_m * 1e3, st.width_m * 1e3, st.thickness_m * 1e3,
                           st.electrode_gap_m * 1e3, three_d=three_d,
                           file=args.geometry, thin_warning=warn_thin)
        elif not three_d and warn_thin:  # the mesh's bounding box against the thickness
            warn_thin_plate(f"--geometry {args.geometry}: thickness "
                            f"{st.thickness_m * 1e3:g} mm", st.thickness_m * 1e3,
                            min(st.length_m, st.width_m) * 1e3,
                            "the mesh's smaller in-plane extent")
        choice = StatorChoice(st, design.material, design)
        warn_refine_unused(choice, args.geometry)
        if not three_d and warn_thin:
            warn_holes(st, f"--geometry {args.geometry}")
        return choice
    mm = {o: getattr(args, o[2:].replace("-", "_"), None) for o in PLATE_OPTIONS}
    mm = {o: PLATE_DEFAULTS_MM[o] if v is None else v for o, v in mm.items()}
    check_plate_mm(mm["--length-mm"], mm["--width-mm"], mm["--thickness-mm"], mm["--gap-mm"],
                   gap_given=getattr(args, "gap_mm", None) is not None,
                   three_d=three_d, thin_warning=warn_thin)
    # the double nearest each decimal typed, as a study's axes and a stator file's give it
    # (6.5 * 1e-3 is 0.006500000000000001, a plate 1 ulp off the study's "6.5 mm")
    stator = PlateStator(length_m=to_si(mm["--length-mm"], 1e-3),
                         width_m=to_si(mm["--width-mm"], 1e-3),
                         thickness_m=to_si(mm["--thickness-mm"], 1e-3),
                         electrode_gap_m=to_si(mm["--gap-mm"], 1e-3))
    return StatorChoice(stator, get_material(getattr(args, "material", None) or "pzt8"))


def warn_refine_unused(choice: StatorChoice, geometry: str) -> None:
    """Warn that ``--refine`` has no effect on a stator file that carries its mesh or is
    meshed by gmsh: the 2D model solves on that mesh and the 3D model extrudes it (modes,
    render, admittance and sweep run the same mesh whatever --refine says, and a
    convergence study over --refine would look converged)."""
    if choice.meshed or choice.parametric:
        warn_unused(("--refine",), f"--geometry {geometry} is meshed by "
                    + ("gmsh at its [mesh] size_mm (default min(length, width) / 8)"
                       if choice.parametric else "its own mesh file"))


def check_steady_frequency(params, frequency_Hz: float, coupling: str) -> int:
    """Refuse a drive too far below the stator's fastest mode for the steady engine (more
    than :data:`contact.steady.slow.MAX_STEPS_PER_PERIOD` steps per drive period), with the range
    of ``--frequency`` it takes (:func:`contact.steady.slow.lowest_frequency_Hz`, from the same
    count); the steps per drive period at ``frequency_Hz`` otherwise. One message for
    ``characteristic``, ``map`` and ``simulate --steady``."""
    from contact.steady.slow import MAX_STEPS_PER_PERIOD, lowest_frequency_Hz, steps_per_period

    n = steps_per_period(params, frequency_Hz, coupling)
    if n <= MAX_STEPS_PER_PERIOD:
        return n
    lo, hi = lowest_frequency_Hz(params, coupling), limits.FREQUENCY_HZ[1]
    steps = f"{n} steps per drive period, above {MAX_STEPS_PER_PERIOD}"
    if lo > hi:  # a stator stiffer than any drive the option takes
        raise LusmError(f"--frequency: no drive in [{limits.FREQUENCY_HZ[0]:g}, {hi:g}] Hz "
                        f"suits the steady engine on this stator, whose fastest mode needs "
                        f"{lo:g} Hz or more ({steps} at {frequency_Hz:g} Hz)", "--frequency")
    raise LusmError(f"--frequency must be in [{lo:g}, {hi:g}] Hz for the steady engine on "
                    f"this stator, got {frequency_Hz:g}: too far below its fastest mode "
                    f"({steps})", "--frequency")


def check_steady_work(solves: int, params, frequency_Hz: float, coupling: str,
                      what: str, option: str) -> None:
    """Refuse, before any work, a steady study above :data:`limits.MAX_STEADY_WORK`: ``solves``
    steady points (or loads) at ``frequency_Hz``, each costing its steps per drive period
    (:func:`check_steady_frequency` first: no point at all if the drive frequency is too
    low). ``what`` says what was counted; the message names ``option``."""
    n = check_steady_frequency(params, frequency_Hz, coupling)
    top = limits.work_bound(limits.MAX_STEADY_WORK)
    if solves * n > top:
        raise LusmError(
            f"{option}: {solves} {what} at {frequency_Hz:g} Hz, {n} steps per drive period each, "
            f"is above the steady engine's limit of {top} (at most {max(top // n, 1)} here; "
            f"{limits.more_work_hint()})", option)


def check_fe_work(cells: int, solves: int, three_d: bool, option: str,
                  stator=None, fewer: str = "solve fewer plates") -> None:
    """Refuse a command whose FE solves together exceed the work bound: ``solves`` meshes of
    ``cells`` elements (or bricks) on average. Each mesh is also bounded alone
    (:func:`check_fe_size`); a sweep or a tuning multiplies it. A parametric ``stator`` is
    meshed by gmsh at its ``[mesh] size_mm``, which ``--refine`` does not change: the
    message then names --geometry and that key (not "lower --refine", which has no effect
    there). ``fewer`` says how to ask for fewer solves, or is
    empty where the command's solves are not the user's to choose (a tuning)."""
    from fem.meshing.parametric import ParametricStator

    top = limits.work_bound(limits.MAX_FE_WORK_3D if three_d else limits.MAX_FE_WORK_2D)
    if cells * solves > top:
        what = "3D bricks" if three_d else "elements"
        fix = f"lower {option}"
        if isinstance(stator, ParametricStator):
            option, fix = "--geometry", "coarsen its [mesh] size_mm"
        raise LusmError(
            f"{option}: {solves} FE solves of about {cells} {what} each ({cells * solves}) is "
            f"above the limit {top} for one command; {fix}{f' or {fewer}' if fewer else ''} "
            f"({limits.more_work_hint()})", option)


def check_b2_in_reach(stator) -> None:
    """Refuse, before any FE work, a plate whose B2 the 2D solver cannot reach from L1
    (:func:`fem.modes.check_b2_in_reach`): a 1000 x 1 mm plate took 14 s and 900 MB of
    solves to be refused."""
    from fem.modes import SlenderPlateError, WidePlateError
    from fem.modes import check_b2_in_reach as check

    try:
        check(stator)
    except (SlenderPlateError, WidePlateError) as exc:
        raise plate_refusal(exc) from None


def check_fe_size(stator, refine: int | None, layers: int | None = None,
                  option: str = "--refine", edge_grading: int = 0, quarter: bool = False,
                  layers_option: bool = True, has_option: bool = True,
                  needs_b2: bool = True) -> int:
    """Elements of the FE mesh ``stator`` and ``refine`` make; refuse a mesh above the bounds.

    The count is exact for the generated plate (``fem.meshing.mesh.grid_lines_m``, and
    ``fem.solid3d.model.hex_grid_lines`` for a 3D mesh graded ``edge_grading`` times, or
    ``fem.solid3d.symmetric.quarter_grid_lines`` with ``quarter``, the quarter-plate model)
    and is the file's for a stator with its own mesh (bounded when it is read). ``layers``
    selects the 3D count; ``layers_option``: whether the command has ``--layers`` to name
    (``tune --model 3d`` takes three layers and has none); ``has_option``: whether it has
    ``option`` at all (``report``, ``simulate --source fem`` have no ``--refine`` to lower);
    ``needs_b2``: the command solves the 2D model for L1 and B2, so a plate
    too slender for the solver to reach B2 is refused first (:func:`check_b2_in_reach`; not
    for the 3D model, whose search holds other modes, nor for an admittance over a band
    the user gave, which needs no L1/B2).
    """
    from fem.meshing.meshed_stator import planform_mesh

    if needs_b2 and layers is None:
        check_b2_in_reach(stator)
    mesh = planform_mesh(stator)
    from fem.cell_count import fe_cell_count

    n = fe_cell_count(stator, refine, layers, edge_grading, quarter)
    if layers is not None:
        top, what = limits.work_bound(limits.MAX_FE_CELLS_3D), "3D bricks"
    else:
        top, what = limits.work_bound(limits.MAX_FE_CELLS_2D), "2D elements"
    if n > top and mesh is not None:  # the stator file's mesh: --refine plays no part
        from fem.meshing.parametric import ParametricStator

        fix = ("coarsen its [mesh] size_mm" if isinstance(stator, ParametricStator)
               else "use a coarser mesh file")
        if layers is not None:  # the 3D layers: fewer fit, where the command has --layers
            given = [o for o in ("--edge-grading",) if typed(o)]
            if layers_option:
                given.append(f"--layers ({layers})")
            fix = f"lower {' or '.join(given)} or {fix}" if given else fix
        raise LusmError(f"--geometry: the stator's mesh needs {n} {what} here, above the limit "
                        f"{top}; {fix} ({limits.more_work_hint()})", "--geometry")
    if n > top:
        from validation.summaries import plate_text

        shape = plate_text(stator)
        dims_typed = [o for o in ("--length-mm", "--width-mm") if typed(o)]
        if not typed(option) and dims_typed and not typed("--geometry"):
            # the user gave the plate, not the mesh option: blame what they typed
            lower = f" or give a lower {option}" if has_option else ""
            raise LusmError(
                f"{dims_typed[0]}: the {shape} needs {n} {what} at the default mesh, above "
                f"the limit {top}; make the plate less elongated ({', '.join(dims_typed)})"
                f"{lower} ({limits.more_work_hint()})", dims_typed[0])
        names = [option] + [o for o, used in (("--refine", True), ("--layers", bool(layers)),
                                              ("--edge-grading", bool(edge_grading)))
                            if used and o != option]
        lower = f"lower {' or '.join(names)} or " if has_option else ""
        dims = (" (the stator file's [plate] length_mm, width_mm)" if typed("--geometry")
                else " (--length-mm, --width-mm)")
        blamed = option if has_option else ("--geometry" if typed("--geometry")
                                            else "--length-mm")
        raise LusmError(f"{blamed}: the {shape} needs {n} {what} here, above the limit {top}; "
                        f"{lower}make the plate less elongated{dims} "
                        f"({limits.more_work_hint()})", blamed)
    return n


def load_design(path: str | Path):
    """:func:`fem.stator_file.load_stator` with every failure as one line naming the file."""
    from fem.stator_file import load_stator

    try:
        return load_stator(path)
    except LusmError:
        raise
    except (ValueError, OSError) as exc:
        raise LusmError(f"--geometry {design_error_text(path, exc)}", "--geometry") from None


def fem_params_of(args: argparse.Namespace, source: str | None):
    """The parameter set of ``--source`` and the stator options (``fem`` when a stator is named).

    ``--geometry`` or a plate option selects the FE reduction of that stator; they cannot be
    combined with ``--source table2`` or ``beam``. :func:`motor_params_of` also says where the
    damping came from.
    """
    return motor_params_of(args, source)[0]


def beam_of_plate(args: argparse.Namespace):
    """Appendix A's beam of the length, width and thickness the options (or --geometry)
    name, with Table 1's constants: ``--source beam`` with plate options, and compare's beam
    column. A stator file with a planform of its own gives the extent of its electrodes (the
    body, without a bare contact tip)."""
    from fem.meshing.meshed_stator import has_planform, planform_mesh
    from rom.beam import plate_layout
    from rom.sources import get_params

    # the 2D plane-stress warning is the FE model's: the beam is not plane stress
    st = stator_from_args(args, warn_thin=False).stator
    gaps = (st.electrode_gap_m,)
    if has_planform(st):  # the file's mesh carries its gap strips (electrode_gap_m is 0)
        from fem.model import gap_layout

        layout = gap_layout(planform_mesh(st))
        gaps = (layout.gap_x_m, layout.gap_y_m)
    if min(gaps) <= 0.0:  # the FE set's refusal: lusm.errors.user_error words it
        from fem.errors import ShortedDriveError

        raise ShortedDriveError(
            f"electrodes {', '.join(map(str, st.drive_electrodes))} driven touch the grounded "
            "ones (no gap strip between them) and are one conductor, which cannot hold two "
            "voltages: the beam's drive would short", (1, 2, 3, 4))
    if typed("--gap-mm"):  # 0.5 and 2 mm give the same A_l: said
        warn("--gap-mm: Appendix A's beam drives whole quadrants, so the gap's width does not "
             "enter its force factors (a gap of 0, one conductor, is refused); the FE set "
             "models the gap")
    length, width = st.length_m, st.width_m
    if has_planform(st):
        # the electroded body, as a parametric stator's length is: a mesh file's bounding
        # box would count a 1 mm tip in (31 mm: L1 65.7 kHz against 67.9 kHz for the same
        # stator described by its [tip] table)
        x0, x1, y0, y1 = planform_mesh(st).electroded_box_m()
        length, width = y1 - y0, x1 - x0
    # the plate's own drive: a stator file driving 2, 3 drives the beam through 2, 3
    return get_params("beam", length_m=length, width_m=width, thickness_m=st.thickness_m,
                      electrode_layout=plate_layout(st.drive_electrodes),
                      damping_ratios=beam_damping(args)[0])


def beam_damping(args: argparse.Namespace | None = None
                 ) -> tuple[tuple[float, float] | None, str]:
    """:func:`set_damping` of Appendix A's beam: Table 1's constants are the paper's PZT-8,
    so PZT-8's data-sheet ``Q_m`` with the default mount loss."""
    from fem.material import pzt8

    return set_damping(args, pzt8(), "beam")


def set_damping(args: argparse.Namespace | None, material, what: str
                ) -> tuple[tuple[float, float] | None, str]:
    """The damping ``--damping`` asks of a set without ratios of its own (``what``: ``"fem"``
    or ``"beam"``): :func:`validation.summaries.plate_damping` of ``material``, or Table 2's
    ratios (None) for ``--damping table2``."""
    from validation.summaries import borrowed_damping, plate_damping

    if getattr(args, "damping", None) == "table2":
        return None, f"{borrowed_damping(what)} (--damping table2)"
    return plate_damping(material, what)


@dataclass(frozen=True)
class Motor:
    """The motor a contact command's options name, resolved once.

    Attributes
    ----------
    params : rom.params.MotorParams
        The parameter set (``--source``, a stator, ``--params``).
    damping_from : str
        Where its damping ratios come from (:func:`validation.summaries.damping_line`).
    coupling, coupling_from : str
        The tangential coupling in use and why (:func:`coupling_of`).
    frequency_Hz : float
        The drive frequency (Hz): ``--frequency`` as typed, or the set's own operating point
        for ``auto``.
    frequency_auto : bool
        Whether ``--frequency`` asked for the set's own operating point.
    """

    params: object
    damping_from: str
    coupling: str
    coupling_from: str
    frequency_Hz: float
    frequency_auto: bool


def default_frequency_text(params) -> str:
    """The drive frequency without ``--frequency``: the paper's 40 kHz for Table 2's set
    (the paper's drive), ``'auto'`` (the set's own operating point) for any other: a
    designer's stator is driven where its modes are, not at the paper's frequency."""
    from contact.model import is_table2

    return "40e3" if is_table2(params) else "auto"


def resolve_motor(args: argparse.Namespace) -> Motor:
    """The parameter set, coupling and drive frequency of ``args`` (with ``--source``,
    ``--coupling`` and ``--frequency``: :func:`default_frequency_text` when not given), with
    the fallback's warning said where the default finds no operating point."""
    params, damping_from = motor_params_of(args, args.source)
    coupling, coupling_from = coupling_of(args, params)
    text = args.frequency if args.frequency is not None else default_frequency_text(params)
    try:
        freq = parse_frequency(text, params)
    except LusmError:
        if args.frequency is not None:
            raise
        # the default asked for no operating point it cannot find: the paper's drive
        warn("--frequency: this set drives no tip ellipse, so it has no operating point; "
             "driving it at the paper's 40 kHz (give --frequency)")
        text, freq = "40e3", 40e3
    return Motor(params, damping_from, coupling, coupling_from, freq,
                 known_frequency(text) is None)


def resolve_drive(args: argparse.Namespace, voltages_V: Sequence[float], preload_N: float,
                  check_size: Callable[[float], None] | None = None, *,
                  load_N: float = 0.0, voltage_option: str = "--voltage",
                  preload_option: str = "--preload") -> tuple[Path | None, Motor]:
    """The start of every contact command, in the order its refusals are said: the ``--plot``
    folder checked (:func:`output_folder`), each of ``voltages_V`` at ``preload_N`` warned of
    (:func:`warn_drive`, the options named as the command spells them), ``check_size`` at a
    typed ``--frequency`` (Hz) before any work, the motor resolved (:func:`resolve_motor`),
    then ``check_size`` at an ``auto`` frequency, which needs the parameter set.

    Returns
    -------
    plot : pathlib.Path or None
        The ``--plot`` folder, None when not given.
    motor : Motor
        The resolved parameter set, coupling and drive frequency.
    """
    plot = output_folder(args, "--plot")
    for v in voltages_V:
        warn_drive(v, preload_N, voltage_option=voltage_option, preload_option=preload_option,
                   load_N=load_N)
    known = known_frequency(args.frequency)
    if known is not None and check_size is not None:
        check_size(known)
    motor = resolve_motor(args)
    if known is None and check_size is not None:
        check_size(motor.frequency_Hz)
    return plot, motor


def add_band_options(p: argparse.ArgumentParser, points: int) -> None:
    """``--f-min``, ``--f-max`` (default: the design's L1 and B2 -+ 15 % of their mean) and
    ``--points`` (default ``points``) of a frequency sweep."""
    f_lo, f_hi = limits.FREQUENCY_HZ
    p.add_argument("--f-min", type=real("--f-min", "Hz", f_lo, f_hi), default=None,
                   metavar="HZ", help="band start (Hz); default: the design's L1 and B2 "
                   "minus 15 %% of their mean")
    p.add_argument("--f-max", type=real("--f-max", "Hz", f_lo, f_hi), default=None,
                   metavar="HZ", help="band end (Hz); default: the design's L1 and B2 plus "
                   "15 %% of their mean")
    p.add_argument("--points", default=points, metavar="N",
                   type=integer("--points", 3, limits.MAX_FREQUENCY_POINTS, work=True),
                   help=f"frequency points (default {points})")


def check_band_order(f_min_Hz: float | None, f_max_Hz: float | None) -> None:
    """Refuse ``--f-min`` not below ``--f-max`` where both are given."""
    if f_min_Hz is not None and f_max_Hz is not None and not f_min_Hz < f_max_Hz:
        raise LusmError(f"--f-min must be below --f-max, got {f_min_Hz:g} and "
                        f"{f_max_Hz:g} Hz", "--f-min")


def fem_damping_origin(geometry: str | None, design) -> str:
    """Where an FE set's damping ratios come from (text for
    :func:`validation.summaries.damping_line`): the stator file's ``[damping]``, or Table 2's
    ratios borrowed."""
    from validation.summaries import borrowed_damping

    if design is None:
        return borrowed_damping("fem")
    if design.damping_origin:
        return f"stator file {geometry} {design.damping_origin}"
    return f"{borrowed_damping('fem')}; stator file {geometry} has no [damping]"


def motor_params_of(args: argparse.Namespace, source: str | None):
    """:func:`fem_params_of` and where its damping ratios come from (text for
    :func:`validation.summaries.damping_line`): Table 2 for the ``table2`` set, a stator
    file's ``[damping]``, the material's ``Q_m`` with the mount's for a stator without
    damping ratios (a stator file without them, the plate options, ``--source fem`` and
    ``beam``: :func:`validation.summaries.plate_damping`), or a ``--params`` file."""
    from fem.material import pzt8
    from validation.summaries import table2_damping

    named = bool(getattr(args, "geometry", None)) or bool(plate_given(args))
    check_damping_clash(args, [f"--{o}" for o in ("geometry", "params")
                               if getattr(args, o, None)])
    if source == "beam":
        warn_unused(("--material",), "Appendix A's beam takes Table 1's constants (density, "
                    "cE11, cE66, e31) whatever the plate's material")
    if getattr(args, "params", None) is not None:
        clash = (["--geometry"] if getattr(args, "geometry", None) else []) + plate_given(args)
        if source is not None:
            clash.append("--source")
        if clash:
            raise LusmError(f"--params cannot be combined with {clash[0]}: the file is the "
                            "whole parameter set", "--params")
        params = params_from_file(args.params)
        warn_unexcited_mode(params, None)  # as a stator file's drive is warned of
        return params, f"params file {args.params} (its C_l, C_b)"
    if named:
        what = "--geometry" if getattr(args, "geometry", None) else plate_given(args)[0]
        if source == "beam" and not getattr(args, "geometry", None):
            return beam_of_plate(args), beam_damping(args)[1]
        if source not in (None, "fem"):
            raise LusmError(f"{what} needs --source fem (or beam, for plate options), got "
                            f"--source {source}", "--source")
        choice = stator_from_args(args)  # checks the options and the file first
        check_fe_size(choice.stator, None, has_option=False)  # no --refine on these commands
        from rom.errors import DesignFileError, NodalPointError
        from rom.from_fem import design_base, fem_params, fem_params_from_file

        design = choice.design
        origin = fem_damping_origin(args.geometry, design)
        if design is not None:
            try:  # the motor tables against Table 2's other constants, before any FE work
                design_base(design)
            except ValueError as exc:
                raise LusmError(f"--geometry {exc}", "--geometry") from None
        ratios = None
        if design is None:
            ratios, origin = set_damping(args, choice.material, "fem")
        try:
            params = (fem_params_from_file(args.geometry) if design is not None
                      else fem_params(choice.stator, choice.material, damping_ratios=ratios))
        except Exception as exc:  # mode solver, factorisation, point search on extreme plates
            from lusm.fe_errors import fe_failure, is_fe_failure

            if is_fe_failure(exc):
                raise fe_failure(exc, choice.stator) from exc
            if design is not None and isinstance(exc, DesignFileError):  # the file's terms
                raise LusmError(f"--geometry {exc}", "--geometry") from None
            if design is not None and isinstance(exc, NodalPointError):
                # a tip or preload point at a node of its mode: the file's [points] key
                raise LusmError(f"--geometry {args.geometry}: {exc}", "--geometry") from None
            raise
        warn_unexcited_mode(params, choice.stator.drive_electrodes)
        return params, origin
    from rom.sources import get_params

    name = source or "table2"
    if name == "table2":
        return get_params(name), table2_damping()
    ratios, origin = (beam_damping(args) if name == "beam"
                      else set_damping(args, pzt8(), "fem"))  # fem_params' default material
    return get_params(name, damping_ratios=ratios), origin


# --- drive ------------------------------------------------------------------------------------

def real_list(option: str, unit: str, lo: float, hi: float, most: int):
    """An argparse ``type`` for ``A,B,C``: at most ``most`` finite numbers in ``[lo, hi]``,
    returned as a tuple; messages name ``option``."""
    one = real(option, unit, lo, hi)
    allowed = _range_text(lo, hi, False, False, unit)

    def parse(text: str) -> tuple[float, ...]:
        items = [t.strip() for t in text.split(",")]
        if not 1 <= len(items) <= most:
            raise argparse.ArgumentTypeError(
                f"{option} takes 1 to {most} comma-separated values in {allowed}, "
                f"got {text!r}")
        if len(items) == 1:
            return (one(items[0]),)
        values = []
        for item in items:
            try:
                values.append(one(item))
            except argparse.ArgumentTypeError:
                # the text typed, not the item alone: '200,' is said, not "got ''", which the
                # user never typed
                why = "an empty item" if not item else f"{item!r} is not one"
                raise argparse.ArgumentTypeError(
                    f"{option} takes 1 to {most} comma-separated values in {allowed}, "
                    f"got {text!r} ({why})") from None
        values = tuple(values)
        twice = sorted({v for v in values if values.count(v) > 1})
        if twice:  # a typo more likely than a wish to compute the same curve twice
            raise argparse.ArgumentTypeError(
                f"{option} lists {twice[0]:g} {unit} more than once, got {text!r}")
        return values

    return parse


MAX_VOLTAGES = 8
"""Most voltages one ``lusm characteristic --voltage A,B,...`` call takes."""


def add_drive_options(p: argparse.ArgumentParser, *, required: bool = True,
                      auto_frequency: bool = True, time_steps: bool = True,
                      voltage_list: bool = False, settling_duration: bool = False) -> None:
    """``--voltage --preload --frequency`` and (with ``time_steps``) ``--duration --dt``,
    with their validity ranges; ``voltage_list``: ``--voltage`` takes ``A,B,...`` (a tuple);
    ``settling_duration``: ``--duration`` defaults to None, the stator's settling time
    (:func:`default_duration_s`), instead of the paper's 0.05 s."""
    g = p.add_argument_group("drive", "operating point and time stepping")
    if required:
        vtype = (real_list("--voltage", "V", *limits.VOLTAGE_V, MAX_VOLTAGES) if voltage_list
                 else real("--voltage", "V", *limits.VOLTAGE_V))
        g.add_argument("--voltage", type=vtype, required=True,
                       metavar="V[,V...]" if voltage_list else None,
                       help=f"drive amplitude V0 (V), in [0, {limits.VOLTAGE_V[1]:g}]"
                       + (f"; up to {MAX_VOLTAGES} comma-separated values, one curve each"
                          if voltage_list else ""))
        g.add_argument("--preload", type=real("--preload", "N", *limits.PRELOAD_N),
                       required=True, help=f"preload F_P (N), in [0, {limits.PRELOAD_N[1]:g}]")
    if auto_frequency:
        g.add_argument("--frequency", default=None,
                       help="drive frequency (Hz), or 'auto' for the set's own operating point; "
                       "default: the paper's 40 kHz for Table 2's set, auto for any other "
                       "(docs/designer.md)")
    else:
        g.add_argument("--frequency", type=real("--frequency", "Hz", *limits.FREQUENCY_HZ),
                       default=40e3, help="drive frequency (Hz)")
    if not time_steps:
        return
    g.add_argument("--duration", default=None if settling_duration else PAPER_DURATION_S,
                   type=real("--duration", "s", *limits.DURATION_S, lo_open=True),
                   help="simulated time (s)" + (
                       f"; default: Table 2's set {PAPER_DURATION_S:g} s, any other set its "
                       "own settling time (five time constants of its modes and its slider, "
                       f"at least {PAPER_DURATION_S:g} s, docs/designer.md)"
                       if settling_duration else f", default {PAPER_DURATION_S:g}"))
    # kept as typed and checked by time_step_of once the drive frequency is known: its range
    # (0, 1/(20 f)] depends on it; a parse-time range of its own, (0, 0.001] s, would accept
    # a --dt that the drive frequency then refuses
    g.add_argument("--dt", default=None, type=_dt_form,
                   help="time step (s), in (0, 1/(20 f)] at the drive frequency f; default "
                        "1e-7 s, or just below it so that a drive period is a whole number of "
                        "steps")


def _dt_form(text: str) -> str:
    """``--dt`` as typed, once it is a positive finite number: a form that is no step at any
    frequency is refused while the options are read, before a stator file's FE reduction
    (``--frequency auto``) that its range waits for; the range is the one
    :func:`time_step_of` then checks, without the frequency's figure."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0.0 < value < math.inf:
        raise argparse.ArgumentTypeError(
            f"--dt must be a number in (0, 1/(20 f)] s at the drive frequency f, got {text!r}")
    return text


def parse_frequency(text: str | float, params=None) -> float:
    """A drive frequency in Hz from ``--frequency`` (a number, or 'auto' with ``params``)."""
    if isinstance(text, str) and text.strip().lower() == "auto" and params is not None:
        from contact.drive import auto_frequency

        try:
            return float(auto_frequency(params))
        except ValueError as exc:  # a set that drives no tip ellipse has no operating point
            raise LusmError(f"--frequency auto: {exc}", "--frequency") from None
    lo, hi = limits.FREQUENCY_HZ
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not (math.isfinite(value) and lo <= value <= hi):
        raise LusmError(f"--frequency must be a number in [{lo:g}, {hi:g}] Hz or 'auto', "
                        f"got {text!r}", "--frequency")
    return value


def known_frequency(text: str | float | None) -> float | None:
    """``--frequency`` in Hz before the parameter set is known: None for 'auto' and for no
    ``--frequency`` (both need the set: :func:`default_frequency_text`), else the number, a
    bad one refused at once (before any work)."""
    if text is None or isinstance(text, str) and text.strip().lower() == "auto":
        return None
    return parse_frequency(text)


def warn_drive(voltage_V: float | None, preload_N: float | None, *,
               voltage_option: str = "--voltage", preload_option: str = "--preload",
               load_N: float = 0.0) -> None:
    """Warn (stderr) for operating points outside the range where Table 2 was measured; the
    options are named as the command spells them (``--voltages`` for a map). With a load
    (N) the slider is pushed even without drive or contact: nothing is said of that."""
    if voltage_V == 0 and preload_N == 0 and not load_N:
        warn(f"{voltage_option} 0 and {preload_option} 0: no drive and no contact force, "
             "nothing moves (motion class 'separated')")
    if voltage_V is not None and voltage_V > limits.VOLTAGE_WARN_V:
        warn(f"{voltage_option} {voltage_V:g} V is above {limits.VOLTAGE_WARN_V:g} V: the "
             "linear piezoelectric model and the contact constants were not validated there")
    if preload_N is not None and preload_N > limits.PRELOAD_WARN_N:
        warn(f"{preload_option} {preload_N:g} N is above {limits.PRELOAD_WARN_N:g} N: the "
             "contact stiffness and friction constants were not validated there")


DEFAULT_DT_S = 1e-7
"""The transients' default time step (s): 250 steps per period at 40 kHz; the library's
``contact.options.DEFAULT_DT_S``, written out so that parsing imports no kernel module."""


def time_step_s(dt_s: float | None, frequency_Hz: float) -> float:
    """``--dt`` as typed (s), or by default :func:`contact.options.default_time_step_s`: the
    largest step up to 1e-7 s that makes the drive period a whole number of steps, at least
    20 (40 kHz: 250 steps of 1e-7 s)."""
    if dt_s is not None:
        return float(dt_s)
    from contact.options import default_time_step_s

    return default_time_step_s(frequency_Hz)


def check_steps(duration_s: float, dt_s: float) -> float:
    """Time steps of one run of ``duration_s`` at ``dt_s`` (a float: inf or 1e300 are
    compared, never allocated); refused above :data:`lusm.limits.MAX_STEPS`."""
    steps = duration_s / dt_s
    top = limits.work_bound(limits.MAX_STEPS)
    if not steps <= top:
        # a denormal --dt gives inf: "is inf time steps" read oddly
        count = f"{steps:.3g}" if math.isfinite(steps) else "more than 1e308"
        raise LusmError(f"--duration {duration_s:g} s / --dt {dt_s:g} s is {count} time "
                        f"steps, above the limit {top:.3g}; raise --dt or shorten --duration "
                        f"({limits.more_work_hint()})", "--dt")
    return steps


def time_step_of(text: str | None, frequency_Hz: float, why: str = "", *,
                 used: bool = True) -> float:
    """The time step (s) of ``--dt`` typed as ``text``, checked at the drive frequency in
    force, or by default :func:`time_step_s`.

    Parameters
    ----------
    text : str or None
        ``--dt`` as typed (None: not given).
    frequency_Hz : float
        The drive frequency in force (Hz), which sets the range (0, 1/(20 f)] s.
    why : str
        A clause saying what the step serves, for a command where that is not obvious.
    used : bool
        False where the step has no effect (``simulate --steady``, said by a warning): a
        positive number is then all that is required, refused with the same range.

    Raises
    ------
    LusmError
        Naming ``--dt``, the range at ``frequency_Hz`` and the text typed.
    """
    if text is None:
        return time_step_s(None, frequency_Hz)
    try:
        value = float(text)
    except (TypeError, ValueError):
        value = math.nan  # refused below, with the range the number would have to be in
    if not (0.0 < value < math.inf) or (used and value > _dt_max(frequency_Hz)):
        raise LusmError(_dt_refusal(frequency_Hz, repr(text), why), "--dt")
    return value


def _dt_max(frequency_Hz: float) -> float:
    """The largest step (s) :func:`check_dt_per_period` takes: 1/(20 f), to roundoff."""
    return 1.0 / (20.0 * frequency_Hz) * (1 + 1e-12)


def _dt_refusal(frequency_Hz: float, got: str, why: str) -> str:
    shown = _dt_shown(frequency_Hz)
    return (f"--dt must be in (0, 1/(20 f)] = (0, {shown:g}] s at --frequency "
            f"{frequency_Hz:g} Hz, got {got}{why}")


def _dt_shown(frequency_Hz: float, digits: int = 4) -> float:
    """The bound 1/(20 f) as said in a refusal: ``digits`` significant digits, one unit of
    the last digit lower only where the rounded figure is a step the check refuses.

    Rounding to nearest keeps round bounds round (1e-06 s at 50 kHz: always rounding down,
    from the float's binary value just below 1e-06, would say 9.999e-07); the step down keeps
    the figure a step that is taken (1/(20 f) at 30 kHz, 1.6667e-06 s, not 1.667e-06, which
    is above it and refused).
    """
    from decimal import Decimal

    exact = 1.0 / (20.0 * frequency_Hz)
    shown = Decimal(f"{exact:.{digits}g}")
    if float(shown) > _dt_max(frequency_Hz):
        # a unit of the last digit of the bound itself: rounding up to 1e-06 at 50001 Hz
        # moves the exponent, and a step down from it would say 9.99e-07 (three digits)
        shown -= Decimal(1).scaleb(Decimal(exact).adjusted() - digits + 1)
    return float(shown)


def check_dt_per_period(dt_s: float, frequency_Hz: float, why: str = "") -> None:
    """Refuse a ``--dt`` above 1/(20 f): fewer than 20 steps per drive period (``why``: a
    clause saying what the step serves, for a command where that is not obvious)."""
    if not 0.0 < dt_s <= _dt_max(frequency_Hz):
        raise LusmError(_dt_refusal(frequency_Hz, f"{dt_s:g}", why), "--dt")


PAPER_DURATION_S = 0.05
"""Default ``--duration`` (s) of Table 2's set and of ``lusm map``'s transients
(:data:`contact.drive.PAPER_DURATION_S`)."""


def default_duration_s(params, voltages_V: Sequence[float], preload_N: float,
                       frequency_Hz: float, dt_s: float, load_N: float = 0.0) -> float:
    """``lusm simulate``'s run length without ``--duration`` (s):
    :func:`contact.drive.default_duration_s` of ``voltages_V``, at most the steps the work
    bound allows (said in one line when it cuts the run, with ``--steady`` suggested)."""
    from contact.drive import default_duration_s as settle_duration

    top = limits.work_bound(limits.MAX_STEPS) * dt_s
    duration, settle = settle_duration(
        params, [(v, preload_N, frequency_Hz) for v in voltages_V], top, load_N)
    if settle > duration:
        warn(f"--duration: the slider settles in about {settle:.3g} s, {settle / dt_s:.3g} "
             f"time steps, above the limit {limits.work_bound(limits.MAX_STEPS):.3g}; running "
             f"{top:.3g} s, which may not settle: --steady finds the steady state directly "
             f"({limits.more_work_hint()})")
    return duration


def check_run_size(duration_s: float, dt_s: float, frequency_Hz: float,
                   runs: int = 1) -> int:
    """Steps of one run; refuse runs beyond the work bounds before anything is allocated.

    Raises
    ------
    LusmError
        ``--dt`` above 1/(20 f), ``--duration`` below 10 periods, or more steps than
        :data:`lusm.limits.MAX_STEPS` (per run), :data:`~lusm.limits.MAX_MAP_STEPS`
        (all runs) or a full-resolution window above :data:`~lusm.limits.MAX_WINDOW_STEPS`.
    """
    check_dt_per_period(dt_s, frequency_Hz)
    periods = duration_s * frequency_Hz
    if periods < 10 * (1 - 1e-12):
        raise LusmError(f"--duration must be >= 10 drive periods = {10 / frequency_Hz:.4g} s "
                        f"at --frequency {frequency_Hz:g} Hz, got {duration_s!r} s",  # as typed
                        "--duration")
    steps = check_steps(duration_s, dt_s)
    window = min(steps, 5.0 / (frequency_Hz * dt_s))  # the last 5 periods, every step
    wtop = limits.work_bound(limits.MAX_WINDOW_STEPS)
    if window > wtop:
        raise LusmError(f"--dt {dt_s:g} s stores {window:.3g} steps of the last periods at full "
                        f"resolution, above the limit {wtop:.3g}; raise --dt "
                        f"({limits.more_work_hint()})", "--dt")
    total = steps * runs
    mtop = limits.work_bound(limits.MAX_MAP_STEPS)
    if runs > 1 and total > mtop:
        raise LusmError(f"{runs} grid points x {steps:.3g} steps = {total:.3g} time steps, above "
                        f"the limit {mtop:.3g}; use fewer --voltages/--preloads points, a "
                        f"shorter --duration or a larger --dt ({limits.more_work_hint()})",
                        "--voltages")
    return int(round(steps))


# --- output -----------------------------------------------------------------------------------

def add_output_options(p: argparse.ArgumentParser, *, folder: str | None = "--plot",
                       folder_help: str = "write the figures (PNG) into DIR",
                       default: str | None = None, json_flag: bool = True) -> None:
    """``--json``, an output folder option (``--plot DIR`` or ``--out DIR``) and ``--force``."""
    g = p.add_argument_group("output")
    if json_flag:
        g.add_argument("--json", action="store_true", help="print one JSON object")
    if folder is not None:
        g.add_argument(folder, default=default, metavar="DIR", help=folder_help)
        g.add_argument("--force", action="store_true",
                       help="write into a non-empty folder lusm did not write (files in the "
                       "way are kept as NAME.bak-N; nothing is deleted)")


def folder_arg(value: str | None, option: str) -> Path | None:
    """The output folder of ``option``; refuse an empty name."""
    if value is None:
        return None
    if not str(value).strip():
        raise LusmError(f"{option} must name a folder, got ''", option)
    return Path(value)


def output_folder(args: argparse.Namespace, option: str) -> Path | None:
    """The folder the user gave with ``option`` (``--out``, ``--plot``), checked before any
    work by :func:`check_output_folder`; None when the option was not given."""
    target = folder_arg(getattr(args, option[2:].replace("-", "_")), option)
    if target is not None:
        check_output_folder(target, option, bool(getattr(args, "force", False)),
                            getattr(args, "command", None))
    return target


def check_output_folder(target: Path, option: str, force: bool = False,
                        command: str | None = None) -> None:
    """Refuse, before any work, an output folder the set could not be moved into or written.

    :func:`lusm.output_set.check_target` (a file, below a file, a non-empty folder lusm
    did not write, a folder of another command than ``command``) plus: the nearest existing
    folder must be writable.
    """
    import os

    from lusm.output_set import OutputError, check_target, check_writable

    check_path_usable(target, option)
    try:
        check_target(target, option, force, command)
    except OutputError as exc:
        raise LusmError(str(exc), option) from None
    existing = next((p for p in [target, *target.parents] if p.exists()), Path.cwd())
    if not os.access(existing, os.W_OK | os.X_OK):
        raise LusmError(f"{option} {target}: the folder {existing} is not writable", option)
    try:  # where the set is staged, by trying it
        check_writable(target, option)
    except OutputError as exc:
        raise LusmError(str(exc), option) from None


def check_path_usable(path: Path, option: str) -> None:
    """Refuse a path the system cannot look up, naming ``option``: a name too long, a loop of
    symbolic links, a folder on the way that cannot be searched (``render --out`` with a
    300-letter name said "cannot use aaa...: File name too long", a link loop "cannot write
    (File exists)"). A path that does not exist yet, or below a file, is the caller's to
    judge."""
    import os

    try:
        os.stat(path)
    except (FileNotFoundError, NotADirectoryError):
        return
    except OSError as exc:
        raise LusmError(f"{option} {path}: {exc.strerror or exc}", option) from None


@contextmanager
def figure_set(target: Path, option: str, force: bool = False,
               command: str | None = None) -> Iterator[Path]:
    """:func:`lusm.output_set.output_set` with its failures as :class:`LusmError`."""
    from lusm.output_set import OutputError, output_set

    try:
        with output_set(target, option, force, command) as stage:
            yield stage
    except OutputError as exc:
        raise LusmError(str(exc), option) from None
    except OSError as exc:  # a full disk, a folder made read-only meanwhile
        raise LusmError(f"{option} {target}: cannot write ({exc.strerror or exc})",
                        option) from None


def write_figures(args: argparse.Namespace, option: str,
                  draw: Callable[[Path], Sequence[str | Path]]) -> list[str]:
    """Draw a figure set into a staging folder (``draw(stage)`` returns the files it wrote)
    and move it into the folder of ``option`` complete (:func:`figure_set`, with ``--force``
    and the command of ``args``); returns the files' paths in that folder."""
    target = folder_arg(getattr(args, option[2:].replace("-", "_")), option)
    with figure_set(target, option, args.force, args.command) as stage:
        return moved(draw(stage), stage, target)


def file_target(text: str, option: str, force: bool, example: str) -> Path:
    """The file ``option`` names, checked before any work: a name (not a folder, ``example``
    says what to name instead), not below a file, not an existing file without ``force``,
    in a folder that can be written."""
    import os

    if not text.strip():
        raise LusmError(f"{option} must name a file, got ''", option)
    path = Path(text)
    check_path_usable(path, option)
    # a trailing separator names a folder (Path drops it: dd.vtu/ would be written as the
    # file dd.vtu)
    last = text.rstrip().replace(os.sep, "/").rsplit("/", 1)[-1]
    if path.is_dir() or last in ("", ".", ".."):  # dd.vtu/. too
        raise LusmError(f"{option} {text.strip()} is a folder; name a file such as {example}",
                        option)
    for parent in path.parents:
        if parent.exists() and not parent.is_dir():
            raise LusmError(f"{option} {path} sits below the file {parent}", option)
        if parent.exists():
            break
    if (path.exists() or path.is_symlink()) and not force:
        raise LusmError(f"{option} {path} already exists; choose a new name or pass --force",
                        option)
    folder = next((p for p in path.absolute().parents if p.exists()), None)
    if folder is not None and not os.access(folder, os.W_OK | os.X_OK):
        raise LusmError(f"{option} {path}: cannot write into {folder} (permission denied)",
                        option)
    return path


def write_text_file(path: Path, option: str, text: str) -> None:
    """Write ``text`` to ``path`` (checked by :func:`file_target`): built in a staging folder
    beside it and moved in whole; a file already there (``--force``) is kept as
    ``NAME.bak-N``, never lost."""
    import os

    from lusm.interrupts import checkpoint
    from lusm.output_set import OutputError, keep_aside, staging

    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with staging(path.parent, path.name, option, path) as stage:
            staged = stage / path.name
            staged.write_text(text, encoding="utf-8")
            checkpoint()  # a Ctrl-C / SIGTERM that Python swallowed: nothing is moved in
            if path.exists() or path.is_symlink():
                keep_aside(path, "--force")
            os.replace(staged, path)
    except OutputError as exc:
        raise LusmError(str(exc), option) from None
    except OSError as exc:  # a full disk, a folder made read-only meanwhile
        raise LusmError(f"{option} {path}: cannot write ({exc.strerror or exc})",
                        option) from None


def moved(paths, stage: Path, target: Path) -> list[str]:
    """Where files written into ``stage`` live once the set is moved into ``target``."""
    return [str(target / Path(p).relative_to(stage)) for p in paths]


def print_json(obj: Any, indent: int | None = None) -> None:
    """Print ``obj`` as valid JSON: NaN and infinities become ``null``."""
    from validation.summaries import json_text

    print(json_text(obj, indent))


# --- messages ---------------------------------------------------------------------------------


def warn_unexcited_mode(params, electrodes) -> None:
    """Warn when the drive's force factor of one mode is roundoff beside the other's
    (:func:`validation.summaries.unexcited_modes`)."""
    from validation.summaries import unexcited_modes

    for text in unexcited_modes(params, electrodes):
        warn(text)


