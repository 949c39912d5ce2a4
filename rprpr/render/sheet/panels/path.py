"""The ``path`` panel: the workspace (the paper's Fig. 3).

Base joints A and B, the singular line y = 0 with its three cases' stretches (Table 1),
the end-point paths with their direction, the robot at each singular instant (and, for
one task, at the start and the end), each singular point keyed by number to its order
and verdict in the lane, and a near miss's distance to the line AB."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.lines import Line2D

from ....model.actuation import SCHEMES
from ....model.five_bar import FIVE_BAR, RPRPR
from ....model.numbers import number
from .. import five_bar_robot as FBR
from ..axes import handles, look
from ..drawing import drawing, kinds
from ..labels import case_label_place
from ..markers import badge, edge, mark_handle, marker_handles, marker_style, nest
from ..motion import Motion, at
from ..page import Indexed, Sheet
from ..robot import (
    CYLINDER,
    CYLINDER_ALPHA,
    ROD,
    SINGULAR_LEGS,
    View,
    base_joints,
    singular_line_handle,
    view,
    workspace,
)
from ..style import (
    LABEL_SIZE,
    LEG1,
    LEG2,
    LINE,
    POINT,
    STATUS_COLOUR,
    STATUS_WORD,
    pt,
    task_colour,
)
from ..words import near_miss_path, order_text, verdict_text

CASES = (  # the singular line's stretches (Table 1): left of A, between A and B, right of B
    "case 2\nθ1 = θ2 = π",
    "case 3\nθ1 = 0, θ2 = π",
    "case 1\nθ1 = θ2 = 0",
)


def draw(sheet: Sheet, pole_inset: bool = False) -> list[Axes]:
    rprpr, _ = kinds(sheet.motions)
    if rprpr:
        sheet.heading(
            "Workspace (paper Fig. 3): end-point path, robot at the singular instants",
            "Workspace (paper Fig. 3): end-point path",
            "Workspace, end-point path",
        )
    else:  # a 5R: its Type II curves instead of the line AB
        sheet.heading(
            "Workspace: end-point path, Type II curves, robot at the singular instants",
            "Workspace: end-point path, Type II curves",
            "Workspace, end-point path",
        )
    x0, x1, y0, y1 = view(sheet.motions)
    h = float(np.clip((y1 - y0) / (x1 - x0) * sheet.column_width, 2.0, 4.4))
    (row,) = sheet.rows("path", (h,), time=False)
    for ax, col in zip(row, sheet.columns, strict=True):
        ax.set_xlabel("x [m]")
        _workspace(sheet, ax, col, h * sheet.row_scale)
    row[0].set_ylabel("y [m]")
    sheet.lane(row[-1], _legend(sheet), notes(sheet))
    return row


def _workspace(sheet: Sheet, ax: Axes, col: Indexed, h: float) -> None:
    """One column's workspace: the line, the bases, robots, paths, marks, near misses."""
    motions = [m for _, m in col]
    # small multiples share one view, among the tasks of one mechanism (metres apart)
    kind = drawing(motions[0])
    v, size = workspace(ax, [m for m in sheet.motions if drawing(m) is kind])
    x0, x1, y0, y1 = v
    ppu = 72 * min(sheet.column_width / (x1 - x0), h / (y1 - y0))  # points per metre
    # the view as drawn: at equal scales the wider of the axes and the data gets room
    grow = max(0.0, sheet.column_width * 72 / ppu - (x1 - x0)) / 2
    rise = max(0.0, h * 72 / ppu - (y1 - y0)) / 2  # as ``grow``, up and down
    drawn = set()
    for i, m in col:  # the singular locus over the view as drawn: the line AB, a 5R's curves
        d = drawing(m)
        if not (d.shared_locus and d.name in drawn):
            d.locus(ax, m, (x0 - grow, x1 + grow, y0 - rise, y1 + rise), d.locus_gid("path", i))
            drawn.add(d.name)
    rprpr = [m for m in motions if drawing(m).name == RPRPR]  # the line AB's three cases
    if rprpr and len(sheet.columns) == 1:  # a small multiple is too narrow to name them
        _case_labels(ax, rprpr, (x0 - grow, x1 + grow, y0, y1), ppu, size)
    base_joints(ax, motions, size)
    _robots(sheet, ax, col, size)
    _paths(sheet, ax, col)
    _singular_points(sheet, ax, col, ppu)
    _approaches(sheet, ax, col, ppu)


def _case_labels(ax: Axes, motions: Sequence[Motion], v: View, ppu: float, size: float) -> None:
    """Each case's name on its stretch of the singular line, within it, above or below the
    line, where no path, leg or base joint runs through it (``labels.case_label_place``);
    none on a stretch too short to hold it."""
    x0, x1, _, _ = v
    a1 = float(motions[0].task.robot.a1)
    avoid = _near_the_line(motions, size, 34 / ppu)
    fs = pt(LABEL_SIZE)
    for (lo, hi), text in zip(((x0, 0.0), (0.0, a1), (a1, x1)), CASES, strict=True):
        longest = max(len(line) for line in text.split("\n"))
        box = ((0.55 * longest * fs + 4) / ppu, (2.5 * fs + 4) / ppu)
        lo, hi = lo + box[0] / 2, hi - box[0] / 2  # within its stretch
        if hi < lo:
            continue  # the stretch is narrower than its name (a small figure): left unnamed
        half = CYLINDER["lw"] / 2 / ppu  # a sleeve's half width
        x, side, lift = case_label_place(lo, hi, avoid, box, CASE_GAP / ppu, half)
        ax.annotate(
            text,
            (x, 0),
            xytext=(0, side * (CASE_GAP + 2 + lift * ppu)),
            textcoords="offset points",
            ha="center",
            va="bottom" if side > 0 else "top",
            fontsize=fs,
            color=LINE,
            gid=f"case-label-{text[5]}",
        )


CASE_GAP = 4.5  # points between the singular line and a case's label: half a sleeve's width


def _near_the_line(motions: Sequence[Motion], size: float, reach: float) -> np.ndarray:
    """The points a case label avoids: the paths, the legs of every robot drawn (at the
    start, the end and each singular instant), the base joints and, ``reach`` [m] around
    each singular point, its mark, ring and key number."""
    pts = [np.column_stack([m.s.x, m.s.y])[:: max(1, len(m.s.t) // 200)] for m in motions]
    along = np.linspace(0, 1, 40)[:, None]
    for m in motions:
        a1 = float(m.task.robot.a1)
        poses = [0, len(m.s.t) - 1, *(at(m, s.t) for s in m.result.singularities)]
        for j in poses:
            E = np.array([m.s.x[j], m.s.y[j]])
            for P in (np.array([0.0, 0.0]), np.array([a1, 0.0])):
                pts.append(P + along * (E - P))
        for b in (0.0, a1):  # the ground symbol and its letter under each base joint
            pts.append(np.column_stack([np.full(5, b), -np.linspace(0, 3, 5) * size]))
    g = np.linspace(-reach, reach, 9)
    disc = np.array([(a, b) for a in g for b in g if a * a + b * b <= reach * reach])
    for m in motions:
        for s in m.result.singularities:
            pts.append(disc + np.array([s.x, 0.0]))
    out = np.concatenate(pts)
    return out[np.all(np.isfinite(out), axis=1)]


def _robots(sheet: Sheet, ax: Axes, col: Indexed, size: float) -> None:
    """Each task's robot at its singular instants (legs dashed, under the line AB) and,
    for one task alone, faint at the start and the end."""
    for i, m in col:
        n = len(m.s.t)
        colour = task_colour(i) if sheet.overlay else None
        if not sheet.overlay:
            draw_robot(ax, m, 0, 0.4, f"robot-{i}-start")
            draw_robot(ax, m, n - 1, 0.4, f"robot-{i}-end")
        for k, s in enumerate(m.result.singularities):
            gid = f"robot-{i}-singular-{k}"
            draw_robot(ax, m, at(m, s.t), 0.85, gid, singular=True, colour=colour)


def draw_robot(ax: Axes, m: Motion, i: int, alpha: float, gid: str, **kw: Any) -> np.ndarray:
    """The robot of ``m`` at sample i, as its mechanism draws it (``drawing``)."""
    return drawing(m).robot(ax, m, i, alpha, gid, **kw)


def _ends(ax: Axes, m: Motion, colour: str, i: int) -> None:
    """The path's start (an open circle) and end (a filled one): the legend says which."""
    for j, (word, face) in ((0, ("start", "white")), (len(m.s.t) - 1, ("end", colour))):
        ax.plot(
            [m.s.x[j]],
            [m.s.y[j]],
            "o",
            ms=6,
            mfc=face,
            mec=colour,
            mew=1.3,
            zorder=7,
            gid=f"path-{word}-{i}",
        )


def _paths(sheet: Sheet, ax: Axes, col: Indexed) -> None:
    """Each end-point path (in its task's colour and line style in an overlay), an arrow
    giving the direction."""
    for i, m in col:
        kw = look(sheet, i, POINT)
        ax.plot(m.s.x, m.s.y, lw=1.8, zorder=4, gid=f"path-{i}", **kw)
        _ends(ax, m, kw["color"], i)
        x, y = m.s.x, m.s.y
        j = int(0.3 * (len(x) - 1))
        if np.all(np.isfinite([x[j], y[j], x[j + 1], y[j + 1]])):
            ax.annotate(
                "",
                xy=(x[j + 1], y[j + 1]),
                xytext=(x[j], y[j]),
                zorder=4,
                arrowprops={
                    "arrowstyle": "-|>",
                    "color": kw["color"],
                    "lw": 1.2,
                    "mutation_scale": 14,
                },
            )


def _singular_points(sheet: Sheet, ax: Axes, col: Indexed, ppu: float) -> None:
    """Each singular point's mark at exactly (x_s, 0) (ringed when of high order; nested
    where tasks' points coincide, ``markers.nest``) with its key number on the side of
    the line the paths leave freer; each inverse-kinematic singular point's cross."""
    span = float(np.diff(ax.dataLim.intervalx)[0]) if ax.dataLim.width > 0 else 1.0
    pts = [
        (
            (i, k),
            s.x,
            float(drawing(m).point(s)[1]),
            _RING_SIZE if s.high_order else marker_style(s, "ok")["markersize"],
        )
        for i, m in col
        for k, s in enumerate(m.result.singularities)
    ]
    placed = nest(pts, (0.01 * span, 1.0))
    paths = np.concatenate([np.column_stack([m.s.x, m.s.y]) for _, m in col])
    for i, m in col:
        for k, s in enumerate(m.result.singularities):
            st = m.result.status_of(s)
            p = placed[i, k]
            px, py = drawing(m).point(s)
            style = marker_style(s, st, edge(sheet, i))
            if s.high_order:  # the ring is the mark's outline: it nests, the star inside
                _ring(ax, (px, py), f"path-ring-{i}-{k}", p.size, p.zorder)
                style["zorder"] = p.zorder + 0.01
            else:
                style.update(markersize=p.size, zorder=p.zorder)
            ax.plot([px], [py], gid=f"path-singular-{i}-{k}", **style)
            dy = p.reach + 7
            side = _freer_side(paths, px + p.dx / ppu, dy / ppu, float(py))
            if (i, k) in sheet.keys:
                key = sheet.keys[i, k]
                badge(ax, key, (px, float(py)), p.dx, side * dy, f"path-key-{i}-{k}")
        for k, ks in enumerate(m.result.kinematic_singularities):
            cross = {**_CROSS, "mec": edge(sheet, i) or _CROSS["mec"]}
            ax.plot([ks.x], [ks.y], "X", ms=11, zorder=6, gid=f"path-kinematic-{i}-{k}", **cross)


def _freer_side(paths: np.ndarray, x: float, d: float, y: float = 0.0) -> int:
    """+1 (above the mark at (x, y)) or -1 (below): where fewer path points lie near
    (x, y ± d)."""
    counts = []
    for side in (1, -1):
        near = (np.abs(paths[:, 0] - x) < 1.2 * d) & (np.abs(paths[:, 1] - y - side * d) < 0.9 * d)
        counts.append(int(np.sum(near)))
    return 1 if counts[0] <= counts[1] else -1


def _approaches(sheet: Sheet, ax: Axes, col: Indexed, ppu: float) -> None:
    """A motion that never meets the line AB: where E comes closest, the distance drawn
    down to the line, keyed."""
    for i, m in col:
        a = m.result.closest_approach
        if a is None:
            continue
        f = m.result.resample(np.array([a.t_y]))
        x, y = float(f.x[0]), float(f.y[0])
        colour = look(sheet, i, POINT)["color"]
        ax.annotate(
            "",
            xy=(x, 0.0),
            xytext=(x, y),
            arrowprops={
                "arrowstyle": "<->",
                "color": colour,
                "lw": 0.9,
                "shrinkA": 0,
                "shrinkB": 0,
            },
            zorder=6,
            gid=f"path-approach-{i}",
        )
        ax.plot(
            [x], [y], "o", ms=5, mfc="white", mec=colour, mew=1.3, zorder=7, gid=f"path-near-{i}"
        )
        badge(ax, sheet.keys[i, "approach"], (x, y / 2), 12, 0, f"path-approach-key-{i}")


_CROSS: dict[str, Any] = {"mfc": STATUS_COLOUR["fail"], "mec": "black"}  # E at A or B


_RING_SIZE = 30.0  # points: the ring around a high-order singular point


def _ring(ax: Axes, at: tuple[float, float], gid: str, size: float, zorder: float) -> None:
    """A red ring around a high-order singular point at ``at``: it must stand out."""
    ax.plot(
        [at[0]],
        [at[1]],
        "o",
        ms=size,
        mfc="none",
        mec=STATUS_COLOUR["fail"],
        mew=2,
        alpha=0.8,
        zorder=zorder,
        gid=gid,
    )


def notes(sheet: Sheet) -> list[str]:
    """The keys of the workspace's marks: each singular instant's time, order, verdict
    and why (as ``rprpr check`` lists them); each near miss's distance."""
    out = []
    for i, m in enumerate(sheet.motions):
        who = sheet.who(m)
        for key, s, t in sheet.keyed(i):
            why = verdict_text(s, SCHEMES[m.task.robot.actuation])
            out.append(
                f"{key}  {who}t = {t} s, {order_text(s)} — "
                f"{STATUS_WORD[m.result.status_of(s)].upper()}" + (f": {why}" if why else "")
            )
        if m.result.closest_approach is not None:
            out.append(
                f"{sheet.keys[i, 'approach']}  {who}{near_miss_path(m.result.closest_approach)}"
            )
    a1s = sorted({float(m.task.robot.a1) for m in sheet.motions})
    if len(a1s) > 1:
        out.append("B1, B2, …: B at a1 = " + ", ".join(f"{number(a)} m" for a in a1s))
    return out + sheet.crowded()


def _sleeve(colour: str) -> Line2D:
    """A leg's sleeve (the cylinder its rod slides in) as a legend handle, as drawn."""
    return Line2D([], [], color=colour, alpha=CYLINDER_ALPHA, **CYLINDER)


def _legend(sheet: Sheet) -> list[Any]:
    """The workspace's legend: the paths, the singular line, the legs (each a pair: its
    sleeve and its rod, drawn one over the other), the marks."""
    motions = sheet.motions
    five = [m for m in motions if drawing(m).name == FIVE_BAR]
    rprpr = len(five) < len(motions)
    extra: list[Any] = [
        *handles(sheet, [("end-point path", POINT)]),
        mark_handle("start of the path (t = 0)", "o", "white", "#333333"),
        mark_handle("end of the path (t = t_f)", "o", "#333333", "#333333"),
    ]
    n = len(extra)  # the robots' entries go here, before the singular line
    extra += [singular_line_handle()] if rprpr else []
    extra += FBR.curve_handles() if five else []
    extra += marker_handles(motions)
    if five:
        extra[n:n] = _five_bar_links(sheet.overlay)
    if rprpr and not sheet.overlay:  # overlaid, each robot is drawn in its task's colour
        extra[n:n] = [
            (
                _sleeve(LEG1),
                Line2D([], [], color=LEG1, label="leg 1 (A–E): sleeve, rod; θ1, s1", **ROD),
            ),
            (
                _sleeve(LEG2),
                Line2D([], [], color=LEG2, label="leg 2 (B–E): sleeve, rod; θ2, s2", **ROD),
            ),
            Line2D(
                [],
                [],
                color="#777777",
                lw=1.6,
                ls=(0, (3, 1.5)),
                label="legs at a singular instant",
            ),
        ]
    elif rprpr:
        extra[n:n] = [
            (
                _sleeve("#777777"),
                Line2D(
                    [],
                    [],
                    color="#777777",
                    label="legs at t_s: sleeve, rod, task's colour",
                    **{**ROD, "ls": SINGULAR_LEGS},
                ),
            )
        ]
    if any(m.result.kinematic_singularities for m in motions if drawing(m).name == RPRPR):
        extra.append(
            Line2D([], [], marker="X", ms=9, ls="none", label="E at A or B (s = 0)", **_CROSS)
        )
    if any(m.result.kinematic_singularities for m in five):
        label = "a leg stretched or folded (Type I)"
        extra.append(Line2D([], [], marker="X", ms=9, ls="none", label=label, **_CROSS))
    return extra


def _five_bar_links(overlay: bool) -> list[Any]:
    """A 5R's legend entries: each leg's proximal and distal links (one over the other),
    and the distal links at a singular instant; overlaid, one entry in grey."""
    if overlay:
        return [
            (
                Line2D([], [], color="#777777", alpha=0.6, **FBR.PROXIMAL),
                Line2D(
                    [],
                    [],
                    color="#777777",
                    label="5R links at t_s: proximal, distal, task's colour",
                    **{**FBR.DISTAL, "ls": SINGULAR_LEGS},
                ),
            )
        ]
    return [
        (
            Line2D([], [], color=LEG1, alpha=0.6, **FBR.PROXIMAL),
            Line2D([], [], color=LEG1, label="leg 1: links A–C, C–E; θ1, φ1", **FBR.DISTAL),
        ),
        (
            Line2D([], [], color=LEG2, alpha=0.6, **FBR.PROXIMAL),
            Line2D([], [], color=LEG2, label="leg 2: links B–D, D–E; θ2, φ2", **FBR.DISTAL),
        ),
        Line2D(
            [],
            [],
            color="#777777",
            lw=1.6,
            ls=(0, (3, 1.5)),
            label="distal links at a singular instant",
        ),
    ]
