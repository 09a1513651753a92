"""The 3D check of the best design: its L1 and B2 from the 3D model beside the 2D ones."""

from __future__ import annotations


def check_3d(problem, ds, row: int) -> dict[str, float]:
    """L1 and B2 (short circuit, Hz) and their split of the design in row ``row`` of the
    result dataset ``ds``, from the default 3D model (:func:`fem.solid3d.model.solid_model`,
    as ``lusm modes --model 3d``) and from the 2D model of the search."""
    from fem.solid3d.model import modes_of_solid_model, solid_model
    from studies.optimize.problem import trial_study
    from studies.optimize.result import row_design
    from studies.task import geometry_of, plate_of

    design = row_design(problem, ds, row)
    study = trial_study(problem, design)
    stator, material = plate_of(study, geometry_of(study, 0))
    modes = modes_of_solid_model(solid_model(stator, material))
    l1, b2 = float(modes.L1.f_short_Hz), float(modes.B2.f_short_Hz)
    l1_2d, split_2d = float(ds["f_L1_short"].values[row]), float(ds["split"].values[row])
    return {"f_L1_3d_Hz": l1, "f_B2_3d_Hz": b2, "split_3d_Hz": b2 - l1,
            "f_L1_2d_Hz": l1_2d, "f_B2_2d_Hz": l1_2d + split_2d, "split_2d_Hz": split_2d}
