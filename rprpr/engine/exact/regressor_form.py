"""The efforts of the RPRPR's two actuation schemes in closed form as linear forms in the
links' inertial parameters π (``BASIS``), affine in the end point's acceleration error e:
the regressor of ``docs/robust.md``, for any number type with +, -, × and ÷ (balls and
their jets: ``robust.regressor``; recording balls: ``certified.kernel_gen`` traces it into
the compiled kernel). Its home is beside ``equations.py``, whose equations it writes out."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from . import equations as dyn

# the links' inertial parameters (π above): (link, what), what one of m, mr, J
BASIS = ((2, "mr"), (2, "J"), (3, "m"), (3, "mr"), (3, "J"),
         (4, "mr"), (4, "J"), (5, "m"), (5, "mr"), (5, "J"))  # fmt: skip
# each link's columns of BASIS: (link, m or None, m r, J)
LINKS = tuple(
    (k, BASIS.index((k, "m")) if (k, "m") in BASIS else None,
     BASIS.index((k, "mr")), BASIS.index((k, "J")))
    for k in (2, 3, 4, 5)
)  # fmt: skip


# -- the regressor in closed form, for ball and jet arithmetic ---------------------------
#
# From the equations (``exact.equations``), with π = ``BASIS`` (J_i = m_i r_i² + I_i), per
# leg i (links 2, 3 on leg 1; 4, 5 on leg 2; s, θ its joint values, g the gravity):
#   U_i = M θ'' + N (the θ row) = J_in θ'' + J_out θ'' + (m r)_in g cos θ
#         + m_out (s² θ'' + 2 s s' θ' + g s cos θ) - (m r)_out (2 s θ'' + 2 s' θ' + g cos θ),
#   F_i = M s'' + N (the s row) = m_out (s'' - s θ'² + g sin θ) + (m r)_out θ'²;
# with λ = μ/δ (eqs. 32-33 and the prismatic μ), c = cos(θ1 - θ2), δ = -a1 y/(s1 s2):
#   revolute:  T1 = U1 - (s1/δ)(c F1 + F2),        T2 = U2 + (s2/δ)(F1 + c F2);
#   prismatic: F1' = F1 + (c U1/s1 + U2/s2)/δ,       F2' = F2 - (U1/s1 + c U2/s2)/δ.
# The error e enters only s'' and θ'': ∂s''/∂e = (cos θ, sin θ), ∂θ''/∂e = (-sin θ, cos θ)/s
# (the legs' kinematics), so each column's change per unit e_x, e_y is its s'', θ''
# terms with these in their place. Mathematically the same efforts as ``efforts_of`` at
# the settings (each column a handful of products of the legs' values instead of the
# equations at ten settings and three error parts).


def closed_form(mechanism: Any) -> bool:
    """Whether ``regressor_columns`` holds for ``mechanism``: the RPRPR's own schemes
    (``exact.equations``' implementations, told apart by their ``automatic`` index);
    another registered implementation is evaluated through its own equations."""
    return type(mechanism).__module__ == dyn.__name__ and mechanism.automatic in (0, 1)


def regressor_columns(p: dyn.Params, kin: Sequence[Any], hyp: Any) -> list[list[list[Any]]]:
    """[effort][``BASIS``][e = 0, per unit e_x, e_y]: the efforts' coefficients of π (None:
    0) from the end point's x, ẋ, ẍ, y, ẏ, ÿ ``kin`` (balls, jets; ``p``: a1, g, scheme)."""
    x, xd, xdd, y, yd, ydd = kin
    l1, l2 = p.mechanism.legs(p, x, xd, xdd, y, yd, ydd, hyp)
    parts = []
    for leg_, u in ((l1, x), (l2, x - p.a1)):  # (u, y): the leg's offset, s (cos θ, sin θ)
        s, w = leg_.s, leg_.th_d
        gc = leg_.cos * p.g
        w2 = w * w
        gt = (-leg_.sin / s, leg_.cos / s)  # ∂θ''/∂e
        gs = (leg_.cos, leg_.sin)  # ∂s''/∂e
        parts.append(
            {
                "pr": (gc, None, None),  # (m r)_in: U
                "J": (leg_.th_dd, *gt),  # J_in, J_out: U
                "m": (s * (s * leg_.th_dd + leg_.s_d * w * 2.0 + gc),
                      -y, u),  # m_out: U (s² ∂θ''/∂e = (-s sin θ, s cos θ))
                "mr": (-(s * leg_.th_dd * 2.0 + leg_.s_d * w * 2.0 + gc),
                       leg_.sin * 2.0, leg_.cos * -2.0),  # (m r)_out: U
                "a": (leg_.s_dd - s * w2 + leg_.sin * p.g, *gs),  # m_out: F
                "b": (w2, None, None),  # (m r)_out: F
            }
        )  # fmt: skip
    c = l1.cos * l2.cos + l1.sin * l2.sin
    inv = 1.0 / (y * p.a1)  # δ = -a1 y/(s1 s2)
    U = [{k: parts[i][k] for k in ("pr", "J", "m", "mr")} for i in (0, 1)]
    F = [{"m": parts[i]["a"], "mr": parts[i]["b"]} for i in (0, 1)]
    if p.mechanism.automatic == 0:  # revolute: T1 = U1 + q1 F1 + r1 F2, T2 = U2 + q2 F2 + r2 F1
        k1 = l1.s * l1.s * l2.s * inv  # -s1/δ
        k2 = l1.s * l2.s * l2.s * inv  # -s2/δ
        rows = []
        for i, (q_own, q_other) in enumerate(((k1 * c, k1), (-(k2 * c), -k2))):
            col: dict[tuple[int, str], Any] = {}
            mine, other = 2 * i + 2, 4 - 2 * i
            col[(mine, "mr")] = U[i]["pr"]
            col[(mine, "J")] = U[i]["J"]
            col[(mine + 1, "J")] = U[i]["J"]
            col[(mine + 1, "m")] = _plus(U[i]["m"], _times(F[i]["m"], q_own))
            col[(mine + 1, "mr")] = _plus(U[i]["mr"], _times(F[i]["mr"], q_own))
            col[(other + 1, "m")] = _times(F[1 - i]["m"], q_other)
            col[(other + 1, "mr")] = _times(F[1 - i]["mr"], q_other)
            rows.append(col)
    else:  # prismatic: F_i' = F_i + q_i U_i/s_i + r_i U_other/s_other
        p1 = -(l2.s * inv)  # 1/(s1 δ)
        p2 = -(l1.s * inv)  # 1/(s2 δ)
        rows = []
        for i, (q_own, q_other) in enumerate(((c * p1, p2), (-(c * p2), -p1))):
            col = {}
            mine, other = 2 * i + 2, 4 - 2 * i
            for link, side, qq in ((mine, i, q_own), (other, 1 - i, q_other)):
                col[(link, "mr")] = _times(U[side]["pr"], qq)
                col[(link, "J")] = _times(U[side]["J"], qq)
                col[(link + 1, "J")] = col[(link, "J")]
                col[(link + 1, "m")] = _times(U[side]["m"], qq)
                col[(link + 1, "mr")] = _times(U[side]["mr"], qq)
            col[(mine + 1, "m")] = _plus(F[i]["m"], col[(mine + 1, "m")])
            col[(mine + 1, "mr")] = _plus(F[i]["mr"], col[(mine + 1, "mr")])
            rows.append(col)
    return [[list(col.get(key, (None, None, None))) for key in BASIS] for col in rows]


def _times(v: Sequence[Any], k: Any) -> tuple[Any, ...]:
    return tuple(None if a is None else a * k for a in v)


def _plus(u: Sequence[Any], v: Sequence[Any]) -> tuple[Any, ...]:
    return tuple(a if b is None else b if a is None else a + b for a, b in zip(u, v, strict=True))
