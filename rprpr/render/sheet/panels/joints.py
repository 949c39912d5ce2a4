"""The ``joints`` panel: the actuated joints θ1, θ2 in degrees, continuous (the paper's
Fig. 5), over the leg lengths s1, s2."""

from __future__ import annotations

import numpy as np
from matplotlib.axes import Axes

from ..axes import degree_ticks, handles, instant_lines, knot_handles, look
from ..motion import finite
from ..page import Sheet
from ..style import LEG1, LEG2

ROW = 1.45  # in, each of θ and s


def draw(sheet: Sheet, pole_inset: bool = False) -> list[Axes]:
    sheet.heading("Actuated joints θ1, θ2 (paper Fig. 5) and leg lengths s1, s2")
    row_t, row_s = sheet.rows("joints", (ROW, ROW))
    degrees = []
    for ax_t, ax_s, col in zip(row_t, row_s, sheet.columns, strict=True):
        instant_lines(ax_t, col, "theta")
        instant_lines(ax_s, col, "s")
        for i, m in col:
            for ax, v, leg, name in (
                (ax_t, np.degrees(m.s.theta1), 0, "theta1"),
                (ax_t, np.degrees(m.s.theta2), 1, "theta2"),
                (ax_s, m.s.s1, 0, "s1"),
                (ax_s, m.s.s2, 1, "s2"),
            ):
                kw = look(sheet, i, (LEG1, LEG2)[leg], leg, pair=True)
                ax.plot(m.s.t, finite(v), lw=1.6, gid=f"{name}-{i}", **kw)
                if ax is ax_t:
                    degrees.append(v[np.isfinite(v)])
    shown = np.concatenate(degrees)
    if shown.size:
        degree_ticks(row_t[0], float(shown.min()), float(shown.max()))
    row_t[0].set_ylabel(r"$\theta$ [deg]")
    row_s[0].set_ylabel("$s$ [m]")
    sheet.lane(
        row_t[-1],
        [
            *handles(sheet, [(r"$\theta_1$ (joint A)", LEG1), (r"$\theta_2$ (joint B)", LEG2)]),
            *knot_handles(sheet),
        ],
    )
    sheet.lane(row_s[-1], handles(sheet, [("$s_1 = |AE|$", LEG1), ("$s_2 = |BE|$", LEG2)]))
    return [*row_t, *row_s]
