"""Matrix exponential of a stack of small dense matrices, in NumPy (scaling and squaring).

The switch model's exact propagators are ``expm(A dt)`` of eighteen 9 x 9 mode matrices.
``scipy.linalg.expm`` computes them correctly but, called once per matrix, it goes through
SciPy's own OpenBLAS, whose threads cost milliseconds per 9 x 9 call on a busy two-core
machine (0.56 s of a 0.65 s ``simulate`` call measured on this project's machine; 0.3 ms
with ``OPENBLAS_NUM_THREADS=1``). Batched NumPy products of the whole stack do the same work
in well under a millisecond whatever the thread setting. ``scipy.linalg.expm`` stays the
reference it is tested against (``tests/test_contact_expm.py``).

Algorithm: Higham (2005), "The scaling and squaring method for the matrix exponential
revisited", SIAM J. Matrix Anal. Appl. 26(4) 1179-1193 -- the diagonal Pade approximant of
degree 3, 5, 7, 9 or 13 chosen from the 1-norm, after scaling by ``2**-s``, then ``s``
squarings -- applied to the balanced stack ``D^-1 A D`` (Parlett-Reinsch, powers of two, so
exact in floating point; ``expm(A) = D expm(D^-1 A D) D^-1``). The mode matrices are far from
normal (``[[0, I], [-K/M, -C/M]]`` with ``K/M ~ 1e10 s^-2``): unbalanced, their 1-norm is
thousands of times their spectral radius and the surplus squarings lose six digits; balanced,
the result agrees with ``scipy.linalg.expm`` and a 40-digit mpmath reference to ~1e-15.
One ``D``, one degree and one ``s`` serve the whole stack (from the elementwise largest
magnitudes and the largest norm): the mode matrices share their structure.
"""

from __future__ import annotations

import numpy as np

# theta_m of Higham (2005), Table 2.3: the largest 1-norm for which the degree-m Pade
# approximant is accurate to double precision without scaling
_THETA = ((3, 1.495585217958292e-2), (5, 2.539398330063230e-1), (7, 9.504178996162932e-1),
          (9, 2.097847961257068e0))
_THETA_13 = 5.371920351148152e0
# Pade numerator coefficients b_0..b_m (Higham 2005, Eq. 2.2 / Algorithm 2.3)
_B = {
    3: (120.0, 60.0, 12.0, 1.0),
    5: (30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0),
    7: (17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0),
    9: (17643225600.0, 8821612800.0, 2075673600.0, 302702400.0, 30270240.0, 2162160.0,
        110880.0, 3960.0, 90.0, 1.0),
    13: (64764752532480000.0, 32382376266240000.0, 7771770303897600.0, 1187353796428800.0,
         129060195264000.0, 10559470521600.0, 670442572800.0, 33522128640.0, 1323241920.0,
         40840800.0, 960960.0, 16380.0, 182.0, 1.0),
}


def expm_stack(a: np.ndarray) -> np.ndarray:
    """``expm`` of each matrix of a stack.

    Parameters
    ----------
    a : ndarray, shape (n, k, k) or (k, k)
        Real or complex square matrices.

    Returns
    -------
    ndarray
        Same shape: ``out[i] = expm(a[i])``.
    """
    a = np.asarray(a)
    single = a.ndim == 2
    if single:
        a = a[None]
    if a.ndim != 3 or a.shape[1] != a.shape[2]:
        raise ValueError(f"expm_stack needs square matrices, got shape {a.shape}")
    d = _balance(np.max(np.abs(a), axis=0)) if a.size else np.ones(a.shape[1])
    a = a * (d[None, :] / d[:, None])  # D^-1 A D
    eye = np.broadcast_to(np.eye(a.shape[1], dtype=a.dtype), a.shape)
    norm = float(np.max(np.abs(a).sum(axis=1))) if a.size else 0.0  # largest 1-norm
    s = 0
    for m, theta in _THETA:
        if norm <= theta:
            u, v = _pade_low(a, eye, _B[m])
            break
    else:
        if norm > _THETA_13:
            s = int(np.ceil(np.log2(norm / _THETA_13)))
            a = a / 2.0**s
        u, v = _pade_13(a, eye)
    r = np.linalg.solve(v - u, v + u)
    for _ in range(s):
        r = r @ r
    r = r * (d[:, None] / d[None, :])  # D expm(B) D^-1
    return r[0] if single else r


def _balance(m: np.ndarray, radix: float = 2.0) -> np.ndarray:
    """Diagonal ``d`` (powers of ``radix``) equalising row and column norms of ``D^-1 M D``.

    Parlett & Reinsch (1969), as in EISPACK ``balanc`` / LAPACK ``gebal`` without permutation.
    The sweeps run on Python floats: for the 9 x 9 matrices of the contact model they are
    several times faster than NumPy calls on rows of nine (each call's overhead dominates).
    """
    b = [[float(x) for x in row] for row in np.asarray(m, dtype=float)]
    n = len(b)
    d = [1.0] * n
    for _sweep in range(64):
        converged = True
        for i in range(n):
            c = sum(b[j][i] for j in range(n)) - b[i][i]
            r = sum(b[i]) - b[i][i]
            if c == 0.0 or r == 0.0:
                continue
            s, f = c + r, 1.0
            while c < r / radix:
                f, c = f * radix, c * radix * radix
            while c >= r * radix:
                f, c = f / radix, c / (radix * radix)
            if (c + r) / f < 0.95 * s:  # c is now c0 f^2: new norms c0 f + r / f
                converged = False
                d[i] *= f
                for j in range(n):
                    b[j][i] *= f
                b[i] = [x / f for x in b[i]]
        if converged:
            break
    return np.array(d)


def _pade_low(a: np.ndarray, eye: np.ndarray, b: tuple[float, ...]):
    """Odd and even parts ``U``, ``V`` of the degree-3..9 Pade numerator."""
    a2 = a @ a
    powers = [eye, a2]  # A^0, A^2, A^4, ...
    while 2 * len(powers) < len(b):
        powers.append(powers[-1] @ a2)
    odd = sum(b[2 * k + 1] * p for k, p in enumerate(powers))
    even = sum(b[2 * k] * p for k, p in enumerate(powers))
    return a @ odd, even


def _pade_13(a: np.ndarray, eye: np.ndarray):
    """Odd and even parts ``U``, ``V`` of the degree-13 Pade numerator (Higham 2005)."""
    b = _B[13]
    a2 = a @ a
    a4 = a2 @ a2
    a6 = a2 @ a4
    u = a @ (a6 @ (b[13] * a6 + b[11] * a4 + b[9] * a2)
             + b[7] * a6 + b[5] * a4 + b[3] * a2 + b[1] * eye)
    v = a6 @ (b[12] * a6 + b[10] * a4 + b[8] * a2) + b[6] * a6 + b[4] * a4 + b[2] * a2 \
        + b[0] * eye
    return u, v
