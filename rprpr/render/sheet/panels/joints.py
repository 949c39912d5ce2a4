"""The ``joints`` panel: the actuated joints θ1, θ2 in degrees, continuous (the paper's
Fig. 5), and the leg lengths s1, s2."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import SubFigure

from ..axes import degree_ticks, legend, panel_title, time_axes
from ..motion import Motion, finite
from ..style import LEG1, LEG2, style


def height(motions: Sequence[Motion]) -> float:
    return 3.0


def draw(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    panel_title(sf, "Actuated joints (paper Fig. 5) and leg lengths", motions)
    ax_t, ax_s = sf.subplots(1, 2)
    time_axes(
        ax_t, motions, r"$\theta_1(t)$, $\theta_2(t)$ (continuous)", r"$\theta$ [deg]", "theta"
    )
    time_axes(ax_s, motions, r"$s_1(t)$, $s_2(t)$", "$s$ [m]", "s")
    degrees = []
    for i, m in enumerate(motions):
        for ax, v, c, name in (
            (ax_t, np.degrees(m.s.theta1), LEG1, "theta1"),
            (ax_t, np.degrees(m.s.theta2), LEG2, "theta2"),
            (ax_s, m.s.s1, LEG1, "s1"),
            (ax_s, m.s.s2, LEG2, "s2"),
        ):
            ax.plot(m.s.t, finite(v), color=c, ls=style(i), lw=1.7, gid=f"{name}-{i}")
            if ax is ax_t:
                degrees.append(v[np.isfinite(v)])
    shown = np.concatenate(degrees)
    if shown.size:
        degree_ticks(ax_t, float(shown.min()), float(shown.max()))
    legend(ax_t, [(r"$\theta_1$ (joint A)", LEG1), (r"$\theta_2$ (joint B)", LEG2)], motions)
    legend(ax_s, [("$s_1 = |AE|$", LEG1), ("$s_2 = |BE|$", LEG2)], motions)
    return [ax_t, ax_s]
