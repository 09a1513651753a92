"""Bad input across every ``lusm`` command: one line naming the option, exit 2, no work done.

A table of named bad inputs (issue 12), each run in-process through ``lusm.cli.main``;
the stator files and meshes they need are written into ``tmp_path``. Every case is refused
before any FE solve or time integration starts (the work bounds of ``lusm.limits``), so
the table runs in seconds.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from bounds import ParameterError
from contact.errors import ChatteringError
from lusm.cli import main
from tests.conftest import ROOT

PLATE = "[plate]\nlength_mm = 30\nwidth_mm = 7.5\nthickness_mm = 3\n"
MESHED = '[plate]\nthickness_mm = 3\n[mesh]\nfile = "{mesh}"\n'


def _plate_mesh():
    from fem.geometry import PlateStator
    from fem.meshing.mesh import structured_mesh

    m = structured_mesh(PlateStator(), 2)
    return m.points_m.T.copy(), m.quads.T.copy(), m.electrode.copy()


def _msh(folder: Path, name: str, pts, quads, tags) -> str:
    from fem.meshing.mesh_io import write_stator_msh

    write_stator_msh(folder / name, pts, {"quad": quads}, {"quad": tags})
    return name


def _meshes(folder: Path) -> dict[str, str]:
    """Bad planform meshes, each a defect issue 12 names; returns name -> stator file."""
    pts, quads, tags = _plate_mesh()
    files: dict[str, tuple] = {}
    files["duplicated"] = (pts, np.vstack((quads, quads[5])), np.append(tags, tags[5]))
    folded = pts.copy()
    inner = int(np.argmin(np.hypot(pts[:, 0] - 0.0, pts[:, 1] - 0.015)))
    folded[inner, 1] += 0.02  # drag one inner node over its neighbours: cells fold over
    files["folded"] = (folded, quads, tags)
    y = pts[quads].mean(axis=1)[:, 1]
    keep = (y < 0.012) | (y > 0.018)  # drop a band of cells: two separate parts
    files["disconnected"] = (pts, quads[keep], tags[keep])
    # a cell folded back over cell 4: it shares cell 4's first edge and lies inside it
    a, b, c, d = quads[4]
    inner2 = pts[[c, d]] * 0.5 + pts[[b, a]] * 0.5
    files["overlap"] = (np.vstack((pts, inner2)),
                        np.vstack((quads, [a, b, len(pts), len(pts) + 1])),
                        np.append(tags, tags[4]))
    # a cell hung on one node of cell 4 and laid across its neighbours
    c4 = pts[quads[4]].mean(axis=0)
    loose = c4 + np.array([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]) * 2.5e-3
    files["overlap_vertex"] = (np.vstack((pts, loose)),
                               np.vstack((quads, [quads[4, 2], *range(len(pts), len(pts) + 3)])),
                               np.append(tags, tags[4]))
    # cell 13 split in two through the middle of its first and third edges: the neighbours
    # across those edges see a hanging node
    a, b, c, d = quads[13]
    mids = np.vstack(((pts[a] + pts[b]) / 2, (pts[c] + pts[d]) / 2))
    m1, m2 = len(pts), len(pts) + 1
    hung = np.vstack((np.delete(quads, 13, axis=0), [a, m1, m2, d], [m1, b, c, m2]))
    files["hanging_node"] = (np.vstack((pts, mids)), hung,
                             np.concatenate((np.delete(tags, 13), [tags[13]] * 2)))
    # the cells above y = 15.25 mm, x < 0 on their own copies of the nodes there: an unmerged
    # seam (a crack), which was accepted and moved L1 by 11 %
    on = np.flatnonzero((np.abs(pts[:, 1] - 15.25e-3) < 1e-12) & (pts[:, 0] < 0))
    above = pts[quads].mean(axis=1)[:, 1] > 15.25e-3
    copy = np.arange(len(pts))
    copy[on] = len(pts) + np.arange(on.size)
    seam = np.where(above[:, None], copy[quads], quads)
    files["seam"] = (np.vstack((pts, pts[on])), seam, tags)
    # electrodes 2 and 3 made gap: one electrode on each side of both centre lines passed the
    # reader, and the model failed with "mesh has no elements under electrode(s) [2, 3]"
    files["only14"] = (pts, quads, np.where(np.isin(tags, (2, 3)), 0, tags))
    bow = quads.copy()
    bow[7] = bow[7, [0, 2, 1, 3]]  # a bow-tie quad
    files["bowtie"] = (pts, bow, tags)
    files["metre_as_mm"] = (pts, quads, tags)
    files["ten_metres"] = (pts * 1e3 / 3, quads, tags)  # a 10 m plate in metres
    out = {}
    for name, (p, q, t) in files.items():
        mesh = _msh(folder, f"{name}.msh", p, q, t)
        text = MESHED.format(mesh=mesh) + ('unit = "mm"\n' if name == "metre_as_mm" else "")
        (folder / f"{name}.toml").write_text(text)
        out[name] = str(folder / f"{name}.toml")
    good = _msh(folder, "good.msh", pts, quads, tags)
    (folder / "tip_far.toml").write_text(MESHED.format(mesh=good)
                                         + "[points]\ntip_mm = [0, 1e300]\n")
    out["tip_far_mesh"] = str(folder / "tip_far.toml")
    # the mesh's own 'tip' vertex on a node no cell uses: named as "[points] tip_mm" in a
    # file without [points]
    from fem.meshing.mesh_io import write_stator_msh

    write_stator_msh(folder / "tip_vertex_far.msh", np.vstack((pts, [[0.0, 0.04]])),
                     {"quad": quads}, {"quad": tags}, {"tip": len(pts)})
    (folder / "tip_vertex_far.toml").write_text(MESHED.format(mesh="tip_vertex_far.msh"))
    out["tip_vertex_far"] = str(folder / "tip_vertex_far.toml")
    (folder / "meshed_ok.toml").write_text(MESHED.format(mesh=good))
    out["meshed_ok"] = str(folder / "meshed_ok.toml")
    return out


@pytest.fixture(scope="module")
def files(tmp_path_factory) -> dict[str, str]:
    """Stator files, meshes and paths the cases refer to as ``{name}``."""
    d = tmp_path_factory.mktemp("bad")
    f: dict[str, str] = {}

    def toml(name: str, text: str) -> None:
        (d / f"{name}.toml").write_text(text)
        f[name] = str(d / f"{name}.toml")

    toml("plate", PLATE)
    toml("off_centre_hole", "[plate]\nlength_mm = 25.6938\nwidth_mm = 7.2\n"
         "thickness_mm = 2.5\n[electrodes]\ngap_mm = 0.4\n[material]\nname = \"paper\"\n"
         "[tip]\nlength_mm = 0.8\nwidth_mm = 1.6\n[chamfers]\nsize_mm = 0.8\n"
         "[[holes]]\ncenter_mm = [1.5, 6.0]\ndiameter_mm = 1.0\n")
    for size in ("07", "085"):
        toml(f"hole_mesh_{size}", PLATE + f"[mesh]\nsize_mm = {size[0]}.{size[1:]}\n"
             "[[holes]]\ncenter_mm = [0, 15]\ndiameter_mm = 1\n")
    f["chamfered_example"] = str(ROOT / "examples" / "chamfered" / "stator.toml")
    import json
    from dataclasses import asdict, replace

    from rom import table2

    (d / "overflow.json").write_text(json.dumps(asdict(replace(table2(), phi_Bl=1e300))))
    f["params_overflow"] = str(d / "overflow.json")
    with open(d / "huge_sparse.toml", "wb") as fh:  # sparse: no disk used
        fh.truncate(2_000_000)
    f["huge_sparse"] = str(d / "huge_sparse.toml")
    toml("unit_list", '[plate]\nthickness_mm = 3\n[mesh]\nfile = "x.msh"\nunit = ["m"]\n')
    toml("tip_far", PLATE + "[points]\ntip_mm = [0, 1e300]\n")
    toml("length_str", '[plate]\nlength_mm = "30"\nwidth_mm = 7.5\nthickness_mm = 3\n')
    toml("huge", "[plate]\nlength_mm = 1e6\nwidth_mm = 7.5\nthickness_mm = 3\n")
    toml("rho_inf", PLATE + '[material]\nbase = "pzt8"\nrho_kg_m3 = inf\n')
    toml("material_list", PLATE + '[material]\nname = ["pzt8"]\n')
    toml("drive_str", PLATE + '[electrodes]\ndrive = "1,4"\n')
    toml("zeta_zero", PLATE + "[damping]\nzeta_L1 = 0\nzeta_B2 = 0.01\n")
    toml("q_and_zeta", PLATE + "[damping]\nQ_m = 100\nzeta_L1 = 0.01\n")
    toml("amplitudes_unreachable", PLATE + "[damping]\nsource = \"paper_amplitudes\"\n")
    toml("slider_heavy", PLATE + "[slider]\nM_slider_kg = 1e6\n")
    toml("mu_d_above_mu_s", PLATE + "[friction]\nmu_d = 0.6\n")
    toml("tip_too_long", PLATE + "[tip]\nlength_mm = 40\nwidth_mm = 2\n")
    toml("tip_no_width", PLATE + "[tip]\nlength_mm = 1\n")
    toml("chamfer_huge", PLATE + "[chamfers]\nsize_mm = 4\n")
    toml("hole_on_edge", PLATE + "[[holes]]\ncenter_mm = [3.5, 5]\ndiameter_mm = 1\n")
    toml("hole_unknown_key", PLATE + "[[holes]]\ncenter_mm = [0, 5]\nradius_mm = 1\n")
    toml("features_and_mesh_file", PLATE + '[chamfers]\nsize_mm = 1\n[mesh]\nfile = "x.msh"\n')
    toml("mesh_size_tiny", PLATE + "[chamfers]\nsize_mm = 1\n[mesh]\nsize_mm = 1e-3\n")
    toml("chamfered_plate", PLATE + "[chamfers]\nsize_mm = 1\n")
    toml("mount_off", PLATE + "[chamfers]\nsize_mm = 1\n[points]\nmounts_mm = [[3.5, 0.2]]\n")
    (d / "utf16.toml").write_text(PLATE, encoding="utf-16")
    f["utf16"] = str(d / "utf16.toml")
    (d / "binary.toml").write_bytes(bytes(range(256)) * 4)
    f["binary"] = str(d / "binary.toml")
    (d / "a_file").write_text("keep")
    f["file"] = str(d / "a_file")
    f["below_file"] = str(d / "a_file" / "sub")
    (d / "user").mkdir()
    (d / "user" / "notes.txt").write_text("mine")
    f["user_folder"] = str(d / "user")
    f["folder"] = str(d)
    f["missing"] = str(d / "missing.toml")
    (d / "loop1").symlink_to(d / "loop2")
    (d / "loop2").symlink_to(d / "loop1")
    f["in_loop"] = str(d / "loop1" / "x")
    f["long_name"] = str(d / ("a" * 300))
    f["export_exists"] = str(d / "a_file")
    (d / "side").mkdir()
    (d / "side" / "modes.h5").write_text("the user's")
    f["xdmf_with_side_file"] = str(d / "side" / "modes.xdmf")
    f.update(_meshes(d))
    return f


# (name, argv, fragments the one error line must contain)
CASES: list[tuple[str, list[str], list[str]]] = [
    # simulate: operating point and time stepping
    ("sim-dt-negative-separate", ["simulate", "--voltage", "200", "--preload", "14", "--dt",
                                  "-1e-7"],
     ["--dt", "(0, 1/(20 f)] s at the drive frequency f", "'-1e-7'"]),
    ("sim-dt-1e-300", ["simulate", "--voltage", "200", "--preload", "14", "--dt", "1e-300"],
     ["--dt", "time steps", "LUSM_MAX_WORK"]),
    ("sim-dt-denormal", ["simulate", "--voltage", "200", "--preload", "14", "--dt", "5e-324"],
     ["--dt", "time steps"]),
    ("sim-dt-1e-13", ["simulate", "--voltage", "200", "--preload", "14", "--dt", "1e-13"],
     ["--dt", "above the limit"]),
    ("sim-dt-above-20-per-period", ["simulate", "--voltage", "200", "--preload", "14", "--dt",
                                    "2e-6"], ["--dt", "1/(20 f)"]),
    ("sim-duration-1000", ["simulate", "--voltage", "200", "--preload", "14", "--duration",
                           "1000"], ["--duration", "(0, 10] s"]),
    ("sim-duration-zero", ["simulate", "--voltage", "200", "--preload", "14", "--duration", "0"],
     ["--duration"]),
    ("sim-duration-short", ["simulate", "--voltage", "200", "--preload", "14", "--duration",
                            "0.000123456789"],
     ["--duration", "10 drive periods", "got 0.000123456789 s"]),  # as typed, every digit
    ("sim-voltage-1e9", ["simulate", "--voltage", "1e9", "--preload", "14"],
     ["--voltage", "[0, 2000] V"]),
    ("sim-voltage-nan", ["simulate", "--voltage", "nan", "--preload", "14"], ["--voltage"]),
    ("sim-voltage-inf", ["simulate", "--voltage", "inf", "--preload", "14"], ["--voltage"]),
    ("sim-voltage-negative", ["simulate", "--voltage", "-5", "--preload", "14"], ["--voltage"]),
    ("sim-preload-1e30", ["simulate", "--voltage", "200", "--preload", "1e30"],
     ["--preload", "[0, 1000] N"]),
    ("sim-preload-text", ["simulate", "--voltage", "200", "--preload", "much"], ["--preload"]),
    ("sim-frequency-zero", ["simulate", "--voltage", "200", "--preload", "14", "--frequency",
                            "0"], ["--frequency", "'auto'"]),
    ("sim-frequency-text", ["simulate", "--voltage", "200", "--preload", "14", "--frequency",
                            "fast"], ["--frequency"]),
    ("sim-frequency-inf", ["simulate", "--voltage", "200", "--preload", "14", "--frequency",
                           "inf"], ["--frequency"]),
    ("sim-plot-empty", ["simulate", "--voltage", "200", "--preload", "14", "--plot", ""],
     ["--plot", "folder"]),
    ("sim-plot-is-file", ["simulate", "--voltage", "200", "--preload", "14", "--plot",
                          "{file}"], ["--plot", "is a file"]),
    ("sim-plot-below-file", ["simulate", "--voltage", "200", "--preload", "14", "--plot",
                             "{below_file}"], ["--plot", "sits below the file"]),
    ("sim-plot-user-folder", ["simulate", "--voltage", "200", "--preload", "14", "--plot",
                              "{user_folder}"], ["--plot", "did not write", "--force"]),
    ("sim-geometry-missing", ["simulate", "--voltage", "200", "--preload", "14", "--geometry",
                              "{missing}"], ["--geometry", "not found"]),
    ("sim-geometry-with-table2", ["simulate", "--voltage", "200", "--preload", "14",
                                  "--source", "table2", "--geometry", "{plate}"],
     ["--geometry", "--source fem"]),
    ("sim-geometry-utf16", ["simulate", "--voltage", "200", "--preload", "14", "--geometry",
                            "{utf16}"], ["--geometry", "utf16.toml", "UTF-8"]),
    ("sim-geometry-binary", ["simulate", "--voltage", "200", "--preload", "14", "--geometry",
                             "{binary}"], ["--geometry", "binary.toml"]),
    ("sim-plate-option-with-geometry", ["simulate", "--voltage", "200", "--preload", "14",
                                        "--geometry", "{plate}", "--length-mm", "30"],
     ["--length-mm cannot be combined with --geometry"]),
    ("sim-unknown-option", ["simulate", "--voltage", "200", "--preload", "14", "--bogus"],
     ["unrecognized"]),
    # map
    ("modes-3d-layers-too-many-bricks", ["modes", "--model", "3d", "--layers", "16",
                                         "--refine", "8"],
     ["--layers: the plate 30 x 7.5 x 3 mm needs 4752 3D bricks", "lower --layers or --refine"]),
    ("modes-3d-gap-zero", ["modes", "--model", "3d", "--gap-mm", "0"],
     ["--gap-mm must be at least 0.001 mm with --model 3d, got 0"]),
    ("map-frequency-zero", ["map", "--frequency", "0"], ["--frequency"]),
    # paths the system cannot look up: the option is named (they said "cannot use ...")
    ("render-out-name-too-long", ["render", "--out", "{long_name}"],
     ["--out", "File name too long"]),
    ("render-out-in-link-loop", ["render", "--out", "{in_loop}"],
     ["--out", "Too many levels of symbolic links"]),
    ("modes-export-name-too-long", ["modes", "--export", "{long_name}.vtu"],
     ["--export", "File name too long"]),
    # a steady map's --dt serves an undecided point's transient: 1e-3 s had run without a word
    ("map-steady-dt-above-20-per-period", ["map", "--method", "steady", "--dt", "1e-3"],
     ["--dt", "1/(20 f)", "--method steady"]),
    ("map-voltages-1e10-points", ["map", "--voltages", "0:1e10:1"], ["--voltages", "limit"]),
    ("map-voltages-beyond-range", ["map", "--voltages", "0:5000:1000"],
     ["--voltages", "[0, 2000] V"]),
    ("map-preloads-malformed", ["map", "--preloads", "a:b"], ["--preloads", "start:stop:step"]),
    ("map-preloads-negative", ["map", "--preloads=-1,2"], ["--preloads", "[0, 1000] N"]),
    ("map-preloads-negative-separate", ["map", "--preloads", "-1,2"], ["--preloads"]),
    ("map-voltages-negative-range", ["map", "--voltages", "-5:5:1"], ["--voltages"]),
    ("map-workers-negative", ["map", "--workers=-3"], ["--workers", "[1, 256]"]),
    ("characteristic-voltages-too-many", ["characteristic", "--voltage", "1,2,3,4,5,6,7,8,9",
                                         "--preload", "14"], ["--voltage", "1 to 8"]),
    ("characteristic-voltage-in-list-bad", ["characteristic", "--voltage", "100,nan",
                                            "--preload", "14"], ["--voltage", "[0, 2000] V"]),
    ("simulate-voltage-list-with-plot", ["simulate", "--voltage", "200,400", "--preload", "14",
                                         "--plot", "plots_out"], ["--plot", "one --voltage"]),
    ("modes-gap-subnormal", ["modes", "--gap-mm", "5e-324"], ["--gap-mm", "at least 0.001 mm"]),
    ("map-workers-zero", ["map", "--workers", "0"], ["--workers"]),
    ("map-total-work", ["map", "--method", "transient", "--voltages", "0:400:1",
                        "--preloads", "1:40:1"], ["time steps", "LUSM_MAX_WORK"]),
    ("map-steady-total-work", ["map", "--voltages", "0:400:1", "--preloads", "1:40:1"],
     ["--voltages", "16040 points", "LUSM_MAX_WORK"]),
    ("map-method-unknown", ["map", "--method", "settled"], ["--method", "steady"]),
    ("map-accuracy-unknown", ["map", "--accuracy", "best"], ["--accuracy", "exact"]),
    ("map-plot-is-file", ["map", "--plot", "{file}"], ["--plot", "is a file"]),
    ("map-dt-tiny", ["map", "--dt", "1e-300"], ["--dt"]),
    # modes: plate, FE size, export, stator files
    ("modes-length-1e-6", ["modes", "--length-mm", "1e-6"], ["--length-mm", "[0.1, 1000] mm"]),
    ("modes-thickness-zero", ["modes", "--thickness-mm", "0"], ["--thickness-mm"]),
    ("modes-width-nan", ["modes", "--width-mm", "nan"], ["--width-mm"]),
    ("modes-refine-100000", ["modes", "--refine", "100000"], ["--refine", "LUSM_MAX_WORK"]),
    # the plate typed, --refine not: the message led with --refine
    # an XDMF export's HDF5 side file in the way: it was refused only after the FE solve
    ("modes-export-side-file", ["modes", "--export", "{xdmf_with_side_file}"],
     ["--export", "side file", "already exists"]),
    # too slender for any mesh to give an L1/B2 pair: it had been told to make the plate less
    # elongated for the mesh bound, and is refused for its slenderness before that count
    ("modes-elongated-default-mesh", ["modes", "--length-mm", "1000", "--width-mm", "1",
                                      "--gap-mm", "0.1"],
     ["--length-mm 1000 and --width-mm 1: the 1000 x 1 mm plate is 1000 times longer",
      "at most about 720 times the width"]),
    # the mesh bound on a plate slender but within reach of B2: the refine typed is named
    ("modes-elongated-refined", ["modes", "--length-mm", "700", "--width-mm", "1",
                                 "--refine", "8"],
     ["--refine: the plate 700 x 1 x 3 mm needs", "above the limit 20000"]),
    ("modes-layers-100000", ["modes", "--model", "3d", "--layers", "100000"], ["--layers"]),
    ("modes-edge-grading-9", ["modes", "--model", "3d", "--edge-grading", "9"],
     ["--edge-grading", "[0, 6]"]),
    ("modes-edge-grading-2d", ["modes", "--edge-grading", "1"], ["--edge-grading", "3d"]),
    ("modes-layers-2d", ["modes", "--layers", "5"], ["--layers", "3d"]),  # was ignored
    # work of many solves together, and of one graded 3D mesh (each ran for minutes)
    ("modes-3d-edge-grading-6", ["modes", "--model", "3d", "--edge-grading", "6"],
     ["--edge-grading", "3000 3D bricks", "limit 2000"]),
    ("tune-refine-48", ["tune", "--refine", "48"], ["--refine", "15 FE solves", "100000"]),
    ("sweep-refine-48", ["sweep", "--width-mm", "6:9:0.1", "--refine", "48"],
     ["--refine", "31 FE solves", "100000"]),
    ("modes-edge-grading-too-fine", ["modes", "--model", "3d", "--edge-grading", "6",
                                     "--gap-mm", "0.001"], ["--edge-grading", "bricks"]),
    ("modes-refine-3d", ["modes", "--model", "3d", "--refine", "40"], ["--refine", "--model 3d"]),
    ("modes-gap-eats-plate", ["modes", "--gap-mm", "8"], ["--gap-mm", "7.5 mm"]),
    # the parse range alone ([0, 1000] mm) hid the rest of the rule
    # the staging folder's name (/proc/.x-partial-...) had stood for the user's folder
    ("report-out-unwritable", ["report", "--out", "/proc/lusm-x", "--quick"],
     ["--out /proc/lusm-x: cannot write there"]),
    ("modes-gap-huge", ["modes", "--gap-mm", "1e9"],
     ["--gap-mm", "[0, 1000] mm", "below the plate's length and width"]),
    ("modes-export-folder", ["modes", "--export", "{folder}"], ["--export", "folder"]),
    ("modes-export-unknown-format", ["modes", "--export", "{folder}/m.unknownext"],
     ["--export", ".unknownext is not a mesh format; use one of .vtu"]),
    ("modes-export-exists", ["modes", "--export", "{export_exists}"],
     ["--export", "already exists"]),
    ("modes-export-below-file", ["modes", "--export", "{below_file}/m.vtu"],
     ["--export", "below the file"]),
    ("modes-geometry-and-width", ["modes", "--geometry", "{plate}", "--width-mm", "8"],
     ["--width-mm cannot be combined with --geometry"]),
    ("modes-geometry-folder", ["modes", "--geometry", "{folder}"], ["--geometry", "folder"]),
    ("stator-unit-list", ["modes", "--geometry", "{unit_list}"], ["[mesh] unit", "unit_list"]),
    ("stator-tip-far", ["modes", "--geometry", "{tip_far}"], ["[points] tip_mm"]),
    ("stator-length-string", ["modes", "--geometry", "{length_str}"],
     ["[plate] length_mm", "length_str.toml"]),
    ("stator-huge-plate", ["modes", "--geometry", "{huge}"], ["length_mm must lie in"]),
    ("stator-rho-inf", ["modes", "--geometry", "{rho_inf}"], ["rho_kg_m3", "[100, 50000] kg/m^3"]),
    ("stator-material-list", ["modes", "--geometry", "{material_list}"], ["[material] name"]),
    ("stator-drive-string", ["modes", "--geometry", "{drive_str}"], ["[electrodes] drive"]),
    ("stator-damping-zero", ["simulate", "--voltage", "200", "--preload", "14", "--geometry",
                             "{zeta_zero}"], ["--geometry", "[damping] zeta_L1", "[1e-05, 1)"]),
    ("stator-damping-q-and-zeta", ["map", "--geometry", "{q_and_zeta}"],
     ["--geometry", "[damping] Q_m", "cannot be combined with zeta_L1"]),
    ("stator-slider-heavy", ["characteristic", "--voltage", "200", "--preload", "14",
                             "--geometry", "{slider_heavy}"],
     ["--geometry", "[slider] M_slider_kg", "[0.0001, 100] kg"]),
    ("stator-mu-d-above-table2-mu-s", ["simulate", "--voltage", "200", "--preload", "14",
                                       "--geometry", "{mu_d_above_mu_s}"],
     ["--geometry", "[friction] mu_d must be <= mu_s"]),
    ("params-damping-bad-q", ["params", "--geometry", "{q_and_zeta}"], ["[damping] Q_m"]),
    ("simulate-damping-amplitudes-unreachable",
     ["simulate", "--voltage", "200", "--preload", "14", "--geometry", "{amplitudes_unreachable}"],
     ["--geometry", "[damping] source = \"paper_amplitudes\"", "even undamped",
      "natural frequency", "[damping] frequency_Hz"]),
    ("mesh-duplicated-cell", ["modes", "--geometry", "{duplicated}"],
     ["duplicated cells"]),
    ("mesh-folded", ["modes", "--geometry", "{folded}"], ["folded.msh", "cells"]),
    ("mesh-disconnected", ["modes", "--geometry", "{disconnected}"], ["separate parts"]),
    ("mesh-overlap", ["modes", "--geometry", "{overlap}"], ["overlapping", "folded"]),
    ("mesh-overlap-at-a-node", ["modes", "--geometry", "{overlap_vertex}"],
     ["overlapping or non-conforming"]),
    ("mesh-hanging-node", ["modes", "--geometry", "{hanging_node}"], ["non-conforming"]),
    ("mesh-bowtie", ["modes", "--geometry", "{bowtie}"], ["degenerate", "cells"]),
    ("mesh-electrodes-1-and-4-only", ["modes", "--geometry", "{only14}"],
     ["[mesh] file", "only14.msh", "no cells under electrodes 2, 3",
      "all four quadrant electrodes 1..4"]),
    ("mesh-unmerged-seam", ["modes", "--geometry", "{seam}"],
     ["seam.msh", "4 nodes used by its cells that coincide with another node", "y = 15.25 mm",
      "merge the duplicate nodes"]),
    ("mesh-metre-declared-mm", ["modes", "--geometry", "{metre_as_mm}"], ["looks like metres"]),
    ("mesh-ten-metres", ["modes", "--geometry", "{ten_metres}"], ["1 m limit"]),
    ("mesh-tip-far", ["modes", "--geometry", "{tip_far_mesh}"], ["tip_mm", "off the mesh"]),
    ("mesh-tip-vertex-far", ["modes", "--geometry", "{tip_vertex_far}"],
     ["tip_vertex_far.toml: the 'tip' vertex group of the mesh file tip_vertex_far.msh is at "
      "[0, 40] mm, off the mesh's cells", "set [points] tip_mm"]),
    # params, compare
    ("params-beam-with-geometry", ["params", "--source", "beam", "--geometry", "{plate}"],
     ["--source fem"]),
    ("params-table2-with-plate", ["params", "--source", "table2", "--length-mm", "30"],
     ["--length-mm needs --source fem"]),
    ("compare-unknown-source", ["compare", "--sources", "abc"], ["--sources", "invalid choice"]),
    # report
    ("report-out-empty", ["report", "--out", ""], ["--out", "folder"]),
    ("report-out-file", ["report", "--out", "{file}"], ["--out", "is a file"]),
    ("report-user-folder", ["report", "--out", "{user_folder}"], ["--out", "did not write"]),
    ("compare-geometry-missing", ["compare", "--geometry", "no_such_stator.toml"],
     ["--geometry", "no_such_stator.toml"]),
    ("sim-params-missing", ["simulate", "--voltage", "200", "--preload", "14", "--params",
                            "no_such_set.json"], ["--params", "no such file"]),
    # read whole before: a 512 MB file took 1.1 GB of memory
    ("sim-params-huge", ["simulate", "--voltage", "200", "--preload", "14", "--params",
                         "{huge_sparse}"], ["--params", "bytes, above 1000000"]),
    ("modes-geometry-huge", ["modes", "--geometry", "{huge_sparse}"],
     ["--geometry", "bytes, above 1000000"]),
    # a device is not a set ("no such file" before)
    ("sim-params-device", ["simulate", "--voltage", "200", "--preload", "14", "--params",
                           "/dev/null"], ["--params /dev/null: not a regular file"]),
    # an overflow failed deep in NumPy, "Array must not contain infs or NaNs", naming nothing
    ("sim-params-overflow", ["simulate", "--voltage", "200", "--preload", "14", "--duration",
                             "0.001", "--params", "{params_overflow}"],
     ["--params: the parameter set's mode matrices overflow", "phi_Bl = 1e+300"]),
    ("admittance-f-max-below-design-band", ["admittance", "--f-max", "1"],
     ["--f-max", "leaves no band"]),
    ("report-geometry-missing", ["report", "--geometry", "no_such_stator.toml"],
     ["--geometry", "no_such_stator.toml"]),
    ("report-length-tiny", ["report", "--length-mm", "1e-6"], ["--length-mm", "mm"]),
    # render
    ("render-out-file", ["render", "--out", "{file}"], ["--out", "is a file"]),
    ("render-refine-zero", ["render", "--refine", "0"], ["--refine"]),
    ("render-geometry-missing", ["render", "--geometry", "{missing}"], ["not found"]),
    ("render-thickness-huge", ["render", "--thickness-mm", "1e6"], ["--thickness-mm"]),
    # tune
    # 7e5 Hz passed the check and lost L1 after 10 FE solves (the tuned plate's electrodes
    # narrower than 1.5 x the gap); 1e6 Hz was above the quoted range and still accepted
    ("tune-target-electrodes-too-narrow", ["tune", "--target-frequency", "7e5"],
     ["--target-frequency 700000 Hz", "targets from about 1692 to 2.245e+05 Hz fit"]),
    ("tune-target-zero", ["tune", "--target-frequency", "0"], ["--target-frequency"]),
    ("tune-target-inf", ["tune", "--target-frequency", "inf"], ["--target-frequency"]),
    ("tune-meshed-geometry", ["tune", "--geometry", "{meshed_ok}"], ["--geometry", "own mesh"]),
    ("tune-refine-3d", ["tune", "--model", "3d", "--refine", "40"], ["--refine"]),
    ("tune-fix-length-with-target", ["tune", "--fix", "length", "--length-mm", "35",
                                     "--target-frequency", "40e3"],
     ["--fix length", "--target-frequency"]),
    ("tune-fix-width-with-target", ["tune", "--fix", "width,thickness_ratio",
                                    "--target-frequency", "5e4"],
     ["--fix width", "--target-frequency"]),
    ("tune-fix-length-and-width", ["tune", "--fix", "length,width"], ["--fix", "both"]),
    ("tune-fix-both-thickness-rules", ["tune", "--fix", "thickness,thickness_ratio"],
     ["--fix", "choose one"]),
    ("tune-fix-unknown", ["tune", "--fix", "height"], ["--fix", "length, width"]),
    ("tune-fix-twice", ["tune", "--fix", "length,length"], ["--fix", "each once"]),
    ("tune-fix-empty", ["tune", "--fix", ""], ["--fix"]),
    ("tune-fix-length-meshed", ["tune", "--fix", "length", "--geometry", "{meshed_ok}"],
     ["--geometry", "own mesh", "--fix length"]),
    # sweep
    ("sweep-1e9-points", ["sweep", "--width-mm", "1:1e9:1"], ["--width-mm", "limit"]),
    ("sweep-two-ranges", ["sweep", "--width-mm", "6:8:1", "--length-mm", "28:30:1"],
     ["exactly one"]),
    ("sweep-no-range", ["sweep", "--width-mm", "8"], ["exactly one", "--width-mm 8 (no range)"]),
    # a malformed 30:40 had been counted as a second range ("got 2 ranges"): as typed now
    ("sweep-range-and-malformed", ["sweep", "--width-mm", "6:10:1", "--length-mm", "30:40"],
     ["exactly one", "got --width-mm 6:10:1 and --length-mm 30:40"]),
    ("sweep-beyond-plate-range", ["sweep", "--width-mm", "1:2000:500"],
     ["--width-mm must lie in"]),
    ("sweep-too-many-solves", ["sweep", "--width-mm", "1:500:1"], ["FE solves"]),
    ("sweep-out-empty", ["sweep", "--width-mm", "6:8:1", "--out", ""], ["--out"]),
    ("sweep-gap-above-width", ["sweep", "--width-mm", "0.1:1:0.1"], ["electrode gap"]),
    ("sweep-fixed-length-bad", ["sweep", "--width-mm", "6:8:1", "--length-mm", "-3"],
     ["--length-mm"]),
    ("sweep-meshed-geometry", ["sweep", "--width-mm", "6:8:1", "--geometry", "{meshed_ok}"],
     ["--geometry"]),
    # admittance
    ("adm-points-1e9", ["admittance", "--points", "1000000000"], ["--points", "LUSM_MAX_WORK"]),
    ("adm-fmin-above-fmax", ["admittance", "--f-min", "7e4", "--f-max", "6e4"],
     ["--f-min", "--f-max"]),
    ("adm-fmin-zero", ["admittance", "--f-min", "0"], ["--f-min"]),
    ("adm-zeta-zero", ["admittance", "--zeta", "0"], ["--zeta"]),
    ("adm-electrodes-5", ["admittance", "--electrodes", "1,5"], ["--electrodes"]),
    ("adm-out-below-file", ["admittance", "--out", "{below_file}"], ["--out", "below the file"]),
    # explore (more in tests/test_explore.py)
    ("sim-load-nan", ["simulate", "--voltage", "400", "--preload", "14", "--load-N", "nan"],
     ["--load-N", "N"]),
    ("sim-steady-plot", ["simulate", "--voltage", "400", "--preload", "14", "--steady",
                         "--plot", "figs"], ["--plot", "--steady"]),
    ("characteristic-voltage-nan", ["characteristic", "--voltage", "nan", "--preload", "14"],
     ["--voltage", "[0, 2000] V"]),
    ("characteristic-frequency-0", ["characteristic", "--voltage", "400", "--preload", "14",
                                    "--frequency", "0"], ["--frequency", "Hz"]),
    ("characteristic-loads-huge", ["characteristic", "--voltage", "400", "--preload", "14",
                                   "--loads", "0:1e9:1e-9"], ["--loads", "above the limit 2000"]),
    ("characteristic-plot-file", ["characteristic", "--voltage", "400", "--preload", "14",
                                  "--plot", "{file}"], ["--plot", "is a file"]),
    ("explore-missing-study", ["explore", "{missing}", "--out", "r.nc"], ["missing.toml"]),
    ("explore-stator-as-study", ["explore", "{plate}", "--out", "r.nc"],
     ["plate is not a study section"]),
    # parametric stator files (fem.meshing.parametric, meshed by gmsh)
    ("modes-tip-too-long", ["modes", "--geometry", "{tip_too_long}"],
     ["--geometry", "[tip] length_mm", "(0, 30]"]),
    ("modes-tip-no-width", ["modes", "--geometry", "{tip_no_width}"],
     ["--geometry", "[tip] needs width_mm"]),
    ("modes-chamfer-huge", ["modes", "--geometry", "{chamfer_huge}"],
     ["--geometry", "[chamfers] size_mm", "(0, 3.5)"]),
    ("modes-hole-on-edge", ["modes", "--geometry", "{hole_on_edge}"],
     ["--geometry", "[[holes]] #1", "outline"]),
    ("modes-hole-unknown-key", ["modes", "--geometry", "{hole_unknown_key}"],
     ["--geometry", "unknown key 'radius_mm' in [[holes]] #1"]),
    ("modes-features-and-mesh-file", ["modes", "--geometry", "{features_and_mesh_file}"],
     ["--geometry", "[mesh] file", "gmsh"]),
    ("modes-mesh-size-tiny", ["modes", "--geometry", "{mesh_size_tiny}"],
     ["--geometry", "[mesh] size_mm", "[0.075, 7.5]"]),
    ("modes-mount-off-the-plate", ["modes", "--geometry", "{mount_off}"],
     ["--geometry", "[points] mounts_mm point 1", "off the stator's planform"]),
    ("modes-parametric-edge-grading-2d", ["modes", "--edge-grading", "1",
                                          "--geometry", "{chamfered_plate}"],
     ["--edge-grading", "--model 3d only"]),
    # a stator file's mesh above the 3D bound: fewer layers fit, which it did not say (the
    # docs' own `lusm modes --model 3d --geometry examples/chamfered/stator.toml`)
    ("modes-3d-file-mesh-too-many-bricks", ["modes", "--model", "3d", "--geometry",
                                            "{chamfered_example}"],
     ["--geometry", "2988 3D bricks", "lower --layers (3) or use a coarser mesh file"]),
    # an off-centre hole mixes L1 into B2 in open circuit: a shape test, which the message
    # blamed on --refine (which does nothing to a gmsh-meshed stator)
    ("modes-off-centre-hole-pairing", ["modes", "--geometry", "{off_centre_hole}"],
     ["could not pair L1 in open circuit", "keep such features symmetric"]),
    # tune has no --layers and does not refine a gmsh-meshed stator: its remedies named both
    ("tune-3d-file-mesh-too-many-bricks", ["tune", "--geometry", "{hole_mesh_07}", "--fix",
                                           "length", "--model", "3d"],
     ["--geometry: the stator's mesh needs 2670 3D bricks here, above the limit 2000; "
      "coarsen its [mesh] size_mm"]),
    ("tune-3d-file-mesh-too-much-work", ["tune", "--geometry", "{hole_mesh_085}", "--fix",
                                         "length", "--model", "3d"],
     ["--geometry: 15 FE solves of about 1734 3D bricks", "coarsen its [mesh] size_mm ("]),
    ("explore-workers-0", ["explore", "{plate}", "--out", "r.nc", "--workers", "0"],
     ["--workers"]),
]


def test_the_table_is_large_and_covers_every_command():
    from lusm.cli import build_parser

    assert len(CASES) >= 60
    assert len({name for name, _, _ in CASES}) == len(CASES)
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    assert {argv[0] for _, argv, _ in CASES} == set(sub.choices)


SLOW_CASES = {"modes-off-centre-hole-pairing"}
"""Cases refused only once the stator is meshed and solved (seconds, not milliseconds)."""


@pytest.mark.parametrize(("argv", "fragments"), [
    pytest.param(*c[1:], id=c[0], marks=[pytest.mark.slow] if c[0] in SLOW_CASES else [])
    for c in CASES])
def test_bad_input_is_refused_in_one_line(argv, fragments, files, capsys):
    args = [a.format(**files) for a in argv]
    rc = main(args)
    captured = capsys.readouterr()
    lines = [ln for ln in captured.err.splitlines() if ln.strip()]
    assert rc == 2, captured.err
    assert "Traceback" not in captured.err
    errors = [ln for ln in lines if ": error: " in ln]
    assert len(errors) == 1 and errors[0] == lines[-1], captured.err
    assert errors[0].startswith(f"lusm {argv[0]}: error: ")
    for fragment in fragments:
        assert fragment in errors[0], errors[0]


def test_nothing_was_written_or_deleted_by_the_refusals(files):
    assert Path(files["file"]).read_text() == "keep"
    user = Path(files["user_folder"])
    assert sorted(p.name for p in user.iterdir()) == ["notes.txt"]
    assert not list(Path(files["folder"]).glob(".*partial*"))


@pytest.mark.parametrize("name", ["duplicated", "overlap"])
def test_the_named_cells_are_the_bad_ones(files, name):
    """The cell numbers in the message index the file's surface cells (as meshio reads them)."""
    import re

    import meshio

    from fem.stator_file import load_stator

    with pytest.raises(ValueError) as info:
        load_stator(files[name])
    numbers = [int(n) for n in re.search(r"cells ([\d, ]+)", str(info.value)).group(1)
               .split(",")]
    m = meshio.read(Path(files[name]).with_suffix(".msh"))
    cells = np.concatenate([b.data for b in m.cells if b.type == "quad"])
    named = [frozenset(cells[n]) for n in numbers]
    if name == "duplicated":
        assert len(numbers) == 2 and named[0] == named[1]
    else:  # the folded cell and the cells on its edge share that edge
        shared = [len(p & q) for i, p in enumerate(named) for q in named[i + 1:]]
        assert len(numbers) >= 2 and 2 in shared


def test_a_valid_mesh_is_still_accepted(files):
    from fem.stator_file import load_stator

    design = load_stator(files["meshed_ok"])
    assert design.stator.length_m == pytest.approx(0.03)


def test_work_bounds_can_be_raised_on_purpose(monkeypatch, capsys):
    # 2.5e7 steps: above the default bound, allowed with LUSM_MAX_WORK=2 (checked, not run)
    from lusm.options import check_run_size

    with pytest.raises(ValueError, match="LUSM_MAX_WORK"):
        check_run_size(0.05, 2e-9, 40e3)
    monkeypatch.setenv("LUSM_MAX_WORK", "2")
    assert check_run_size(0.05, 2e-9, 40e3) == 25_000_000
    # a bad factor is the variable's fault, even when an option's bound would have used it
    # first (it was blamed on --refine), and a huge one is refused, not an OverflowError
    for value in ["lots", "0", "1e308", "inf"]:
        monkeypatch.setenv("LUSM_MAX_WORK", value)
        for argv in (["params"], ["modes", "--refine", "3"]):
            assert main(argv) == 2
            err = capsys.readouterr().err.strip()
            assert err.startswith("lusm: error: LUSM_MAX_WORK must be a number in "
                                  "[1, 1000000]"), err
            assert len(err.splitlines()) == 1 and repr(value) in err


def test_warnings_where_the_model_stops_meaning_anything(capsys):
    from lusm.options import check_plate_mm, warn_drive

    check_plate_mm(30.0, 7.5, 20.0, 0.5, three_d=True)  # the 3D model has no such limit
    warn_drive(0.0, 0.0, load_N=0.1)  # the load pushes the slider: it moves
    assert capsys.readouterr().err == ""
    check_plate_mm(30.0, 7.5, 20.0, 0.5)
    warn_drive(900.0, 300.0)
    warn_drive(0.0, 0.0)
    err = capsys.readouterr().err
    assert "plane-stress" in err and "--thickness-mm 20" in err
    assert "--voltage 900" in err and "--preload 300" in err
    assert "nothing moves" in err


def test_json_is_valid_without_infinity(capsys):
    import json

    from lusm.options import print_json

    print_json({"a": float("inf"), "b": [float("nan"), 1.0], "c": np.float64(2.0)})
    text = capsys.readouterr().out
    assert json.loads(text) == {"a": None, "b": [None, 1.0], "c": 2.0}


def test_an_unexpected_error_is_one_line_exit_1(monkeypatch, capsys):
    import lusm.commands.params as cmd

    def boom(args):
        raise ZeroDivisionError("division by zero")

    monkeypatch.setattr(cmd, "run", boom)  # a bug in a command
    assert main(["params"]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "ZeroDivisionError" in err and "please report" in err and "LUSM_DEBUG" in err


@pytest.mark.slow
def test_sigterm_removes_the_staging_folder(tmp_path):
    out = tmp_path / "r"
    proc = subprocess.Popen([sys.executable, "-m", "lusm.cli", "report", "--quick",
                             "--no-progress", "--out", str(out)], cwd=ROOT,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and not list(tmp_path.glob(".*partial*")):
        time.sleep(0.05)
    assert list(tmp_path.glob(".*partial*")), "the report did not start staging"
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert "Traceback" not in err
    assert list(tmp_path.iterdir()) == []  # no staging folder, no half report


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_a_signal_python_swallows_still_stops_the_command(signum, monkeypatch, tmp_path,
                                                           capsys):
    # A handler that runs inside a __del__ or weakref callback (importlib's module locks have
    # one) cannot propagate its exception: Python prints "Exception ignored" and carries on.
    import lusm.commands.params as cmd
    from lusm.output_set import output_set

    class SignalOnCollect:
        def __del__(self):
            signal.raise_signal(signum)

    def command(args):
        with output_set(tmp_path / "out") as stage:
            (stage / "a.png").write_bytes(b"x")
            obj = SignalOnCollect()
            del obj  # the signal's exception is swallowed here
            (stage / "b.png").write_bytes(b"y")  # so the command goes on

    monkeypatch.setattr(cmd, "run", command)
    assert main(["params"]) == 130
    err = capsys.readouterr().err  # Python's own "Exception ignored" report, then the line
    assert err.strip().splitlines()[-1] == "lusm params: interrupted"
    assert list(tmp_path.iterdir()) == []  # nothing moved in, no staging folder left
    assert signal.getsignal(signal.SIGTERM) is signal.SIG_DFL
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


@pytest.mark.filterwarnings("ignore::pytest.PytestUnraisableExceptionWarning")
def test_an_error_caused_by_a_signal_is_the_interruption(monkeypatch, tmp_path, capsys):
    # a signal landing inside a numba call comes back from the dispatcher as "SystemError:
    # ... returned a result with an exception set" (seen with Ctrl-C in lusm characteristic):
    # the command must end as interrupted (130), not as an internal error (1)
    import lusm.commands.params as cmd
    from lusm.output_set import output_set

    class SignalOnCollect:
        def __del__(self):
            signal.raise_signal(signal.SIGTERM)

    def command(args):
        with output_set(tmp_path / "out") as stage:
            (stage / "a.png").write_bytes(b"x")
            obj = SignalOnCollect()
            del obj
            raise SystemError("CPUDispatcher(...) returned a result with an exception set")

    monkeypatch.setattr(cmd, "run", command)
    assert main(["params"]) == 130
    assert capsys.readouterr().err.strip().splitlines()[-1] == "lusm params: interrupted"
    assert list(tmp_path.iterdir()) == []


def test_debug_env_shows_the_traceback():
    env = {**os.environ, "LUSM_DEBUG": "1"}
    proc = subprocess.run([sys.executable, "-m", "lusm.cli", "simulate", "--voltage",
                           "200", "--preload", "14", "--dt", "1e-13"], cwd=ROOT,
                          capture_output=True, text=True, env=env, timeout=120)
    assert proc.returncode != 0 and "Traceback" in proc.stderr


def test_library_errors_are_mapped_to_the_option_that_sets_them():
    from fem.geometry import PlateStator
    from lusm.errors import LusmError, user_error

    with pytest.raises(ParameterError) as info:  # a ValueError still, for library callers
        PlateStator(length_m=-1.0)
    e = user_error(info.value)
    assert isinstance(e, LusmError) and e.option == "--length-mm"
    assert str(e) == "--length-mm must be in (0, 10000] mm, got -1000"  # the option's mm
    e = user_error(FileNotFoundError(2, "No such file or directory", "/x/y.png"))
    assert str(e) == "cannot use /x/y.png: No such file or directory"
    e = user_error(UnicodeDecodeError("utf-8", b"\xff", 0, 1, "invalid start byte"))
    assert "UTF-8" in str(e) and "byte 0" in str(e)


@pytest.mark.slow
def test_an_export_is_moved_in_complete(tmp_path, capsys):
    out = tmp_path / "new" / "m.vtu"
    assert main(["modes", "--refine", "2", "--export", str(out)]) == 0
    assert out.is_file() and sorted(p.name for p in out.parent.iterdir()) == ["m.vtu"]
    capsys.readouterr()
    assert main(["modes", "--refine", "2", "--export", str(out)]) == 2  # not overwritten
    assert "already exists" in capsys.readouterr().err
    first = out.read_bytes()
    assert main(["modes", "--refine", "2", "--export", str(out), "--force"]) == 0
    assert sorted(p.name for p in out.parent.iterdir()) == ["m.vtu", "m.vtu.bak-1"]
    assert (out.parent / "m.vtu.bak-1").read_bytes() == first  # --force keeps the old file


def test_an_export_with_a_long_file_name_is_written(tmp_path):
    # a 244-byte name, which the file system takes, failed after the solve: its staging
    # folder ".NAME-partial-XXXXXXXX" went over the 255-byte limit ("File name too long")
    out = tmp_path / ("f" * 240 + ".vtu")
    assert main(["modes", "--refine", "2", "--export", str(out)]) == 0
    assert out.is_file() and [p.name for p in tmp_path.iterdir()] == [out.name]


@pytest.mark.parametrize("exc, code, words", [
    (ChatteringError("contact chattering: more switches than allowed within one step",
                     step_remedy=True), 2, ["error: contact chattering", "smaller --dt"]),
    (ChatteringError("contact chattering in the full-model shooting"), 2,
     ["error: contact chattering in the full-model shooting"]),
    (RuntimeError("f(a) and f(b) must have different signs"), 1,
     ["RuntimeError", "please report"]),
])
def test_the_kernels_refusal_is_bad_input_but_other_runtime_errors_are_bugs(
        exc, code, words, monkeypatch, capsys):
    # the kernel's chattering is a property of the operating point (exit 2, one line); any
    # other RuntimeError from the library (a SciPy root finder giving up) is not the user's
    import contact.simulate

    def refuse(*args, **kwargs):
        raise exc

    monkeypatch.setattr(contact.simulate, "simulate", refuse)
    assert main(["simulate", "--voltage", "200", "--preload", "14"]) == code
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and all(w in err for w in words), err
    assert "max_events_per_step" not in err and "dt_s" not in err  # the CLI's words only


@pytest.mark.parametrize("exc, code, last", [
    (KeyboardInterrupt(), 130, "lusm params: interrupted"),
    (ParameterError("voltage_V", float("nan"), 0.0, None, "V"), 2,
     "lusm params: error: --voltage must be a finite number >= 0 V, got nan"),
])
def test_the_last_line_is_its_own_after_an_open_progress_bar(exc, code, last, monkeypatch,
                                                             capsys):
    # a bar left open by an interrupted loop has no line end: the command's one line was
    # printed after its text (seen with Ctrl-C during lusm map)
    from tqdm import tqdm

    import lusm.commands.params as cmd

    def command(args):
        bar = tqdm(total=10, desc="work", file=sys.stderr)
        bar.update(3)
        raise exc

    monkeypatch.setattr(cmd, "run", command)
    assert main(["params"]) == code
    err = capsys.readouterr().err
    assert err.endswith("\n") and err.splitlines()[-1] == last


def test_a_ctrl_c_before_the_command_starts_is_one_line(monkeypatch, capsys):
    # Ctrl-C during the first fraction of a second (imports, the BLAS probe, parsing) printed
    # a KeyboardInterrupt traceback: it is the same interruption as later on
    import lusm.cli as cli

    def interrupted():
        raise KeyboardInterrupt

    monkeypatch.setattr(cli, "build_parser", interrupted)
    assert main(["params"]) == 130
    assert capsys.readouterr().err.strip() == "lusm params: interrupted"


def test_library_warnings_are_one_line_naming_the_command(capsys):
    # the 2D model's validity warning came out in Python's form: the library's file and line,
    # the warning's class, then the statement that raised it
    assert main(["params", "--source", "fem", "--gap-mm", "2"]) == 0
    err = capsys.readouterr().err.strip().splitlines()
    assert err and all(line.startswith("lusm params: warning: ") for line in err), err
    assert any("electrode gap 2 mm exceeds thickness/6" in line for line in err)
    assert not any("GapValidityWarning" in line or ".py:" in line for line in err)


def test_an_export_into_a_folder_it_cannot_write_names_the_users_file(tmp_path, monkeypatch,
                                                                      capsys):
    # the message named the staging folder's random name (".m.vtu-partial-xxxx")
    real_mkdir = os.mkdir

    def denied(path, *args, **kwargs):  # only the staging folder: its parent is made first
        if os.path.basename(path).startswith(".m.vtu-partial-"):
            raise PermissionError(13, "Permission denied", path)
        return real_mkdir(path, *args, **kwargs)

    monkeypatch.setattr(os, "mkdir", denied)
    out = tmp_path / "ro" / "m.vtu"
    assert main(["modes", "--refine", "2", "--export", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert err == f"lusm modes: error: --export {out}: cannot write there (Permission denied)"


@pytest.mark.slow
def test_an_export_that_cannot_be_written_whole_is_refused_and_leaves_nothing(tmp_path):
    """Under a file-size limit meshio's XDMF writer lost its HDF5 writes in h5py's
    finalizers: tracebacks, "wrote m.xdmf", exit 0, and a truncated m.h5 moved in that meshio
    cannot read. The limit is set in the child (Python ignores SIGXFSZ: writes fail EFBIG)."""
    out = tmp_path / "x" / "m.xdmf"
    code = ("import resource; resource.setrlimit(resource.RLIMIT_FSIZE, (30720, 30720)); "
            "from lusm.cli import main; raise SystemExit(main(['modes', '--refine', '2', "
            f"'--export', {str(out)!r}]))")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       cwd=ROOT, timeout=300)
    assert r.returncode == 2, r.stderr
    assert r.stderr.strip().splitlines() == [
        f"lusm modes: error: --export: cannot write {out} whole (File too large)"]
    assert not out.parent.exists() or list(out.parent.iterdir()) == []


def test_an_export_into_a_folder_it_cannot_write_is_refused_before_the_solve(tmp_path,
                                                                             monkeypatch,
                                                                             capsys):
    # it was refused only after the FE solve (30 s of a 3D model)
    import fem.modes

    def no_solve(*args, **kwargs):
        raise AssertionError("solved before checking the export's folder")

    monkeypatch.setattr(fem.modes, "plate_modes", no_solve)
    monkeypatch.setattr(os, "access", lambda path, mode: False)
    out = tmp_path / "m.vtu"
    assert main(["modes", "--export", str(out)]) == 2
    assert capsys.readouterr().err.strip() == (
        f"lusm modes: error: --export {out}: cannot write into {tmp_path} (permission denied)")


def test_a_report_that_cannot_be_written_names_its_folder(tmp_path, monkeypatch, capsys):
    """A file-size limit while the report's set was written said "cannot use: File too
    large", naming neither --out nor the folder (the other commands say both)."""
    import errno

    import validation.report

    def full(out, **kwargs):
        raise OSError(errno.EFBIG, os.strerror(errno.EFBIG))

    monkeypatch.setattr(validation.report, "write_report", full)
    out = tmp_path / "r"
    assert main(["report", "--out", str(out)]) == 2
    assert capsys.readouterr().err.strip() == (
        f"lusm report: error: --out {out}: cannot write (File too large)")


@pytest.mark.parametrize("exc, said", [
    # the range in the option's units, the library's reason after it
    (ParameterError("frequency_Hz", 1.0, 2e4, None, "Hz", reason="the fastest mode"),
     "--frequency must be >= 20000 Hz, got 1 (the fastest mode)"),
    (ParameterError("dt_s", 1e-7, 0.0, 8.5e-10, "s", low_open=True),
     "--dt must be in (0, 8.5e-10] s, got 1e-07"),
    (ParameterError("electrode_gap_m", 0.01, 0.0, 0.0075, "m", high_open=True),
     "--gap-mm must be in [0, 7.5) mm, got 10"),
    (ParameterError("voltage_V", float("nan"), 0.0, None, "V"),
     "--voltage must be a finite number >= 0 V, got nan"),
    # no range (a work bound): the library's words after the option, its assignment named
    (ParameterError("refine", 8, message="refine = 8 makes 3e+04 elements"),
     "--refine 8 makes 3e+04 elements"),
    (ParameterError("layers", 9, message="too many bricks"), "--layers: too many bricks"),
    # a parameter no option sets, and a plain ValueError: the library's line
    (ParameterError("mu_d", 2.0, 0.0, 1.0), "mu_d must be in [0, 1], got 2.0"),
    (ValueError("load_N = 50 N: no steady state from rest"),
     "--load-N 50 N: no steady state from rest"),
    (ValueError("check the plate and --refine"), "check the plate and --refine"),
])
def test_library_refusals_are_said_with_the_options_the_user_typed(exc, said):
    from lusm.errors import user_error

    assert str(user_error(exc)) == said


@pytest.mark.parametrize("argv, option", [
    (["modes", "--geometry", ""], "--geometry"), (["params", "--geometry", ""], "--geometry"),
    (["modes", "--export", ""], "--export"),
    (["simulate", "--voltage", "200", "--preload", "14", "--params", ""], "--params"),
])
def test_an_empty_path_is_refused_not_read_as_not_given(argv, option, capsys):
    # "" ran the default plate (and --export "" wrote nothing) with exit 0
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert f"{option} must name" in err and len(err.splitlines()) == 1


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="needs named pipes")
@pytest.mark.parametrize(("option", "argv", "said"), [
    ("--geometry", ["modes", "--geometry"], "is a FIFO (named pipe), not a TOML file"),
    ("--params", ["simulate", "--voltage", "200", "--preload", "14", "--params"],
     "not a regular file (a FIFO (named pipe))"),
])
def test_a_named_pipe_given_as_an_input_file_is_refused_at_once(tmp_path, capsys, option,
                                                                 argv, said):
    # a stator file named by a FIFO was "stator file not found" (it exists); the one reader
    # of small input files (fem.small_file) opens nothing that could block and says what the
    # path is. A writer is never attached: a reader that opened the pipe would wait for ever
    fifo = tmp_path / "in.toml"
    os.mkfifo(fifo)
    assert main([*argv, str(fifo)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and option in err[0] and said in err[0]


def test_the_small_file_reader_checks_what_it_reads_not_only_the_size_reported(tmp_path):
    # /proc files report size 0 and yield more: the cap holds on the bytes read
    from fem.small_file import FileTooLarge, read_small_text

    proc = Path("/proc/self/maps")
    if not proc.exists() or proc.stat().st_size != 0:
        pytest.skip("needs a file whose reported size is 0 and whose content is not")
    with pytest.raises(FileTooLarge):
        read_small_text(proc, 10)
    (tmp_path / "ok.toml").write_bytes("\ufeffname = 'x'\n".encode())
    assert read_small_text(tmp_path / "ok.toml", 100) == "name = 'x'\n"


@pytest.mark.slow
def test_a_ctrl_c_after_the_command_is_done_is_ignored():
    # a Ctrl-C during the interpreter's shutdown, right after lusm modes or lusm render had
    # printed their last line, printed a KeyboardInterrupt traceback from threading._shutdown
    # and exited 0: once the command is done, SIGINT is ignored to the end of the process
    code = ("import signal, sys\n"
            "from lusm.cli import main\n"
            "sys.argv = ['lusm', 'params', '--json']\n"
            "rc = main()\n"
            "print(signal.getsignal(signal.SIGINT) is signal.SIG_IGN)\n"
            "sys.exit(rc)\n")
    run = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                         text=True, timeout=120)
    assert run.returncode == 0 and run.stdout.strip().splitlines()[-1] == "True"


_ENDED = [["params", "--json"], ["simulate", "--voltage", "-1"]]
"""A command that ends 0 (with its output on stdout) and one refused (2)."""


def _after_main(argv: list[str], then: str) -> subprocess.CompletedProcess:
    """A Python process that runs ``lusm ARGV`` through ``main()``, then the code ``then``
    (with ``os``, ``signal``, ``subprocess``, ``sys``, ``time``, ``atexit`` imported), then
    exits with the command's code."""
    code = ("import atexit, os, signal, subprocess, sys, time\n"
            "from lusm.cli import main\n"
            f"sys.argv = ['lusm', *{argv!r}]\n"
            "rc = main()\n" + then + "sys.exit(rc)\n")
    return subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True,
                          text=True, timeout=120)


@pytest.mark.parametrize("argv", _ENDED)
def test_a_sigterm_after_the_command_has_ended_keeps_its_exit_code(argv):
    """A SIGTERM landing after the command had moved its output in and printed its last
    line killed the process with exit 143 and no word (3 of 30 late SIGTERMs to lusm
    simulate --plot; exploratory testing): the command's end is said, and its exit code
    (0 done, 2 refused) stays, with what it printed. Here the signal is sent after main()
    returned, where the interpreter's shutdown would run: it ends the process there."""
    import json

    run = _after_main(argv, "os.kill(os.getpid(), signal.SIGTERM)\n"
                            "print('still here')\n")
    assert run.returncode == (0 if argv[0] == "params" else 2), run.stderr
    assert "still here" not in run.stdout  # ended by the signal, not by running on
    if argv[0] == "params":  # its JSON, still in Python's buffer at the signal, is kept
        assert json.loads(run.stdout)
    else:
        assert "lusm simulate: error: " in run.stderr


@pytest.mark.parametrize("argv", _ENDED)
@pytest.mark.slow
def test_a_sigterm_ends_a_hung_clean_up_with_the_commands_exit_code(argv):
    """Once the command had ended SIGTERM was ignored to the process's exit, so a clean-up
    that hung (explore's cluster shutdown, an exit hook) could be stopped by SIGKILL alone
    (review). Here an exit hook hangs and a child process sends SIGTERM: the process ends
    at once, with the command's exit code."""
    code = ("def hang():\n"
            "    subprocess.Popen([sys.executable, '-c', 'import os, signal, time; '\n"
            "                      f'time.sleep(0.5); os.kill({os.getpid()}, signal.SIGTERM)'])\n"
            "    print('clean-up hangs', file=sys.stderr, flush=True)\n"
            "    time.sleep(600)\n"
            "    print('clean-up done', file=sys.stderr)\n"
            "atexit.register(hang)\n")
    # the hook sleeps 600 s: a SIGTERM that does not end it fails here, by the timeout
    run = _after_main(argv, code)
    assert run.returncode == (0 if argv[0] == "params" else 2), run.stderr
    assert "clean-up hangs" in run.stderr and "clean-up done" not in run.stderr


def test_unreadable_inputs_are_named_as_such(tmp_path, capsys):
    # a dangling study link said "cannot use dangling: No such file or directory"; a
    # non-UTF-8 --params file quoted Python's codec message
    link = tmp_path / "study.toml"
    link.symlink_to(tmp_path / "missing.toml")
    assert main(["explore", str(link), "--out", str(tmp_path / "o.nc")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no such study file (a symbolic link to a missing file)" in err[0]
    bad = tmp_path / "p.json"
    bad.write_bytes(b"\xff\xfe{}")
    assert main(["simulate", "--voltage", "200", "--preload", "14", "--params", str(bad)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--params" in err[0] and "not UTF-8 text (byte 0" in err[0]
    assert "codec" not in err[0]


def test_an_export_path_ending_in_a_separator_names_a_folder(tmp_path, capsys):
    """``--export out/dd.vtu/`` names a folder: it had been written as the file dd.vtu (the
    trailing separator is dropped by pathlib). It is refused before any work, and nothing is
    made."""
    target = tmp_path / "out" / "dd.vtu"
    for tail in ("/", "/."):  # pathlib drops a trailing '.' as well (review)
        assert main(["modes", "--refine", "1", "--export", f"{target}{tail}"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and "--export" in err[0] and "is a folder" in err[0]
        assert not (tmp_path / "out").exists()
