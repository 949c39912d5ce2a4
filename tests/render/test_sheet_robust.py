"""The audit sheet's torque panel with declared uncertainty: the band every effort the box
allows lies in, about each singular instant, and the proven saturation window shaded.

The band is checked against the independent mpmath reference (``tests/reference.py``):
at times inside it, the reference's T1, T2 at every corner of the box lie in the band.
"""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.render import sheet as P
from tests.engine.robust.test_windows import P2, _evaluate, _task_with, _u
from tests.engine.robust.test_worst import _links

Q = Fraction


def test_the_band_holds_every_corner_and_the_window_is_shaded() -> None:
    task = load_task(P2)  # its own limit: 300 N m
    u = _u({3: (Q(1, 20), Q(1, 20), Q(0)), 5: (Q(1, 20), Q(1, 20), Q(0))}, Q(1, 100))
    result = audit(task, samples=101, uncertainty=u)
    fig = P.render([P.motion(result, "p2.yaml")], ["torques"])
    ax = next(a for a in fig.get_axes() if a.get_gid() == "panel-torques")
    by = {a.get_gid(): a for a in ax.get_children() if a.get_gid()}
    (r,) = result.robust
    assert r.span is not None
    shade = by["torques-window-0-0"]  # a Rectangle in data x
    assert shade.get_x() == pytest.approx(r.span[0], abs=1e-12)
    assert shade.get_x() + shade.get_width() == pytest.approx(r.span[1], abs=1e-12)
    corners = [
        (links, e)
        for links in _links(task, u)
        for e in [
            (a, b)
            for a in (-u.acceleration, u.acceleration)
            for b in (-u.acceleration, u.acceleration)
        ]
    ]
    lo, hi = ax.get_ylim()
    checked = 0
    for name in ("T1", "T2"):
        band = by[f"torques-band-0-0-{name}"]
        verts = np.concatenate([p.vertices for p in band.get_paths()])
        for near in (2.25, 2.75):  # a time of the band's own grid, away from t_s
            x = verts[np.argmin(np.abs(verts[:, 0] - near)), 0]
            at = verts[verts[:, 0] == x, 1]
            b_lo, b_hi = at.min(), at.max()
            assert b_lo < b_hi and lo < b_lo and b_hi < hi  # not clipped here
            values = []
            for links, e in corners:
                v = float(_evaluate(_task_with(task, links), Q(float(x)), e)[name])
                assert b_lo - 1e-9 * abs(v) <= v <= b_hi + 1e-9 * abs(v)
                values.append(v)
                checked += 1
            # r exact: the efforts are multilinear, the band's ends are corners
            assert max(values) == pytest.approx(b_hi, rel=1e-9)
            assert min(values) == pytest.approx(b_lo, rel=1e-9)
    keys = "\n".join(t.get_text() for t in fig.texts).replace("\n    ", " ")
    assert 1e-3 <= r.window < 1e-2  # 3 digits: x.xx ms, rounded up (an upper bound)
    up = math.ceil(Fraction(r.window) * 10**5) / 100
    shown = f"over the box: |T1| > 300 N m for at most {up:g} ms around t = 2.5 s"
    assert shown + " (shaded)" in keys  # the audit's window (tests/engine/robust/test_windows.py)
    assert checked >= 2 * len(corners)


def test_without_uncertainty_no_band() -> None:
    result = audit(load_task(P2), samples=51)
    fig = P.render([P.motion(result, "p2.yaml")], ["torques"])
    ax = next(a for a in fig.get_axes() if a.get_gid() == "panel-torques")
    gids = [a.get_gid() or "" for a in ax.get_children()]
    assert not any(g.startswith(("torques-band", "torques-window")) for g in gids)
