"""The references' linear solve (tests/reference.py, tests/fivebar/reference.py): mpmath's
``lu_solve`` on lists of mpf."""

from __future__ import annotations

from typing import Any

import mpmath


def lu_solve(A: list[list[Any]], b: list[Any]) -> list[Any]:
    """x with A x = b: ``mpmath.lu_solve``'s algorithm step for step (10 guard bits, its
    row-sum pivoting, its "numerically singular" tolerance) on lists of mpf, with every
    product by an exact zero left out. x - 0·y is x exactly, so x is bit for bit
    mpmath's; the references' matrices are mostly zeros, and mpmath's own matrices spent
    most of the references' solving time indexing them."""
    ctx = mpmath.mp
    prec = ctx.prec
    try:
        ctx.prec += 10
        A = [[ctx.convert(v) for v in row] for row in A]
        b = [ctx.convert(v) for v in b]
        n = len(A)
        tol = abs(max(ctx.fsum((A[i][j] for i in range(n)), absolute=1) for j in range(n))
                  * ctx.eps)  # fmt: skip
        p: list[int] = [0] * (n - 1)
        for j in range(n - 1):
            biggest: Any = 0
            for k in range(j, n):
                s = ctx.fsum([abs(v) for v in A[k][j:] if v])  # zeros add nothing
                if abs(s) <= tol:
                    raise ZeroDivisionError("matrix is numerically singular")
                if not A[k][j]:
                    continue  # 0 is never above the biggest so far (0 to start)
                current = 1 / s * abs(A[k][j])
                if current > biggest:
                    biggest, p[j] = current, k
            if biggest == 0:  # a column of zeros (mpmath fails on its pivot, None)
                raise ZeroDivisionError("matrix is numerically singular")
            A[j], A[p[j]] = A[p[j]], A[j]
            if abs(A[j][j]) <= tol:
                raise ZeroDivisionError("matrix is numerically singular")
            pivot, row_j = A[j][j], A[j]
            for i in range(j + 1, n):
                row = A[i]
                if not row[j]:
                    continue  # a zero factor: the row stays as it is
                row[j] /= pivot
                f = row[j]
                for k in range(j + 1, n):
                    if row_j[k]:
                        row[k] -= f * row_j[k]
        if abs(A[n - 1][n - 1]) <= tol:
            raise ZeroDivisionError("matrix is numerically singular")
        for k in range(n - 1):  # L y = P b
            b[k], b[p[k]] = b[p[k]], b[k]
        for i in range(1, n):
            for j in range(i):
                if A[i][j] and b[j]:
                    b[i] -= A[i][j] * b[j]
        x = b  # U x = y
        for i in range(n - 1, -1, -1):
            for j in range(i + 1, n):
                if A[i][j] and x[j]:
                    x[i] -= A[i][j] * x[j]
            x[i] /= A[i][i]
        return x
    finally:
        ctx.prec = prec
