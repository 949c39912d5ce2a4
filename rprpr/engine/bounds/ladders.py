"""Where the first partition of [0, t_f] is cut finer: about the times where |T1| or
|T2| looks largest in double precision (``_ladders``). The doubles only choose where to
cut: every bound still comes from the ball pass. ``Ladders`` is a part of
``envelope.Envelope``."""

from __future__ import annotations

import numpy as np
from flint import fmpq_poly

from ...model.numbers import to_float
from ..certified.balls import polyval
from ..certified.motion import CertifiedMotion
from ..certified.through import Through
from ..exact import equations as dyn

LADDER_GRID = 2049  # doubles evaluated to guess where |T| peaks (``_ladders``)
LADDER_SPLIT = 64  # about a guessed maximum: boxes of 1/LADDER_SPLIT of the uniform width
LADDER_CORE = 32  # ... this many on either side, then boxes growing by
LADDER_RATIO = 1.15  # ... this factor
LADDER_REACH = 8  # ... out to this many uniform widths


class Ladders:
    """Where to cut the first partition finer: about the likely maxima of |T|, for
    ``Envelope`` (a part of it: what it reads of the envelope is declared here)."""

    motion: CertifiedMotion
    tf: float
    t_last: float
    throughs: list[Through]

    def _ladders(self, h: float) -> np.ndarray:
        """Cuts about the times t* where |T1| or |T2| looks largest (the maxima of a
        double-precision evaluation on LADDER_GRID points, not within t_f/64 of an
        instant, refined by a parabola): LADDER_CORE boxes of h/LADDER_SPLIT on either
        side (h the uniform width), then boxes growing by LADDER_RATIO out to
        LADDER_REACH h. About a maximum, the mean-value form bounds |T| over a box of
        width w within ~C w² of the maximum (C: the enclosure of T' over the box, wider
        than |T''| w), and a box at a distance r from it below the maximum when w is a
        small fraction of r: the passes over the corpus of bench_many fall by a fifth
        (often the first one certifies the peak). The doubles only choose where to cut:
        every bound still comes from the ball pass (a wrong guess costs another pass,
        never a wrong value)."""
        if not self.tf > 0:
            return np.zeros(0)
        t = np.linspace(0.0, self.t_last, LADDER_GRID)
        with np.errstate(all="ignore"):
            T = np.abs(self._float_torques(t))
        T[~np.isfinite(T)] = -1.0
        for e in [e for _, e in self.motion.instants] + [th.e for th in self.throughs]:
            T[:, np.abs(t - e.hi) <= self.tf / 64] = -1.0  # the doubles cancel near t_s
        fine = h / LADDER_SPLIT
        core = fine * np.arange(1, LADDER_CORE + 1)
        far = core[-1] * LADDER_RATIO ** np.arange(1, 64)
        steps = np.concatenate([core, far[far < LADDER_REACH * h]])
        cuts = []
        for row in T:
            j = int(np.argmax(row))
            if not row[j] > 0:
                continue
            c = t[j]
            if 0 < j < len(t) - 1:  # the parabola through the three samples about the max
                a, b, e = row[j - 1], row[j], row[j + 1]
                den = a - 2 * b + e
                if den < 0:
                    c = t[j] + 0.5 * (a - e) / den * (t[1] - t[0])
            cuts.append(np.concatenate([[c], c - steps, c + steps]))
        if not cuts:
            return np.zeros(0)
        out = np.concatenate(cuts)
        return out[(out > 0.0) & (out < self.t_last)]

    def _float_torques(self, t: np.ndarray) -> np.ndarray:
        """T1, T2 (rows) at the times t in double precision, from the same formulas
        (``equations``) on the recentred polynomials: a guide for ``_ladders``, no bound."""
        m, traj = self.motion, self.motion.traj

        def values(p: fmpq_poly, at: np.ndarray) -> list[np.ndarray]:
            d1 = p.derivative()
            return [polyval(at, [to_float(c) for c in q.coeffs()] or [0.0])
                    for q in (p, d1, d1.derivative())]  # fmt: skip

        x, xd, xdd = values(traj.x, t)
        if traj.path is not None:
            q, q1, q2 = values(m.recentred, x - to_float(m.center))
            y, yd, ydd = q, q1 * xd, q2 * xd * xd + q1 * xdd
        else:
            y, yd, ydd = values(m.recentred, t - to_float(m.t_center))
        a1 = to_float(traj.a1)
        l1 = dyn.leg(x, xd, xdd, y, yd, ydd, np.hypot)
        l2 = dyn.leg(x - a1, xd, xdd, y, yd, ydd, np.hypot)
        d = dyn.dynamics(l1, l2, dyn.Params.of(m.robot, to_float))
        return np.array(dyn.efforts(d, d.mu1 / d.delta, d.mu2 / d.delta))
