"""``lusm optimize`` (studies.optimize): the search through its own machinery (the sampler,
the batches on dask, the parts, the dataset) with an analytic evaluator in place of the FE
and motor solve, and one small real run of the command."""

from __future__ import annotations

import json

import numpy as np
import pytest

from studies.optimize import optimize, problem_from_dict
from studies.task import empty_outputs, geometry_of

pytestmark = pytest.mark.slow  # a dask client and tens of sampler calls per test


def analytic(study, index):
    """A plate's outputs as a known function of its length x and width y (mm): the no-load
    velocity 10 - (x - 31)^2 - (y - 8)^2 (m/s), largest at (31, 8), and the stall force
    x + y (N)."""
    g = geometry_of(study, index)
    out = empty_outputs(study)
    x, y = g["length"] * 1e3, g["width"] * 1e3
    out["f_L1_short"] = np.array(50e3)
    out["split"] = np.array(100.0 * (x - 30.0))
    out["no_load_velocity"][...] = 10.0 - (x - 31.0) ** 2 - (y - 8.0) ** 2
    out["stall_force"][...] = x + y
    out["motion_class"][...] = "pure-slip"
    out["point_status"][...] = "ok"
    return out


def doc(evaluations: int = 40, constraints=None, objectives=None, seed: int = 3) -> dict:
    """A study of the paper's plate with length and width as design variables."""
    return {"outputs": ["no_load_velocity"], "axes": {"voltage": "200 V"},
            "optimize": {"evaluations": evaluations, "seed": seed,
                         "variables": {"length": {"min": "28 mm", "max": "34 mm"},
                                       "width": {"min": "6 mm", "max": "10 mm"}},
                         "objectives": objectives or [{"output": "no_load_velocity",
                                                       "goal": "maximize"}],
                         "constraints": constraints or {}}}


@pytest.fixture(scope="module")
def client():
    """Two worker threads in this process: the analytic evaluator needs no process."""
    distributed = pytest.importorskip("distributed")
    with distributed.Client(processes=False, n_workers=2, threads_per_worker=1,
                            dashboard_address=None) as c:
        yield c


def _table(path):
    from studies.dataset import open_result

    ds = open_result(path)
    return ds, {k: ds[k].values for k in ("length", "width", "objective_no_load_velocity",
                                          "feasible", "best")}


def test_a_constrained_optimum_is_found(client, tmp_path):
    """Maximise 10 - (x - 31)^2 - (y - 8)^2 under x + y <= 38 mm (as a stall force <= 38 N):
    the optimum is on the constraint, at (30.5, 7.5) with 9.5."""
    problem = problem_from_dict(doc(60, {"stall_force": {"max": "38 N"}}))
    result = optimize(problem, tmp_path / "r.nc", client=client, evaluate=analytic)
    ds, t = _table(result.path)
    assert result.evaluations == 60 and result.batch == 2 and len(result.best) == 1
    row = int(np.flatnonzero(t["best"])[0])
    x, y = t["length"][row] * 1e3, t["width"][row] * 1e3
    assert x + y <= 38.0 + 1e-9
    assert t["objective_no_load_velocity"][row] > 9.2  # of 9.5
    assert abs(x - 30.5) < 0.6 and abs(y - 7.5) < 0.6
    # labelled as explore's dataset: units, the trial, the constraint's value
    assert ds["length"].attrs["units"] == "m"
    assert ds["objective_no_load_velocity"].attrs["units"] == "m/s"
    assert ds["constraint_stall_force_max"].values[row] <= 0
    assert json.loads(ds.attrs["best_trials"]) == [int(ds["trial"].values[row])]
    assert not (tmp_path / "r.nc.parts").exists()


def test_a_run_stopped_before_its_first_record_leaves_no_parts_folder(tmp_path):
    from studies.optimize.store import Store
    from studies.parts import parts_folder

    problem, out = problem_from_dict(doc(4)), tmp_path / "r.nc"
    with pytest.raises(KeyboardInterrupt), Store(problem, out, resume=False):
        assert parts_folder(out).is_dir()
        raise KeyboardInterrupt
    assert not parts_folder(out).exists()
    with Store(problem, out, resume=False) as store:
        assert store.created and not store.records
    assert parts_folder(out).is_dir()  # a clean exit keeps it (write_result removes it)


def test_resume_after_an_interruption_gives_the_same_result(client, tmp_path):
    problem = problem_from_dict(doc(14))
    whole = optimize(problem, tmp_path / "whole.nc", client=client, evaluate=analytic)

    def stop(trial):
        if trial >= 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        optimize(problem, tmp_path / "cut.nc", client=client, evaluate=analytic, on_trial=stop)
    kept = len(list((tmp_path / "cut.nc.parts").glob("g*.npz")))
    assert 1 <= kept < 14
    resumed = optimize(problem, tmp_path / "cut.nc", client=client, evaluate=analytic,
                       resume=True)
    assert resumed.reused == kept and resumed.computed == 14 - kept
    _, a = _table(whole.path)
    _, b = _table(resumed.path)
    for k in a:
        np.testing.assert_array_equal(a[k], b[k], err_msg=k)
    assert resumed.best == whole.best


def analytic_tuner(study, variable):
    """The width (m) at which an analytic plate of length x (mm) is tuned: x / 4 + 0.5 mm;
    none below x = 28.5 mm."""
    x = geometry_of(study, 0)["length"] * 1e3
    if x < 28.5:
        raise ValueError(f"no crossing at length {x} mm")
    return (x / 4.0 + 0.5) * 1e-3


def analytic_tuned(study, index):
    """:func:`analytic` with the split of the analytic tune: 1 kHz per mm off its width."""
    out = analytic(study, index)
    g = geometry_of(study, index)
    out["split"] = np.array(1e6 * (g["width"] - analytic_tuner(study, "width")))
    return out


def test_a_tuned_search_evaluates_tuned_plates_and_resumes_exactly(client, tmp_path):
    """split = "tuned": every evaluated plate has the tuner's width; a length the tuner finds
    no crossing for (below 28.5 mm) or tunes outside [7, 8.5] mm (above 32 mm) is infeasible,
    not evaluated, not a crash; an interrupted run resumed ends as the whole run."""
    d = doc(12, {"split": "tuned", "tune": {"variable": "width", "min": "7 mm",
                                            "max": "8.5 mm"}})
    del d["optimize"]["variables"]["width"]
    problem = problem_from_dict(d)
    assert problem.tune.variable == "width" and problem.tune.high == pytest.approx(8.5e-3)
    run = {"client": client, "evaluate": analytic_tuned, "tuner": analytic_tuner}
    whole = optimize(problem, tmp_path / "whole.nc", **run)
    from studies.dataset import open_result

    ds = open_result(whole.path)
    x, w = ds["length"].values * 1e3, ds["tuned_width"].values * 1e3
    ok = (x >= 28.5) & (x <= 32.0)
    np.testing.assert_allclose(w[x >= 28.5], x[x >= 28.5] / 4 + 0.5)
    assert np.isnan(w[x < 28.5]).all() and ok.any() and (~ok).any()
    np.testing.assert_array_equal(ds["feasible"].values == 1, ok)
    assert (ds["constraint_tuned"].values[~ok] > 0).all()
    assert all(str(s).startswith("tune: ") for s in ds["status"].values[~ok])
    np.testing.assert_allclose(ds["split"].values[ok], 0.0, atol=1e-6)
    (best,) = np.flatnonzero(ds["best"].values)
    assert abs(x[best] - 30.94) < 1.0  # the optimum along the tuned ridge

    def stop(trial):
        if trial >= 5:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        optimize(problem, tmp_path / "cut.nc", on_trial=stop, **run)
    resumed = optimize(problem, tmp_path / "cut.nc", resume=True, **run)
    assert resumed.reused >= 1 and resumed.computed == 12 - resumed.reused
    again = open_result(resumed.path)
    for k in ("length", "tuned_width", "objective_no_load_velocity", "constraint_tuned",
              "feasible", "best"):
        np.testing.assert_array_equal(ds[k].values, again[k].values, err_msg=k)


def test_a_two_sided_bound_of_an_uncomputed_output_is_nan():
    """A design not evaluated (not tunable) has NaN outputs: a bound with both sides gives
    two NaN values, not a TypeError (numpy's bools add as a logical or)."""
    from studies.optimize.metrics import constraint_values

    problem = problem_from_dict(doc(4, {"stall_force": {"min": "1 N", "max": "40 N"}}))
    (bound,) = problem.bounds
    values = constraint_values(bound, empty_outputs(problem.study),
                               {"length": 30e-3, "width": 8e-3}, problem.study)
    assert len(values) == 2 and np.isnan(values).all()


def test_a_constraint_no_design_meets_is_reported_not_an_optimum(client, tmp_path):
    problem = problem_from_dict(doc(6, {"stall_force": {"max": "20 N"}}))  # x + y >= 34
    result = optimize(problem, tmp_path / "r.nc", client=client, evaluate=analytic)
    ds, t = _table(result.path)
    assert result.infeasible_everywhere and result.best == () and result.feasible == 0
    assert not t["feasible"].any() and not t["best"].any()
    assert (ds["constraint_stall_force_max"].values > 0).all()


def test_two_objectives_give_a_pareto_front(client, tmp_path):
    """Maximise the velocity and minimise the stall force: no design of the front is
    dominated by any evaluated design."""
    objectives = [{"output": "no_load_velocity", "goal": "maximize"},
                  {"output": "stall_force", "goal": "minimize"}]
    problem = problem_from_dict(doc(20, objectives=objectives))
    result = optimize(problem, tmp_path / "r.nc", client=client, evaluate=analytic)
    ds, _ = _table(result.path)
    v, f = ds["objective_no_load_velocity"].values, ds["objective_stall_force"].values
    front = np.flatnonzero(ds["best"].values)
    assert len(front) >= 2 and len(result.best) == len(front)
    for i in front:
        assert not np.any((v >= v[i]) & (f <= f[i]) & ((v > v[i]) | (f < f[i])))


def test_the_drive_frequency_and_a_ratio_are_objectives():
    """A ratio's unit, an operating point picked by ``at``, the bounds' units."""
    problem = problem_from_dict(doc(4, {"split": "0.5 %", "volume": {"max": "800 mm3"},
                                        "limits": True},
                                    [{"output": "stall_force / volume", "goal": "maximize",
                                      "at": {"voltage": "200 V"}}]))
    (o,) = problem.objectives
    assert o.unit == "N/(m^3)" and o.at == {"voltage": 200.0}
    split, volume, limits = problem.bounds
    assert split.relative and split.high == pytest.approx(0.005)
    assert volume.high == pytest.approx(800e-9)
    assert (limits.name, limits.high) == ("limit_ratio", 1.0)
    assert "limit_ratio" in problem.study.outputs


@pytest.mark.parametrize("change, key", [
    ({"variables": {"lenght": {"min": "28 mm", "max": "34 mm"}}}, "optimize.variables.lenght"),
    ({"variables": {"length": {"min": "34 mm", "max": "28 mm"}}}, "optimize.variables.length"),
    ({"evaluations": 0}, "optimize.evaluations"),
    ({"objectives": [{"output": "speed", "goal": "maximize"}]}, "optimize.objectives[0]"),
    ({"objectives": [{"output": "stall_force", "goal": "max"}]}, "optimize.objectives[0]"),
    ({"constraints": {"split": "0.5"}}, "optimize.constraints.split"),
    ({"constraints": {"heat": {"max": "1 W"}}}, "optimize.constraints.heat"),
    ({"variables": {"tip_length": {"min": "1 mm", "max": "2 mm"}}},
     "optimize.variables.tip_length"),
    ({"constraints": {"split": "tuned"}}, "optimize.constraints.tune"),
    ({"constraints": {"split": "tuned", "tune": "thickness"}}, "optimize.constraints.tune"),
    ({"constraints": {"tune": "length"}}, "optimize.constraints.tune"),
    ({"constraints": {"split": "tuned", "tune": {"variable": "length", "min": "9 mm",
                                                 "max": "8 mm"}}},
     "optimize.constraints.tune"),
])
def test_bad_optimize_tables_name_their_key(change, key):
    d = doc()
    d["optimize"].update(change)
    with pytest.raises(ValueError, match=key.replace("[", r"\[").replace(".", r"\.")):
        problem_from_dict(d)


def test_the_command_end_to_end(tmp_path, capsys):
    """A real search, small: two plates by FE (the coupling of B2 under a split bound) on a
    one-worker LocalCluster, its figure, its best design as a stator file that loads, and
    that design's 3D check."""
    from fem.stator_file import load_stator
    from lusm.cli import main

    study = tmp_path / "fe.toml"
    study.write_text('outputs = ["split"]\n[optimize]\nevaluations = 2\n'
                     '[optimize.variables]\nlength = { min = "29 mm", max = "31 mm" }\n'
                     '[[optimize.objectives]]\noutput = "k_eff_B2"\ngoal = "maximize"\n'
                     '[optimize.constraints]\nsplit = "20 %"\n')
    out, plots, best = tmp_path / "r.nc", tmp_path / "plots", tmp_path / "best.toml"
    assert main(["optimize", str(study), "--out", str(out), "--workers", "1", "--plot",
                 str(plots), "--write", str(best), "--check-3d", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["evaluations"] == 2 and summary["computed"] == 2
    (b,) = summary["best"]
    assert summary["figures"] == [str(plots / "convergence.png")]
    assert (plots / "convergence.png").stat().st_size > 0
    check = summary["check_3d"]
    assert check["f_L1_2d_Hz"] == pytest.approx(b["f_L1_short_Hz"])
    assert check["f_L1_3d_Hz"] == pytest.approx(check["f_L1_2d_Hz"], rel=0.01)
    design = load_stator(best)
    assert design.stator.length_m == pytest.approx(b["design"]["length"], rel=1e-9)
    assert main(["optimize", str(study), "--out", str(out)]) == 2  # not overwritten
    assert "--force" in capsys.readouterr().err


def test_a_ctrl_c_keeps_the_parts_and_resume_completes_the_same_run(dask_client, tmp_path,
                                                                   monkeypatch, capsys):
    """``lusm optimize`` interrupted by SIGINT after its first evaluation: exit 130, the kept
    parts said in one line before the CLI's "interrupted", nothing from dask; ``--resume``
    ends with the dataset of an uninterrupted run (a real FE-only search of four designs on
    the session's two workers: batches of two, the first cut in its middle)."""
    import os
    import signal

    import studies.optimize.store as S
    from lusm.cli import main
    from studies.dataset import open_result
    from studies.parts import parts_folder

    study = tmp_path / "fe.toml"
    study.write_text('outputs = ["split"]\n[solver]\nfe_order = 1\nfe_refine = 1\n'
                     '[optimize]\nevaluations = 4\nseed = 2\nstartup = 2\n'
                     '[optimize.variables]\nlength = { min = "29 mm", max = "31 mm" }\n'
                     '[[optimize.objectives]]\noutput = "k_eff_B2"\ngoal = "maximize"\n')
    whole, cut = tmp_path / "whole.nc", tmp_path / "cut.nc"
    on = ["--scheduler", dask_client.scheduler.address]
    assert main(["optimize", str(study), "--out", str(whole), *on, "--json"]) == 0
    capsys.readouterr()
    write_part = S.write_part

    def write_then_interrupt(folder, index, data):
        write_part(folder, index, data)
        os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(S, "write_part", write_then_interrupt)
    assert main(["optimize", str(study), "--out", str(cut), *on]) == 130
    lines = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert lines == [f"lusm optimize: 1 evaluated design is kept in {parts_folder(cut)}; run "
                     "the same command with --resume to continue",
                     "lusm optimize: interrupted"], lines
    assert not cut.exists() and len(list(parts_folder(cut).glob("g*.npz"))) == 1
    monkeypatch.setattr(S, "write_part", write_part)
    assert main(["optimize", str(study), "--out", str(cut), *on, "--resume", "--json"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert (summary["reused"], summary["computed"]) == (1, 3)
    a, b = open_result(whole), open_result(cut)
    assert sorted(a.data_vars) == sorted(b.data_vars)
    for k in a.data_vars:
        np.testing.assert_array_equal(a[k].values, b[k].values, err_msg=k)
    assert a.attrs["best_trials"] == b.attrs["best_trials"]
