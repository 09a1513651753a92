"""Matrix exponential of a stack of small dense matrices, compiled (scaling and squaring).

The switch model's exact propagators are ``expm(A dt)`` of eighteen 9 x 9 mode matrices.
``scipy.linalg.expm`` computes them correctly but, called once per matrix, it goes through
SciPy's own OpenBLAS, whose threads cost milliseconds per 9 x 9 call on a busy two-core
machine (0.56 s of a 0.65 s ``simulate`` call measured on this project's machine; 0.3 ms
with ``OPENBLAS_NUM_THREADS=1``). Batched NumPy products of the whole stack did the same work
in about 0.2 ms, most of it the per-call cost of NumPy on 9 x 9 operands (a steady point
builds two systems); the same algorithm compiled with numba (plain loops over the stack, no
BLAS) takes about a tenth of that. ``scipy.linalg.expm`` stays the reference it is tested
against (``tests/test_contact_expm.py``).

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
from numba import njit

# theta_m of Higham (2005), Table 2.3: the largest 1-norm for which the degree-m Pade
# approximant is accurate to double precision without scaling
_THETA = np.array([1.495585217958292e-2, 2.539398330063230e-1, 9.504178996162932e-1,
                   2.097847961257068e0])
_DEGREES = np.array([3, 5, 7, 9])
_THETA_13 = 5.371920351148152e0
# Pade numerator coefficients b_0..b_m (Higham 2005, Eq. 2.2 / Algorithm 2.3), one row per
# degree 3, 5, 7, 9, 13, zero-padded
_B = np.zeros((5, 14))
for _row, _coef in enumerate((
    (120.0, 60.0, 12.0, 1.0),
    (30240.0, 15120.0, 3360.0, 420.0, 30.0, 1.0),
    (17297280.0, 8648640.0, 1995840.0, 277200.0, 25200.0, 1512.0, 56.0, 1.0),
    (17643225600.0, 8821612800.0, 2075673600.0, 302702400.0, 30270240.0, 2162160.0,
     110880.0, 3960.0, 90.0, 1.0),
    (64764752532480000.0, 32382376266240000.0, 7771770303897600.0, 1187353796428800.0,
     129060195264000.0, 10559470521600.0, 670442572800.0, 33522128640.0, 1323241920.0,
     40840800.0, 960960.0, 16380.0, 182.0, 1.0),
)):
    _B[_row, :len(_coef)] = _coef


def expm_stack(a: np.ndarray) -> np.ndarray:
    """``expm`` of each matrix of a stack.

    Parameters
    ----------
    a : ndarray, shape (n, k, k) or (k, k)
        Real square matrices.

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
    if np.iscomplexobj(a):
        raise ValueError("expm_stack takes real matrices")
    out = _expm_kernel(np.ascontiguousarray(a, dtype=np.float64), _THETA, _DEGREES,
                       _THETA_13, _B)
    return out[0] if single else out


@njit(cache=True, nogil=True)
def _expm_kernel(a, theta, degrees, theta_13, coef):
    """The stack's exponentials: one ``D``, one degree and one ``s`` for the whole stack (from
    the elementwise largest magnitudes and the largest 1-norm), each matrix in turn."""
    n, k, _ = a.shape
    out = np.empty_like(a)
    if n == 0:
        return out
    big = np.zeros((k, k))
    for i in range(n):
        for r in range(k):
            for c in range(k):
                big[r, c] = max(big[r, c], abs(a[i, r, c]))
    d = _balance(big, 2.0)
    b = np.empty_like(a)  # D^-1 A D
    norm = 0.0
    for i in range(n):
        for r in range(k):
            for c in range(k):
                b[i, r, c] = a[i, r, c] * (d[c] / d[r])
        for c in range(k):
            col = 0.0
            for r in range(k):
                col += abs(b[i, r, c])
            norm = max(norm, col)
    row = 4
    s = 0
    for j in range(theta.size):
        if norm <= theta[j]:
            row = j
            break
    if row == 4 and norm > theta_13:
        s = int(np.ceil(np.log2(norm / theta_13)))
    scale = 2.0 ** -s
    m = degrees[row] if row < 4 else 13
    x = np.empty((k, k))
    u = np.empty((k, k))
    v = np.empty((k, k))
    t1 = np.empty((k, k))
    t2 = np.empty((k, k))
    p2 = np.empty((k, k))
    p4 = np.empty((k, k))
    p6 = np.empty((k, k))
    bc = coef[row]
    for i in range(n):
        for r in range(k):
            for c in range(k):
                x[r, c] = b[i, r, c] * scale
        _matmul(x, x, p2)
        if m == 13:
            _matmul(p2, p2, p4)
            _matmul(p2, p4, p6)
            for r in range(k):
                for c in range(k):
                    t1[r, c] = bc[13] * p6[r, c] + bc[11] * p4[r, c] + bc[9] * p2[r, c]
            _matmul(p6, t1, t2)
            for r in range(k):
                for c in range(k):
                    t2[r, c] += bc[7] * p6[r, c] + bc[5] * p4[r, c] + bc[3] * p2[r, c]
                t2[r, r] += bc[1]
            _matmul(x, t2, u)
            for r in range(k):
                for c in range(k):
                    t1[r, c] = bc[12] * p6[r, c] + bc[10] * p4[r, c] + bc[8] * p2[r, c]
            _matmul(p6, t1, v)
            for r in range(k):
                for c in range(k):
                    v[r, c] += bc[6] * p6[r, c] + bc[4] * p4[r, c] + bc[2] * p2[r, c]
                v[r, r] += bc[0]
        else:
            # odd and even parts: sums of b_(2j+1) A^2j and b_2j A^2j, the odd one times A
            for r in range(k):
                for c in range(k):
                    t1[r, c] = 0.0
                    v[r, c] = 0.0
                t1[r, r] = bc[1]
                v[r, r] = bc[0]
            p4[:, :] = p2
            for j in range(1, (m - 1) // 2 + 1):
                for r in range(k):
                    for c in range(k):
                        t1[r, c] += bc[2 * j + 1] * p4[r, c]
                        v[r, c] += bc[2 * j] * p4[r, c]
                if 2 * j + 2 < m:
                    _matmul(p4, p2, p6)
                    p4[:, :] = p6
            _matmul(x, t1, u)
        for r in range(k):
            for c in range(k):
                t1[r, c] = v[r, c] - u[r, c]
                t2[r, c] = v[r, c] + u[r, c]
        _solve(t1, t2)  # t2 <- (V - U)^-1 (V + U)
        for _ in range(s):
            _matmul(t2, t2, t1)
            t2[:, :] = t1
        for r in range(k):
            for c in range(k):
                out[i, r, c] = t2[r, c] * (d[r] / d[c])  # D expm(B) D^-1
    return out


@njit(cache=True, nogil=True)
def _matmul(x, y, out):
    k = x.shape[0]
    for r in range(k):
        for c in range(k):
            acc = 0.0
            for j in range(k):
                acc += x[r, j] * y[j, c]
            out[r, c] = acc


@njit(cache=True, nogil=True)
def _solve(m, rhs):
    """``rhs <- m^-1 rhs`` by Gaussian elimination with partial pivoting (``m`` destroyed)."""
    k = m.shape[0]
    for col in range(k):
        p = col
        for r in range(col + 1, k):
            if abs(m[r, col]) > abs(m[p, col]):
                p = r
        if p != col:
            for c in range(k):
                m[col, c], m[p, c] = m[p, c], m[col, c]
                rhs[col, c], rhs[p, c] = rhs[p, c], rhs[col, c]
        piv = m[col, col]
        for r in range(col + 1, k):
            f = m[r, col] / piv
            if f != 0.0:
                for c in range(col, k):
                    m[r, c] -= f * m[col, c]
                for c in range(k):
                    rhs[r, c] -= f * rhs[col, c]
    for col in range(k - 1, -1, -1):
        for c in range(k):
            acc = rhs[col, c]
            for j in range(col + 1, k):
                acc -= m[col, j] * rhs[j, c]
            rhs[col, c] = acc / m[col, col]


@njit(cache=True, nogil=True)
def _balance(m, radix):
    """Diagonal ``d`` (powers of ``radix``) equalising row and column norms of ``D^-1 M D``.

    Parlett & Reinsch (1969), as in EISPACK ``balanc`` / LAPACK ``gebal`` without permutation.
    """
    n = m.shape[0]
    b = m.copy()
    d = np.ones(n)
    for _sweep in range(64):
        converged = True
        for i in range(n):
            c = 0.0
            r = 0.0
            for j in range(n):
                if j != i:
                    c += b[j, i]
                    r += b[i, j]
            if c == 0.0 or r == 0.0:
                continue
            s = c + r
            f = 1.0
            while c < r / radix:
                f *= radix
                c *= radix * radix
            while c >= r * radix:
                f /= radix
                c /= radix * radix
            if (c + r) / f < 0.95 * s:  # c is now c0 f^2: new norms c0 f + r / f
                converged = False
                d[i] *= f
                for j in range(n):
                    b[j, i] *= f
                for j in range(n):
                    b[i, j] /= f
        if converged:
            break
    return d
