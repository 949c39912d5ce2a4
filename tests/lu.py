"""The references' linear solve (tests/reference.py, tests/fivebar/reference.py): mpmath's
``lu_solve`` on lists of mpf."""

from __future__ import annotations

from typing import Any

import mpmath
from mpmath.libmp import fone, fzero, mpf_abs, mpf_add, mpf_div, mpf_gt, mpf_le, mpf_mul, mpf_sum


def lu_solve(A: list[list[Any]], b: list[Any]) -> list[Any]:
    """x with A x = b: ``mpmath.lu_solve``'s algorithm step for step (10 guard bits, its
    row-sum pivoting, its "numerically singular" tolerance) on lists of mpf, with every
    product by an exact zero left out. x - 0·y is x exactly, so x is bit for bit
    mpmath's; the references' matrices are mostly zeros, and mpmath's own matrices spent
    most of the references' solving time indexing them.

    The steps are mpmath's own raw operations (``mpmath.libmp``: ``mpf_mul``, ``mpf_add``,
    ``mpf_div``, ``mpf_sum``) at the working precision and rounding that mpf's operators
    and ``fsum`` use, on the mpf's raw values: the same roundings, without an mpf object
    made for every intermediate."""
    ctx = mpmath.mp
    prec = ctx.prec
    try:
        ctx.prec += 10
        wp, rnd = ctx._prec_rounding
        mpf = ctx.mpf
        M = [[v._mpf_ if type(v) is mpf else ctx.convert(v)._mpf_ for v in row] for row in A]
        y = [v._mpf_ if type(v) is mpf else ctx.convert(v)._mpf_ for v in b]
        n = len(M)
        colmax = fzero  # max over columns of Σ_i |A_ij| (mpmath's tolerance)
        for j in range(n):
            s = mpf_sum([row[j] for row in M], wp, rnd, True)  # fsum(absolute=1)
            if j == 0 or mpf_gt(s, colmax):
                colmax = s
        tol = mpf_abs(mpf_mul(colmax, ctx.eps._mpf_, wp, rnd), wp, rnd)
        p: list[int] = [0] * (n - 1)
        # Σ_{l >= j} |A_kl| of each row (by the row's identity) since it last changed: a
        # row that a step leaves as it is has a zero in that step's column, so its sum
        # from the next column on adds the same nonzero terms, in the same order
        sums: dict[int, Any] = {}
        for j in range(n - 1):
            biggest = fzero
            for k in range(j, n):
                s = sums.get(id(M[k]))
                if s is None:
                    s = mpf_sum([mpf_abs(v, wp, rnd) for v in M[k][j:] if v != fzero], wp, rnd)
                    sums[id(M[k])] = s
                if mpf_le(mpf_abs(s, wp, rnd), tol):
                    raise ZeroDivisionError("matrix is numerically singular")
                if M[k][j] == fzero:
                    continue  # 0 is never above the biggest so far (0 to start)
                current = mpf_mul(mpf_div(fone, s, wp, rnd), mpf_abs(M[k][j], wp, rnd), wp, rnd)
                if mpf_gt(current, biggest):
                    biggest, p[j] = current, k
            if biggest == fzero:  # a column of zeros (mpmath fails on its pivot, None)
                raise ZeroDivisionError("matrix is numerically singular")
            M[j], M[p[j]] = M[p[j]], M[j]
            if mpf_le(mpf_abs(M[j][j], wp, rnd), tol):
                raise ZeroDivisionError("matrix is numerically singular")
            pivot, row_j = M[j][j], M[j]
            for i in range(j + 1, n):
                row = M[i]
                if row[j] == fzero:
                    continue  # a zero factor: the row stays as it is
                del sums[id(row)]  # changed: its sum is made again at the next step
                f = row[j] = mpf_div(row[j], pivot, wp, rnd)
                for k in range(j + 1, n):
                    if row_j[k] != fzero:
                        row[k] = mpf_add(row[k], mpf_mul(f, row_j[k], wp, rnd), wp, rnd, 1)
        if mpf_le(mpf_abs(M[n - 1][n - 1], wp, rnd), tol):
            raise ZeroDivisionError("matrix is numerically singular")
        for k in range(n - 1):  # L y = P b
            y[k], y[p[k]] = y[p[k]], y[k]
        for i in range(1, n):
            for j in range(i):
                if M[i][j] != fzero and y[j] != fzero:
                    y[i] = mpf_add(y[i], mpf_mul(M[i][j], y[j], wp, rnd), wp, rnd, 1)
        x = y  # U x = y
        for i in range(n - 1, -1, -1):
            for j in range(i + 1, n):
                if M[i][j] != fzero and x[j] != fzero:
                    x[i] = mpf_add(x[i], mpf_mul(M[i][j], x[j], wp, rnd), wp, rnd, 1)
            x[i] = mpf_div(x[i], M[i][i], wp, rnd)
        return [ctx.make_mpf(v) for v in x]
    finally:
        ctx.prec = prec
