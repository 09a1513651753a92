"""The NumPy matrix exponential of the propagators against SciPy's and a 40-digit reference."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm

from contact.expm import expm_stack
from contact.model import OperatingPoint, build_system


@pytest.fixture(scope="module")
def mode_matrices(paper_params):
    return build_system(paper_params, OperatingPoint(200.0, 14.0, 40e3), paper_params.mu_d).A


@pytest.mark.parametrize("dt_s", [1e-9, 5e-8, 1e-7, 2e-7])
def test_propagators_match_scipy(mode_matrices, dt_s):
    """The stiff, far-from-normal mode matrices at the time steps the kernel uses."""
    a = mode_matrices * dt_s
    ref = np.stack([expm(m) for m in a])
    assert np.max(np.abs(expm_stack(a) - ref)) <= 1e-13 * np.max(np.abs(ref))


def test_high_precision_reference(mode_matrices):
    """Balancing keeps full accuracy where plain scaling and squaring loses ~6 digits."""
    mpmath = pytest.importorskip("mpmath")
    mpmath.mp.dps = 40
    a = mode_matrices[-1] * 1e-7
    exact = np.array(mpmath.expm(mpmath.matrix(a.tolist())).tolist(), dtype=float)
    assert np.max(np.abs(expm_stack(a) - exact)) <= 1e-14 * np.max(np.abs(exact))


@pytest.mark.parametrize("scale", [1e-4, 0.05, 0.5, 2.0, 8.0, 40.0])
def test_every_pade_degree(scale):
    """Random stacks whose norms select each Pade degree (3..13) and the squaring branch."""
    a = np.random.default_rng(7).standard_normal((4, 6, 6)) * scale / 6.0
    ref = np.stack([expm(m) for m in a])
    assert np.max(np.abs(expm_stack(a) - ref)) <= 1e-12 * np.max(np.abs(ref))


def test_exponential_laws():
    """expm(0) = I, expm of a diagonal is elementwise, expm(A) expm(-A) = I, one matrix in."""
    assert np.array_equal(expm_stack(np.zeros((2, 3, 3))), np.broadcast_to(np.eye(3), (2, 3, 3)))
    d = np.diag([-3.0, 0.1, 2.0])
    assert np.allclose(expm_stack(d), np.diag(np.exp([-3.0, 0.1, 2.0])), rtol=1e-14, atol=0)
    a = np.random.default_rng(3).standard_normal((5, 5))
    assert np.allclose(expm_stack(a) @ expm_stack(-a), np.eye(5), atol=1e-12)
    with pytest.raises(ValueError, match="square"):
        expm_stack(np.zeros((2, 3)))
