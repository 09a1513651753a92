"""FE failures and refused plates as the user's bad input: one line naming the options (or
the stator file) that chose the plate, and why no L1/B2 pair exists there."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager

from lusm import limits
from lusm.errors import LusmError, short_reason
from lusm.messages import typed


def slender_reason(exc) -> str:
    """Why a :class:`fem.modes.SlenderPlateError`'s plate has no L1/B2 pair, in mm."""
    return (f"the {exc.length_m * 1e3:g} x {exc.width_m * 1e3:g} mm plate is "
            f"{exc.length_m / exc.width_m:.4g} times longer than wide: free-free beam theory "
            f"puts its B2 near 1/{exc.f_ratio:.3g} of L1's frequency, with {exc.nearer} "
            f"in-plane modes nearer L1 than B2, beyond the {exc.searched} the FE solver "
            "searches near L1, so no L1/B2 pair can be found (an L1/B2 motor needs the two "
            "close, the paper's 30 x 7.5 mm plate has them about 1 % apart)")


def slender_plate_error(exc) -> LusmError:
    """A :class:`fem.modes.SlenderPlateError` in the options' terms: the plate options typed
    (or the stator file) with their values, beam theory's reason and the slenderness that
    fits, on one line."""
    if typed("--geometry"):
        named, option = "--geometry: ", "--geometry"
        fix = "the stator file's [plate] length_mm or width_mm"
    else:
        dims = [o for o in ("--length-mm", "--width-mm") if typed(o)] or ["--length-mm"]
        values = {"--length-mm": exc.length_m, "--width-mm": exc.width_m}
        named = " and ".join(f"{o} {values[o] * 1e3:g}" for o in dims) + ": "
        option, fix = dims[0], "--length-mm or --width-mm"
    return LusmError(f"{named}{slender_reason(exc)}; give {fix} for a length at most about "
                     f"{exc.max_slenderness:.0f} times the width", option)


def plate_refusal(exc) -> LusmError:
    """A plate refused before its solve (:class:`fem.modes.SlenderPlateError` or
    :class:`fem.modes.WidePlateError`, by :func:`fem.modes.check_b2_in_reach`) in the
    options' terms, on one line."""
    from fem.modes import SlenderPlateError

    return slender_plate_error(exc) if isinstance(exc, SlenderPlateError) \
        else wide_plate_error(exc)


def wide_plate_error(exc) -> LusmError:
    """A :class:`fem.modes.WidePlateError` in the options' terms: the options typed (or the
    stator file), the reason, on one line."""
    if typed("--geometry"):
        # the length is the overall one, a protruding tip included
        return LusmError(f"--geometry: {exc} (its length the plate's and a protruding "
                         "tip's); make the stator file's [plate] width_mm smaller than that",
                         "--geometry")
    dims = [o for o in ("--width-mm", "--length-mm") if typed(o)] or ["--width-mm"]
    values = {"--length-mm": exc.length_m, "--width-mm": exc.width_m}
    named = " and ".join(f"{o} {values[o] * 1e3:g}" for o in dims)
    fix = {"--width-mm": "give a --width-mm below the length",
           "--length-mm": "give a --length-mm above the width"}[dims[0]]
    return LusmError(f"{named}: {exc}; {fix} (a width about a quarter of the length for an "
                     "L1/B2 pair)", dims[0])


def is_fe_failure(exc: BaseException) -> bool:
    """A solver failure an extreme stator can cause (not a bug): the mode solver's or SuperLU's
    ``RuntimeError``, or scikit-fem's point search giving up (a bare ``Exception``)."""
    return isinstance(exc, RuntimeError) or (
        type(exc) is Exception and "Newton iteration didn't converge" in str(exc))


def _slender_clause(stator) -> str | None:
    """Why a slender plate's solve may have missed B2, or None: beam theory's count of the
    modes nearer L1 than B2 (:func:`fem.modes.modes_nearer_than_b2`) within one of the most
    the solver searches (the count is the FE spectrum's or one low; a plate beyond the bound is
    refused before its solve, :func:`fem.modes.check_b2_in_reach`). ``stator``: anything with
    ``length_m`` and ``width_m``, or None.

    Not a fixed length / width (such as 17): plates of 30 to 300 x 1 mm solve and give
    their pair, and one of them failing for another reason is not told that its B2 lies
    beyond the modes solved."""
    from fem.beam_shapes import bending_over_rod_frequency
    from fem.meshing.meshed_stator import overall_length_m
    from fem.modes import N_MODES, SEARCH_GROWTH, modes_nearer_than_b2

    width = getattr(stator, "width_m", None)
    if not (getattr(stator, "length_m", None) and width):
        return None
    length = overall_length_m(stator)
    if length <= width:  # not a beam along its length: the generic message says why
        return None
    searched = SEARCH_GROWTH[-1] * N_MODES
    nearer = modes_nearer_than_b2(length / width)
    if nearer < searched - 1:
        return None
    ratio = 1.0 / bending_over_rod_frequency(2, length / width)
    return (f"a {length * 1e3:g} x {width * 1e3:g} mm plate is {length / width:.4g} times "
            f"longer than wide, and free-free beam theory puts its B2 near 1/{ratio:.3g} of "
            f"L1's frequency, with about {nearer} in-plane modes nearer L1 than B2, at the "
            f"edge of the {searched} modes the solver searches near L1: an L1/B2 motor needs "
            "the two close (the paper's 30 x 7.5 mm plate has them about 1 % apart), a width "
            "of about a quarter of the length")


def _thick_clause(stator) -> str | None:
    """Why a thick plate may have no L1/B2 pair, or None: thickness over the smaller in-plane
    dimension beyond :data:`lusm.limits.MEASURED_THICK_RATIO`, the largest at which the
    2D model was measured against 3D (below it, 0.6 % off at most: a failure there has another
    cause, and the thin-plate warning has said the rest). ``stator``: anything with
    ``length_m``, ``width_m`` and ``thickness_m``, or None."""
    dims = [getattr(stator, k, None) for k in ("length_m", "width_m", "thickness_m")]
    if not all(dims):
        return None
    inplane, thickness = min(dims[0], dims[1]), dims[2]
    if thickness / inplane <= limits.MEASURED_THICK_RATIO:
        return None
    return (f"a {thickness * 1e3:g} mm thick plate is {thickness / inplane:.3g} x its smaller "
            f"in-plane dimension ({inplane * 1e3:g} mm), beyond the thin plate "
            f"(below {limits.PLANE_STRESS_RATIO:g} x) whose in-plane L1 and B2 the 2D model "
            "identifies")


def fe_failure(exc: Exception, stator=None) -> ValueError:
    """A mode-solver or sparse-solver failure on an extreme plate, as bad input (``stator``,
    when given, lets a slender plate's message say why B2 is missing)."""
    from fem.modes import ModeIdentificationError, SlenderPlateError, WidePlateError

    if isinstance(exc, SlenderPlateError | WidePlateError):  # refused before its solve
        return plate_refusal(exc)
    reason = short_reason(exc)
    unidentified = isinstance(exc, ModeIdentificationError)
    # identification and pairing test the modes' shapes, which no --refine changes: the
    # plate is named, not the mesh
    slender = _slender_clause(stator)
    if slender and unidentified:
        # a 1000 x 1 mm plate: too slender, not "wider than about half its length"
        return ValueError(f"L1 and B2 were not found for this stator ({reason}): {slender}; "
                          "check the plate (--geometry or --length-mm, --width-mm)")
    thick = _thick_clause(stator)
    if thick and unidentified:
        # a 30 x 7.5 x 39 mm plate: its thickness is named too
        return ValueError(f"L1 and B2 were not found for this stator ({reason}): {thick}; "
                          "check the plate (--geometry or --thickness-mm, --length-mm, "
                          "--width-mm)")
    if unidentified:
        return ValueError(
            f"L1 and B2 were not found for this stator ({reason}): they are identified as the "
            "free-free beam modes of Eq. 3, which a plate wider than about half its length "
            "(30 x 16 mm is the widest paper-length plate that passes) or with a large "
            "feature does not have, and which a feature off the centre line (a hole, a tip) "
            "mixes into one another where their frequencies cross; check the plate "
            "(--geometry or --length-mm, --width-mm), or keep such features symmetric")
    return ValueError(f"the FE solve failed for this stator ({reason}); check the "
                      "plate (--geometry or --length-mm, --width-mm, --thickness-mm, --gap-mm) "
                      "and --refine")


@contextmanager
def fe_failures_as_input(stator=None) -> Iterator[None]:
    """Inside it, a mode-solver or sparse-solver failure is raised as :func:`fe_failure` (bad
    input, one line); any other exception passes unchanged."""
    from fem.modes import ModeSolverError

    try:
        yield
    except Exception as exc:
        if isinstance(exc, ModeSolverError) or is_fe_failure(exc):
            raise fe_failure(exc, stator) from exc
        raise
