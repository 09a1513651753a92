"""Small findings of issue 42 that are not refusals: a parameter set that excites neither
mode is warned of as a stator file's drive is, and a one-layer linear 3D model says no
NumPy warning of its own."""

from __future__ import annotations

import json
from dataclasses import asdict, replace

import pytest

from lusm.cli import main
from rom import table2


@pytest.mark.slow
def test_a_params_file_without_force_factors_is_warned(tmp_path, capsys):
    """A_l = A_b = 0 at a fixed frequency: 'pure-stick', settled, no word (the stator file
    route warns, --frequency auto refuses)."""
    path = tmp_path / "zero.json"
    path.write_text(json.dumps(asdict(replace(table2(), A_l=0.0, A_b=0.0))))
    assert main(["simulate", "--params", str(path), "--voltage", "200", "--preload", "14",
                 "--frequency", "40000", "--duration", "0.00025", "--json"]) == 0
    cap = capsys.readouterr()
    assert "A_l = A_b = 0 N/V" in cap.err and "no thrust" in cap.err, cap.err
    json.loads(cap.out)


def test_a_one_layer_linear_3d_model_says_no_numpy_warning(capsys):
    """No potential is left to condense at one layer of order 1: 'Mean of empty slice' and
    'invalid value encountered in scalar divide' leaked as warnings."""
    assert main(["modes", "--model", "3d", "--layers", "1", "--order", "1"]) == 0
    err = capsys.readouterr().err
    assert "empty slice" not in err and "invalid value" not in err, err
