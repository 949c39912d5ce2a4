"""The ``joints`` panel: the joint angles θ1, θ2 in degrees, continuous (the paper's
Fig. 5), over the leg lengths s1, s2; the heading says which are actuated."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from matplotlib.axes import Axes

from ....model.actuation import REVOLUTE
from ..axes import degree_ticks, handles, instant_lines, knot_handles, look
from ..drawing import drawing, kinds
from ..motion import Motion, finite
from ..page import Sheet
from ..style import LEG1, LEG2

ROW = 1.45  # in, each of θ and s


def heading(motions: Sequence[Motion]) -> str:
    """The panel's heading: which joints the motors drive, by the tasks' actuation (the
    paper's revolute motors drive θ1, θ2; linear actuators drive s1, s2)."""
    kinds = {m.task.robot.actuation for m in motions}
    if kinds <= {REVOLUTE}:
        return "Actuated joints θ1, θ2 (paper Fig. 5) and leg lengths s1, s2"
    if REVOLUTE not in kinds:
        return "Joint angles θ1, θ2 (paper Fig. 5), passive, and actuated joints s1, s2 (prismatic)"
    return (
        "Joint angles θ1, θ2 (paper Fig. 5), leg lengths s1, s2 (actuated: θ revolute, s prismatic)"
    )


def short_headings(motions: Sequence[Motion]) -> tuple[str, ...]:
    """Shorter forms of ``heading``, for a figure of a given size (one line)."""
    kinds = {m.task.robot.actuation for m in motions}
    if kinds <= {REVOLUTE}:
        return ("Actuated joints θ1, θ2 and leg lengths s1, s2", "Actuated θ1, θ2; legs s1, s2")
    if REVOLUTE not in kinds:
        return (
            "Passive θ1, θ2; actuated legs s1, s2 (prismatic)",
            "Passive θ1, θ2; actuated s1, s2",
        )
    return ("Joint angles θ1, θ2 and leg lengths s1, s2", "Joints θ1, θ2; legs s1, s2")


FIVE_BAR_HEADINGS = (
    "Motor angles θ1, θ2 (links A–C, B–D) and distal links' angles φ1, φ2 (C–E, D–E)",
    "Motor angles θ1, θ2 and distal angles φ1, φ2",
    "Motors θ1, θ2; distal φ1, φ2",
)
MIXED_HEADINGS = (
    "Joint angles θ1, θ2 (paper Fig. 5); RPRPR leg lengths s1, s2; 5R distal links' angles φ1, φ2",
    "Joints θ1, θ2; legs s1, s2 (RPRPR), φ1, φ2 (5R)",
)


def draw(sheet: Sheet, pole_inset: bool = False) -> list[Axes]:
    rprpr, five = kinds(sheet.motions)
    if not five:
        sheet.heading(heading(sheet.motions), *short_headings(sheet.motions))
    else:
        sheet.heading(*(MIXED_HEADINGS if rprpr else FIVE_BAR_HEADINGS))
    # the second row is in metres for an RPRPR, in degrees for a 5R: shared by kind only
    kind = [drawing(c[0][1]) for c in sheet.columns]
    groups = [d.name for d in kind] if rprpr and five else None
    row_t, row_s = sheet.rows("joints", (ROW, ROW), groups=groups)
    degrees = []
    for ax_t, ax_s, col in zip(row_t, row_s, sheet.columns, strict=True):
        instant_lines(ax_t, col, "theta")
        instant_lines(ax_s, col, "s")
        for i, m in col:
            (v1, n1), (v2, n2) = drawing(m).second_row(m)
            for ax, v, leg, name in (
                (ax_t, np.degrees(m.s.theta1), 0, "theta1"),
                (ax_t, np.degrees(m.s.theta2), 1, "theta2"),
                (ax_s, v1, 0, n1),
                (ax_s, v2, 1, n2),
            ):
                kw = look(sheet, i, (LEG1, LEG2)[leg], leg, pair=True)
                ax.plot(m.s.t, finite(v), lw=1.6, gid=f"{name}-{i}", **kw)
                if ax is ax_t:
                    degrees.append(v[np.isfinite(v)])
    shown = np.concatenate(degrees)
    if shown.size:
        degree_ticks(row_t[0], float(shown.min()), float(shown.max()))
    row_t[0].set_ylabel(r"$\theta$ [deg]")
    for c, ax in enumerate(row_s):  # each run of columns of one mechanism says its unit
        if c == 0 or kind[c] is not kind[c - 1]:
            ax.set_ylabel(kind[c].second_label)
    sheet.lane(
        row_t[-1],
        [
            *handles(sheet, [(r"$\theta_1$ (joint A)", LEG1), (r"$\theta_2$ (joint B)", LEG2)]),
            *knot_handles(sheet),
        ],
    )
    second = [n for d in dict.fromkeys(map(drawing, sheet.motions)) for n in d.second_names]
    sheet.lane(row_s[-1], handles(sheet, second))
    return [*row_t, *row_s]
