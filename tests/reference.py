"""An independent high-precision reference for the inverse kinematics and dynamics.

Written apart from the engine (it imports nothing from ``rprpr.engine``): mpmath at 60
significant digits and more, straight from the paper's equations:

* x(t) and y(t) = p(x(t)) from the task's exact coefficients; x', x'', y' = p'(x) x',
  y'' = p''(x) x'^2 + p'(x) x'';
* inverse kinematics by the polar decomposition of (u, v) = (x, y) and (x - a1, y):
  θ = atan2(v, u), s = |(u, v)|, cos θ = u/s, sin θ = v/s, and by differentiating
  u = s cos θ, v = s sin θ:
  s' = u' cos θ + v' sin θ, θ' = (v' cos θ - u' sin θ)/s (eqs. 41-42),
  s'' = u'' cos θ + v'' sin θ + s θ'^2, θ'' = (v'' cos θ - u'' sin θ - 2 s' θ')/s;
* M, N of eqs. (7)-(14); λ from eq. (18), (J_u)^T λ = M_u q'' + N_u, a 2x2 system solved
  by Cramer's rule; T from eq. (17), T = M_a q'' + N_a - (J_a)^T λ; δ = det (J_u)^T
  (eq. 29) and δ' = cos(θ1 - θ2)(θ1' - θ2');
* with ``robot.actuation: prismatic``, a direct solve of the four equations (4),
  M q'' + N = Q + J^T λ with Q = (0, F1, 0, F2) and J = ∂Φ/∂q of the loop constraint
  Φ = (s1 cos θ1 - a1 - s2 cos θ2, s1 sin θ1 - s2 sin θ2), for (F1, F2, λ1, λ2) by
  mpmath's LU solver; "T1", "T2" then hold the forces F1, F2 [N] (the efforts);
* ``energy``: the kinetic plus potential energy of links 2-5 from the joint values
  (link 2 about A, link 3 sliding on it with its centre at s1 - r3 from A; the same for
  leg 2), for the power balance Q·q' = dE/dt.

x(t), y(t) and their derivatives are exact (exact rationals at the rational t: gmpy2's
``mpq``, Python fractions where gmpy2 is missing); the working precision starts at 60
digits plus the digits λ = μ/δ loses (-log10 |y|) and grows until evaluations at d and
d + 30 digits agree to 40 digits. At a root of y, λ and T are two-sided limits
(``limit``: ``None`` at a pole). ``reference`` gives θ's principal value;
``theta_branch`` gives θ on its continuous branch, the crossings of the legs' branch cuts
found by isolating the real roots of y(t) exactly (Sturm sequences over fractions).

Each value is computed once per task and time in a test process (``_reference``), the
joint values apart from the dynamics (``_kinematics``, ``_dynamics``: a box of link
parameters shares the first), each robot's parameters once per precision.
"""

from __future__ import annotations

from fractions import Fraction
from functools import lru_cache
from typing import Any

import mpmath
from flint import fmpq
from mpmath.libmp import fone, mpf_abs, mpf_add, mpf_gt, mpf_mul, mpf_sub

from rprpr.model.task import Task

from .lu import lu_solve

Rational: Any = Fraction  # exact rationals: gmpy2's in C (mpmath runs on it too), the same
try:  # values as Fraction's, where it is installed (the test extra installs it)
    from gmpy2 import mpq

    Rational = mpq
except ImportError:  # pragma: no cover
    pass

KEYS = (
    "x", "y", "x_dot", "y_dot", "x_ddot", "y_ddot", "theta1", "s1", "theta2", "s2",
    "theta1_dot", "s1_dot", "theta2_dot", "s2_dot", "theta1_ddot", "s1_ddot",
    "theta2_ddot", "s2_ddot", "delta", "delta_dot", "lambda1", "lambda2", "T1", "T2",
)  # fmt: skip


def _mpf(q: Any) -> Any:
    if isinstance(q, fmpq):
        return mpmath.mpf(int(q.p)) / int(q.q)
    if isinstance(q, (Fraction, Rational)):
        return mpmath.mpf(int(q.numerator)) / int(q.denominator)
    return mpmath.mpf(q)


def _poly(coeffs: tuple[Any, ...], x: Any) -> tuple[Any, Any, Any]:
    """p(x), p'(x), p''(x) by Horner's scheme (exact in rationals)."""
    v = d1 = d2 = Rational(0)
    for c in reversed(coeffs):
        d2 = d2 * x + 2 * d1
        d1 = d1 * x + v
        v = v * x + c
    return v, d1, d2


def _fractions(p: Any) -> tuple[Any, ...]:
    """The coefficients of the fmpq_poly p, lowest degree first, as exact rationals."""
    return tuple(Rational(int(c.p), int(c.q)) for c in p.coeffs())


def _motion(task: Task, t: Fraction) -> tuple[Any, ...]:
    """x, x', x'', y, y', y'' at the rational time t, exactly (rationals)."""
    key = _key(task)
    return _motion_of(key[0], key[1], t)


@lru_cache(maxsize=16384)
def _motion_of(xc: tuple[Any, ...], pc: tuple[Any, ...], t: Fraction) -> tuple[Any, ...]:
    x, xd, xdd = _poly(xc, Rational(t))
    p, p1, p2 = _poly(pc, x)
    return x, xd, xdd, p, p1 * xd, p2 * xd * xd + p1 * xdd


_CONSTANTS: dict[tuple[int, int], tuple[Any, tuple[Any, ...]]] = {}


def _constants(r: Any) -> tuple[Any, ...]:
    """The robot's parameters as mpf at the working precision (each rounded once, as
    ``_mpf`` rounds it), and the sums and products of them alone that ``_evaluate`` forms
    first (the same operations in the same order: the same values), once per robot object
    (robots are frozen; each is kept beside its values, so its id names it alone) and
    precision."""
    known = _CONSTANTS.get((id(r), mpmath.mp.prec))
    if known is not None and known[0] is r:
        return known[1]
    L = r.links
    a1, g = _mpf(r.a1), _mpf(r.gravity)
    m2, I2, r2 = _mpf(L[2].mass), _mpf(L[2].inertia), _mpf(L[2].r)
    m3, I3, r3 = _mpf(L[3].mass), _mpf(L[3].inertia), _mpf(L[3].r)
    m4, I4, r4 = _mpf(L[4].mass), _mpf(L[4].inertia), _mpf(L[4].r)
    m5, I5, r5 = _mpf(L[5].mass), _mpf(L[5].inertia), _mpf(L[5].r)
    out = (
        a1, g, m3, I3, r3, m5, I5, r5,
        m2 * r2**2 + I2, m4 * r4**2 + I4,  # the constant heads of M11 and M33
        m2 * r2, m4 * r4,  # of N1 and N3
    )  # fmt: skip
    if len(_CONSTANTS) > 4096:  # robots made one per corner of a box: keep it bounded
        _CONSTANTS.clear()
    _CONSTANTS[id(r), mpmath.mp.prec] = (r, out)
    return out


def _evaluate(task: Task, motion: tuple[Any, ...], upto_delta: bool = False) -> dict[str, Any]:
    """Every quantity from the exact motion at one time, at the current precision (with
    ``upto_delta``, the kinematics and δ, δ' only)."""
    kin, legs = _kinematics(task.robot, motion)
    return kin if legs is None or upto_delta else _dynamics(task.robot, kin, legs)


def _kinematics(r: Any, motion: tuple[Any, ...], rates: bool = True) -> tuple[dict[str, Any], Any]:
    """The joint values, δ and δ' from the exact motion at one time (the robot's a1 alone
    read), and what ``_dynamics`` reads of them (None where E is at A or B). Without
    ``rates``: x, y, s1, s2 and δ alone."""
    a1 = _constants(r)[0]
    x, xd, xdd, y, yd, ydd = (_mpf(v) for v in motion)
    out = {"x": x, "y": y, "x_dot": xd, "y_dot": yd, "x_ddot": xdd, "y_ddot": ydd}
    if not rates:
        out = {"x": x, "y": y}
    legs: list[Any] = []
    for u, name in ((x, "1"), (x - a1, "2")):
        s = mpmath.sqrt(u * u + y * y)
        out[f"s{name}"] = s
        if s == 0:  # E at A or B: this leg's angle and rates are undefined
            legs.append(None)
            continue
        c, sn = u / s, y / s  # cos θ, sin θ of the polar decomposition (exact at y = 0)
        if not rates:
            legs.append((None,) * 6 + (c, sn))
            continue
        th = mpmath.atan2(y, u)
        s_d = xd * c + yd * sn
        th_d = (yd * c - xd * sn) / s
        s_dd = xdd * c + ydd * sn + s * th_d**2
        th_dd = (ydd * c - xdd * sn - 2 * s_d * th_d) / s
        out.update({
            f"theta{name}": th, f"s{name}": s, f"theta{name}_dot": th_d,
            f"s{name}_dot": s_d, f"theta{name}_ddot": th_dd, f"s{name}_ddot": s_dd,
        })  # fmt: skip
        legs.append((th, s, s_d, th_d, s_dd, th_dd, c, sn))
    if None in legs:
        return out, None
    (*_, th1d, _, _, c1, sn1), (*_, th2d, _, _, c2, sn2) = legs
    # (J_u)^T of eq. (24) transposed; rows of eq. (18)
    A = [[c1, sn1], [-c2, -sn2]]
    delta = A[0][0] * A[1][1] - A[0][1] * A[1][0]  # (29)
    out["delta"] = delta
    if rates:
        out["delta_dot"] = (c1 * c2 + sn1 * sn2) * (th1d - th2d)  # cos(θ1 - θ2)(θ1' - θ2')
    return out, (legs, A, delta)


def _dynamics(r: Any, kin: dict[str, Any], legs: Any) -> dict[str, Any]:
    """``kin`` (left as it is) with λ and T of the robot ``r`` (its links, gravity and
    actuation), from ``_kinematics``'s values at the same precision: the kinematics are
    the same for every robot of the same a1 (the corners of a box of links)."""
    (legs, A, delta) = legs
    (_, s1, s1d, th1d, s1dd, th1dd, c1, sn1), (_, s2, s2d, th2d, s2dd, th2dd, c2, sn2) = legs
    out = dict(kin)
    # the parameters, with M11's m2 r2² + I2 (M11_2), M33's m4 r4² + I4 (M33_4), N1's
    # m2 r2 and N3's m4 r4
    _, g, m3, I3, r3, m5, I5, r5, M11_2, M33_4, m2r2, m4r4 = _constants(r)
    M11 = M11_2 + m3 * (s1 - r3) ** 2 + I3  # (7): m2 r2² + I2 + m3 (s1 - r3)² + I3
    M22 = m3  # (8)
    M33 = M33_4 + m5 * (s2 - r5) ** 2 + I5  # (9)
    M44 = m5  # (10)
    N1 = 2 * m3 * s1d * th1d * (s1 - r3) + (m2r2 + m3 * (s1 - r3)) * g * c1
    N2 = -m3 * (s1 - r3) * th1d**2 + m3 * g * sn1  # (12)
    N3 = 2 * m5 * s2d * th2d * (s2 - r5) + (m4r4 + m5 * (s2 - r5)) * g * c2
    N4 = -m5 * (s2 - r5) * th2d**2 + m5 * g * sn2  # (14)
    b = [M22 * s1dd + N2, M44 * s2dd + N4]
    if delta == 0:
        out["lambda1"] = out["lambda2"] = out["T1"] = out["T2"] = None
        return out
    if r.actuation == "prismatic":
        rhs = [M11 * th1dd + N1, M22 * s1dd + N2, M33 * th2dd + N3, M44 * s2dd + N4]
        # J = dΦ/dq, rows Φ_x, Φ_y; columns θ1, s1, θ2, s2
        J = [[-s1 * sn1, c1, s2 * sn2, -c2], [s1 * c1, sn1, -s2 * c2, -sn2]]
        Q = [[0, 0], [1, 0], [0, 0], [0, 1]]  # ∂Q/∂(F1, F2)
        A4 = [[*Q[i], J[0][i], J[1][i]] for i in range(4)]
        F1, F2, lam1, lam2 = lu_solve(A4, rhs)
        out.update(lambda1=lam1, lambda2=lam2, T1=F1, T2=F2)
        return out
    lam1 = (b[0] * A[1][1] - A[0][1] * b[1]) / delta
    lam2 = (A[0][0] * b[1] - b[0] * A[1][0]) / delta
    # (17): T = M_a q'' + N_a - (J_a)^T λ, J_a of eq. (23)
    Ja = [[-s1 * sn1, s2 * sn2], [s1 * c1, -s2 * c2]]
    out["lambda1"], out["lambda2"] = lam1, lam2
    out["T1"] = M11 * th1dd + N1 - (Ja[0][0] * lam1 + Ja[1][0] * lam2)
    out["T2"] = M33 * th2dd + N3 - (Ja[0][1] * lam1 + Ja[1][1] * lam2)
    return out


def energy(task: Task, t: Any) -> Any:
    """The kinetic plus potential energy of links 2-5 at the time t [J] (mpf)."""
    r = task.robot
    L = r.links
    g = _mpf(r.gravity)
    q = reference(task, t)
    total = mpmath.mpf(0)
    for i, (inner, outer) in enumerate(((2, 3), (4, 5)), start=1):
        m_in, I_in, r_in = (_mpf(v) for v in (L[inner].mass, L[inner].inertia, L[inner].r))
        m_out, I_out, r_out = (_mpf(v) for v in (L[outer].mass, L[outer].inertia, L[outer].r))
        th, s, th_d, s_d = q[f"theta{i}"], q[f"s{i}"], q[f"theta{i}_dot"], q[f"s{i}_dot"]
        d = s - r_out  # link `outer`'s centre from the base joint along the leg
        kinetic = (m_in * r_in**2 + I_in + I_out) * th_d**2 / 2
        kinetic += m_out * (s_d**2 + d**2 * th_d**2) / 2
        potential = g * (m_in * r_in + m_out * d) * mpmath.sin(th)
        total += kinetic + potential
    return total


_TOLERANCE: dict[tuple[int, int], Any] = {}


def _agree(a: dict[str, Any], b: dict[str, Any], digits: int) -> bool:
    """|u - v| <= 10^-digits (1 + |v|) for every key, u from ``a`` and v from ``b``, at the
    working precision: the operations of ``abs(u - v) > tol * (1 + abs(v))`` on mpf,
    done by mpmath's own functions on the raw values (the same roundings: the same
    answer, without an mpf made for each intermediate)."""
    prec, rnd = mpmath.mp._prec_rounding
    tol = _TOLERANCE.get((digits, prec))
    if tol is None:
        tol = _TOLERANCE[digits, prec] = (mpmath.mpf(10) ** -digits)._mpf_
    for k in KEYS:
        u, v = a.get(k), b.get(k)
        if (u is None) != (v is None):
            return False
        if v is None:
            continue
        gap = mpf_abs(mpf_sub(u._mpf_, v._mpf_, prec, rnd), prec, rnd)
        if mpf_gt(gap, mpf_mul(tol, mpf_add(fone, mpf_abs(v._mpf_, prec, rnd), prec, rnd),
                               prec, rnd)):  # fmt: skip
            return False
    return True


def reference(task: Task, t: Any, dps: int = 60) -> dict[str, Any]:
    """Every quantity at the time t (float, fmpq or Fraction, taken exactly): mpf values,
    None where undefined (E at A or B: the leg's angle and rates, δ, λ, T; at a root of
    y, λ and T: see ``limit``). Computed once per task and time in a test process (the
    same values, a new dict on every call)."""
    tq = Fraction(int(t.p), int(t.q)) if isinstance(t, fmpq) else Fraction(t)
    return dict(_reference(_key(task), tq, dps, False))


def delta(task: Task, t: Any, dps: int = 60) -> Any:
    """``reference(task, t)["delta"]`` alone: δ (eq. 29) by the same formulas, to the same
    agreement (40 digits between d and d + 30 digits), without the angles, the rates and
    the dynamics."""
    tq = Fraction(int(t.p), int(t.q)) if isinstance(t, fmpq) else Fraction(t)
    return _reference(_key(task), tq, dps, True)["delta"]


_TASK_OF: dict[tuple[Any, ...], Task] = {}
_KEY_OF: dict[int, tuple[Task, tuple[Any, ...]]] = {}


def _key(task: Task) -> tuple[Any, ...]:
    """Everything ``_motion`` and ``_evaluate`` read of a task, as a hashable value (tasks
    with the same key have the same reference values); once per task object (tasks are
    frozen, and each is kept here beside its key, so its id names it alone)."""
    known = _KEY_OF.get(id(task))
    if known is not None and known[0] is task:
        return known[1]
    r = task.robot
    links = tuple((i, str(k.mass), str(k.inertia), str(k.r)) for i, k in sorted(r.links.items()))
    key = (
        _fractions(task.x_of_t), _fractions(task.path),
        str(r.a1), str(r.gravity), r.actuation, links,
    )  # fmt: skip
    _TASK_OF.setdefault(key, task)
    if len(_KEY_OF) > 4096:
        _KEY_OF.clear()
    _KEY_OF[id(task)] = (task, key)
    return key


@lru_cache(maxsize=16384)
def _reference(key: tuple[Any, ...], tq: Fraction, dps: int, delta_only: bool) -> dict[str, Any]:
    """``reference`` (or x, y, s1, s2 and δ alone) of the task of ``key``; callers copy the
    dict."""
    task = _TASK_OF[key]
    motion = _motion_of(key[0], key[1], tq)
    y = motion[3]
    # λ = μ/δ loses about -log10 |y| digits to cancellation: start above that
    lost = (y.denominator.bit_length() - abs(y.numerator).bit_length()) * 0.30103 if y else 0
    d = dps + max(0, int(lost))

    def values() -> dict[str, Any]:
        return _kinematics(task.robot, motion, False)[0] if delta_only else _evaluate(task, motion)

    while True:
        with mpmath.workdps(d):
            lo = values()
        with mpmath.workdps(d + 30):
            hi = values()
        if _agree(lo, hi, 40) or d > 20000:
            return {k: hi.get(k) for k in KEYS}
        d *= 2


def limit(task: Task, ts: Any, dps: int = 60) -> dict[str, Any] | None:
    """λ1, λ2, T1, T2 in the limit t -> ts (an exact root of y), from both sides at
    ε = 10^-25 and 10^-35: None when the sides part or the values grow (a pole)."""
    ts = Fraction(int(ts.p), int(ts.q)) if isinstance(ts, fmpq) else Fraction(ts)
    names = ("lambda1", "lambda2", "T1", "T2")
    avgs, gaps = [], []
    for k in (25, 35):
        eps = Fraction(1, 10**k)
        sides = [reference(task, ts + sgn * eps, dps) for sgn in (-1, 1)]
        avgs.append({n: (sides[0][n] + sides[1][n]) / 2 for n in names})
        gaps.append({n: abs(sides[0][n] - sides[1][n]) for n in names})
    tol = mpmath.mpf(10) ** -18
    settled = all(abs(avgs[0][n] - avgs[1][n]) < tol * (1 + abs(avgs[1][n])) for n in names)
    close = all(gaps[1][n] < tol * (1 + abs(avgs[1][n])) for n in names)  # an odd pole
    return avgs[1] if settled and close else None


def limit_of(task: Task, ts: Any, name: str) -> Any:
    """One quantity's two-sided limit at ts (for λ1, bounded even at a pole of λ2)."""
    ts = Fraction(int(ts.p), int(ts.q)) if isinstance(ts, fmpq) else Fraction(ts)
    eps = Fraction(1, 10**35)
    sides = [reference(task, ts + sgn * eps)[name] for sgn in (-1, 1)]
    return (sides[0] + sides[1]) / 2


# -- θ on its continuous branch ----------------------------------------------------------
# θ_i(t) = atan2(y, u_i) + 2π n(t): the principal angle moved by 2π at each time r < t at
# which y changes sign on the far side of the leg's base joint (u_i(r) < 0, its branch
# cut); exactly on the cut, the limit from the left (the motion's polynomials extend
# below t = 0, so this holds at t = 0 too). The roots of y(t) are isolated exactly here,
# with Sturm sequences over Python fractions (nothing shared with the engine's own root
# finding).

Poly = list[Fraction]  # coefficients, lowest degree first, no trailing zeros


def _trim(p: Poly) -> Poly:
    while p and p[-1] == 0:
        p = p[:-1]
    return p


def _mul(p: Poly, q: Poly) -> Poly:
    if not p or not q:
        return []
    out = [Fraction(0)] * (len(p) + len(q) - 1)
    for i, a in enumerate(p):
        for j, b in enumerate(q):
            out[i + j] += a * b
    return _trim(out)


def _add(p: Poly, q: Poly) -> Poly:
    n = max(len(p), len(q))
    return _trim([(p[i] if i < len(p) else 0) + (q[i] if i < len(q) else 0) for i in range(n)])


def _compose(p: Poly, q: Poly) -> Poly:
    """p(q(t)) by Horner."""
    out: Poly = []
    for c in reversed(p):
        out = _add(_mul(out, q), [c])
    return out


def _diff(p: Poly) -> Poly:
    return _trim([k * c for k, c in enumerate(p)][1:])


def _rem(p: Poly, q: Poly) -> Poly:
    p = list(p)
    while len(p) >= len(q):
        f = p[-1] / q[-1]
        shift = len(p) - len(q)
        for i, c in enumerate(q):
            p[shift + i] -= f * c
        p = _trim(p[:-1])
    return p


def _quo(p: Poly, q: Poly) -> Poly:
    p, out = list(p), [Fraction(0)] * max(len(p) - len(q) + 1, 0)
    while len(p) >= len(q):
        f = p[-1] / q[-1]
        shift = len(p) - len(q)
        out[shift] = f
        for i, c in enumerate(q):
            p[shift + i] -= f * c
        p = _trim(p[:-1])
    return _trim(out)


def _gcd(p: Poly, q: Poly) -> Poly:
    while q:
        p, q = q, _rem(p, q)
    return [c / p[-1] for c in p]


def _val(p: Poly, t: Fraction) -> Fraction:
    v = Fraction(0)
    for c in reversed(p):
        v = v * t + c
    return v


def _sign(v: Fraction) -> int:
    return (v > 0) - (v < 0)


def _sturm(p: Poly) -> list[Poly]:
    seq = [p, _diff(p)]
    while seq[-1]:
        seq.append([-c for c in _rem(seq[-2], seq[-1])])
    return seq[:-1]


def _roots_in(seq: list[Poly], a: Fraction, b: Fraction) -> int:
    """The number of distinct roots in (a, b] of the square-free seq[0]."""

    def changes(t: Fraction) -> int:
        signs = [s for s in (_sign(_val(p, t)) for p in seq) if s]
        return sum(1 for i in range(1, len(signs)) if signs[i] != signs[i - 1])

    return changes(a) - changes(b)


def _sqf(p: Poly) -> Poly:
    return _quo(p, _gcd(p, _diff(p))) if len(p) > 1 else p


def _isolate(sqf: Poly, lo: Fraction, hi: Fraction) -> list[tuple[Fraction, Fraction]]:
    """The roots of the square-free ``sqf`` in [lo, hi]: (r, r) when exact, else (a, b)
    with one root inside, sqf(a) sqf(b) != 0."""
    seq = _sturm(sqf)
    out = [(lo, lo)] if _val(sqf, lo) == 0 else []
    todo = [(lo, hi)]
    while todo:
        a, b = todo.pop()
        n = _roots_in(seq, a, b)
        if n == 1 and _val(sqf, b) == 0:
            out.append((b, b))
        elif n == 1 and _val(sqf, a) != 0:
            out.append((a, b))
        elif n:
            m = (a + b) / 2
            todo += [(a, m), (m, b)]
    return sorted(out)


def _cut_roots(task: Task, leg: int) -> list[tuple[Fraction, Fraction, int, bool]]:
    """The roots of y(t) in [0, t_f] on the leg's cut: (a, b, sign of y after, crossing?)
    with the root equal to a == b, or the only root of y in (a, b)."""
    xc = [Fraction(int(c.p), int(c.q)) for c in task.x_of_t.coeffs()]
    pc = [Fraction(int(c.p), int(c.q)) for c in task.path.coeffs()]
    a1 = Fraction(int(task.robot.a1.p), int(task.robot.a1.q))
    y = _compose(pc, xc)
    u = _add(xc, [-a1]) if leg == 2 else xc
    tf = Fraction(int(task.duration.p), int(task.duration.q))
    if len(y) < 2:
        return []
    sy = _sqf(y)
    g = _gcd(y, u) if len(u) > 1 else [Fraction(1)]
    gseq = _sturm(_sqf(g)) if len(g) > 1 else None
    useq = _sturm(_sqf(u)) if len(u) > 1 else None
    out = []
    for a, b in _isolate(sy, Fraction(0), tf):
        if a == b:
            if _val(u, a) >= 0:
                continue
            d, m = y, 0
            while _val(d, a) == 0:
                d, m = _diff(d), m + 1
            out.append((a, b, _sign(_val(d, a)), m % 2 == 1))
            continue
        if gseq is not None and _roots_in(gseq, a, b):
            continue  # y and u vanish together: E at the base joint, not on its cut
        while useq is not None and (_roots_in(useq, a, b) or _val(u, a) == 0):
            m = (a + b) / 2
            if _val(sy, m) == 0:
                a = b = m
                break
            a, b = (a, m) if _sign(_val(sy, m)) != _sign(_val(sy, a)) else (m, b)
        if _val(u, a) >= 0:
            continue
        if a == b:
            d, k = y, 0
            while _val(d, a) == 0:
                d, k = _diff(d), k + 1
            out.append((a, b, _sign(_val(d, a)), k % 2 == 1))
            continue
        before, after = _sign(_val(y, a)), _sign(_val(y, b))
        out.append((a, b, after, before != after))
    return out


_CUTS: dict[Any, tuple[Poly, list[tuple[Fraction, Fraction, int, bool]]]] = {}


def theta_branch(task: Task, t: Any) -> tuple[Any, Any]:
    """θ1 and θ2 at the time t on their continuous branches (mpf; None where E is at the
    leg's base joint)."""
    tq = Fraction(int(t.p), int(t.q)) if isinstance(t, fmpq) else Fraction(t)
    x, _, _, y, _, _ = _motion(task, tq)
    a1 = Fraction(int(task.robot.a1.p), int(task.robot.a1.q))
    return _theta(task, tq, x, y, 1), _theta(task, tq, x - a1, y, 2)


def _theta(task: Task, tq: Fraction, u: Fraction, y: Fraction, leg: int) -> Any:
    key = (str(task.x_of_t), str(task.path), str(task.robot.a1), str(task.duration), leg)
    if key not in _CUTS:
        xc = [Fraction(int(c.p), int(c.q)) for c in task.x_of_t.coeffs()]
        pc = [Fraction(int(c.p), int(c.q)) for c in task.path.coeffs()]
        _CUTS[key] = (_sqf(_compose(pc, xc)), _cut_roots(task, leg))
    sy, cuts = _CUTS[key]
    if u == 0 and y == 0:
        return None
    turns, on_cut = 0, 0
    for a, b, after, crossing in cuts:
        if a == b or tq <= a or tq >= b:
            at, past = tq == a == b, tq > a if a == b else tq >= b
        else:
            v = _val(sy, tq)
            at, past = v == 0, v != 0 and _sign(v) != _sign(_val(sy, a))
        if at:  # on the cut: the limit from the left, ±π with the sign of y before
            on_cut = -after if crossing else after
        if past and crossing:
            turns -= after
    with mpmath.workdps(60):
        principal = mpmath.pi * on_cut if on_cut else mpmath.atan2(_mpf(y), _mpf(u))
        return principal + 2 * mpmath.pi * turns
