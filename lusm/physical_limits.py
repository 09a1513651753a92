"""The physical limits of an operating point in the commands' terms: one warning line before
the results, a ``limits`` object in the JSON, a table in the text
(:mod:`contact.operating_limits`)."""

from __future__ import annotations

from lusm.messages import warn


def warn_beyond(limits, where: str = "") -> None:
    """Say, in one line, every quantity of ``limits`` beyond the ceramic's limit (nothing
    when all are within, or when ``limits`` is None: a set without shape data)."""
    line = None if limits is None else limits.warning(where)
    if line is not None:
        warn(line)


def limits_json(limits) -> dict | None:
    """``{quantity: {value, limit, ratio, unit}, basis}`` (SI), or None."""
    return None if limits is None else limits.to_dict()


def print_limits(doc: dict | None) -> None:
    """A :func:`limits_json` object as ``limit <quantity>  <value> (limit <limit>, ratio
    <r>)`` lines, in the printed units of :data:`contact.operating_limits.QUANTITIES`; the
    stress line also says what it is and gives the peaks' sum where that differs."""
    from contact.operating_limits import QUANTITIES

    if not doc:
        return
    for q, (_, _, factor, unit) in QUANTITIES.items():
        d = doc[q]
        limit = d["limit"]
        bound = (f"limit {limit * factor:.3g} {unit}, ratio {d['ratio']:.3g}"
                 if limit == limit else "no limit of its own")  # NaN: the dampers' total
        what = ""
        if "sum_of_peaks" in d:
            what = (f"; {d['basis']}, the peaks' sum {d['sum_of_peaks'] * factor:.4g} {unit}"
                    if d["sum_of_peaks"] != d["value"] else f"; {d['basis']}")
        print(f"{'limit ' + q.replace('_', ' '):<30} {d['value'] * factor:.4g} {unit} "
              f"({bound}; {doc['basis']}{what})")
