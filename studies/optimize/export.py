"""The best design as a stator file (``lusm optimize --write``)."""

from __future__ import annotations

from typing import Any

from studies.optimize.problem import Problem

STATOR_KEYS = {"length": ("plate", "length_mm"), "width": ("plate", "width_mm"),
               "thickness": ("plate", "thickness_mm"), "gap": ("electrodes", "gap_mm"),
               "tip_length": ("tip", "length_mm"), "tip_width": ("tip", "width_mm"),
               "chamfer": ("chamfers", "size_mm")}
"""Where each design variable lives in a stator file (table, key in mm)."""


def best_stator_text(problem: Problem, design: dict[str, Any], comment: str) -> str:
    """A stator file (TOML) of ``design``: the study's stator file with the design's values
    set (its comments and layout kept, each changed key saying its former value), or a plain
    plate with the study's other axis values. ``comment`` goes at the top."""
    import tomlkit

    study = problem.study
    if study.stator is not None:
        doc = tomlkit.parse(study.stator.path.read_text(encoding="utf-8"))
    else:
        doc = tomlkit.document()
        doc["name"] = "optimised plate"
        ax = study.axes
        doc["plate"] = {"length_mm": ax["length"][0] * 1e3, "width_mm": ax["width"][0] * 1e3,
                        "thickness_mm": ax["thickness"][0] * 1e3}
        doc["electrodes"] = {"gap_mm": ax["gap"][0] * 1e3, "drive": [1, 4]}
        doc["material"] = {"name": ax["material"][0]}
    for name, value in design.items():
        if name == "material":
            table, key, new = "material", "name", value
        elif name in STATOR_KEYS:
            (table, key), new = STATOR_KEYS[name], float(f"{value * 1e3:.12g}")
        else:  # the drive frequency is no stator's: said in the comment
            continue
        if table not in doc:
            doc[table] = tomlkit.table()
        old = doc[table].get(key)
        item = tomlkit.item(new)
        if study.stator is not None and old is not None and old != new:
            item.comment(f"optimised (was {old})")
        doc[table][key] = item
    head = "".join(f"# {line}\n" if line else "#\n" for line in comment.splitlines())
    return head + "\n" + tomlkit.dumps(doc)
