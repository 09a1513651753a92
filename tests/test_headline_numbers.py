"""The README's and the report's headline figures, pinned (as scikit-fem pins its examples).

Each value below was computed by this code when the figure was written into the README; the
tolerances are loose enough for another BLAS or CPU and tight enough that a real change of the
model or the solver breaks them. A change that moves one on purpose updates the pin, the
README (``python -m validation.doc_numbers && python -m validation.doc_numbers --fill``) and
says why in its commit.
"""

from __future__ import annotations

import pytest

from tests.conftest import cached_run

# --- FE (2D, order 2, default mesh): lusm modes --------------------------------------------
# These move when the 2D model changes (issue 8, FE fidelity): update them with the README.
FE_PINS_HZ = {
    ("L1", "short"): 56479.73,
    ("L1", "open"): 58366.91,
    ("B2", "short"): 54164.29,
    ("B2", "open"): 55314.35,
}


@pytest.fixture(scope="module")
def fe_modes():
    from fem.geometry import PlateStator
    from fem.modes import DEFAULT_REFINE, plate_modes

    return plate_modes(PlateStator(), "pzt8", 2, DEFAULT_REFINE)


@pytest.mark.parametrize(("mode", "circuit"), list(FE_PINS_HZ))
def test_default_plate_frequencies(fe_modes, mode, circuit):
    f = getattr(getattr(fe_modes, mode), f"f_{circuit}_Hz")
    assert f == pytest.approx(FE_PINS_HZ[mode, circuit], rel=2e-6)  # 0.1 Hz


# --- contact on Table 2: lusm simulate --------------------------------------------------------
@pytest.mark.parametrize(("voltage", "preload", "velocity", "motion"), [
    (200.0, 14.0, 0.0076314, "stick-slip"),
    (400.0, 14.0, 0.191921, "slip-separation"),
])
def test_table2_velocities(voltage, preload, velocity, motion):
    r = cached_run(voltage, preload)
    assert r.steady.motion == motion
    assert r.steady.velocity_m_s == pytest.approx(velocity, rel=1e-4)


def test_dead_zone_edge_at_14_N(paper_params):
    from validation.hard_cases import dead_zone_edge

    edge = dead_zone_edge(paper_params, 14.0, tol_V=0.05)
    assert edge == pytest.approx(139.07, abs=0.1)  # +16 % above the paper's 120 V
