"""The audit sheet of ``rprpr plot`` (matplotlib: only the plot path imports this module).

``motion`` samples a task densely (``audit``'s grid plus the singular instants, so that
every t_s is drawn at its exact value); ``render`` draws the chosen panels of one motion,
or several overlaid, on a ``matplotlib.figure.Figure`` (headless, no pyplot); ``save``
writes it as PNG, SVG or PDF.

Panels (``PANELS``), each a row of the sheet, in the order asked for:

* ``path``: the workspace (the paper's Fig. 3): base joints A and B, the singular line
  y = 0 with its three cases' stretches, the end-point path, the robot at the start, the
  end and each singular instant, each singular point with its order and verdict;
* ``x``: x_E(t) (Fig. 2) and y_E(t);
* ``delta``: δ(t) = sin(θ1 - θ2) (eq. 29, Fig. 4), each singular instant marked with its
  order;
* ``joints``: θ1, θ2 in degrees, continuous (Fig. 5), and s1, s2;
* ``torques``: T1, T2 (eq. 28). Where a torque is unbounded the axis keeps the bounded
  part (the range outside ``CLIP_WINDOW`` t_f of each unbounded instant), a dashed line
  marks t_s and ▲/▼ mark where each curve leaves the axes; ``checks.torque_limit`` is
  drawn as bands beyond ±limit.

Conventions, stated once:

* colour is the quantity, the same in every panel: leg 1 (A-E; θ1, s1, T1) blue, leg 2
  (B-E; θ2, s2, T2) green, the end point E (path, x_E, y_E) black, δ purple;
* line style is the task, in the order given (``STYLES``);
* a singular instant is a star when of high order (order >= 2), a diamond when of first
  order, filled red when a rule fails the task there, amber when a rule warns (unbounded
  torques outside strict mode), yellow when it passes: the same findings as
  ``rprpr check``.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import IO, Any

import matplotlib
import numpy as np
from matplotlib import ticker
from matplotlib.axes import Axes
from matplotlib.figure import Figure, SubFigure
from matplotlib.lines import Line2D
from matplotlib.patches import Polygon
from matplotlib.transforms import blended_transform_factory

from .._version import __version__
from ..engine.audit import AuditResult
from ..engine.sampling import Samples
from ..engine.singular import SingularInstant
from ..model.task import Task

PANELS = ("path", "x", "delta", "joints", "torques")
FORMATS = {".png": "png", ".svg": "svg", ".pdf": "pdf"}

LEG1 = "#0072B2"  # leg 1, A-E: θ1, s1, T1
LEG2 = "#009E73"  # leg 2, B-E: θ2, s2, T2
POINT = "#000000"  # the end point E: path, x_E, y_E
DELTA = "#6A3D9A"  # δ
LINE = "#D62728"  # the singular line y = 0
STATUS_COLOUR = {"fail": "#D62728", "warn": "#E69F00", "ok": "#F0E442"}
STATUS_WORD = {"fail": "fails", "warn": "warning", "ok": "passes"}
_SEVERITY = {"ok": 0, "warn": 1, "fail": 2}
STYLES: tuple[Any, ...] = (
    "-",
    "--",
    "-.",
    ":",
    (0, (8, 2, 2, 2, 2, 2)),
    (0, (1, 1)),
    (0, (6, 2)),
    (0, (3, 4, 1, 4)),
)

NEAR_DELTA = 0.1  # |δ| below this is "near" a Type II singularity (band on δ, cue in the GIF)
CLIP_WINDOW = 0.1  # fraction of t_f about an unbounded instant left out when scaling T
LIMIT_SHOWN = 10.0  # a torque limit beyond this multiple of the plotted range is only noted
WIDTH = 11.0  # sheet width [in]

RC: Any = {  # matplotlib's rcParams for the sheet (Any: its stubs want literal keys)
    "font.size": 9,
    "axes.titlesize": 9.5,
    "axes.labelsize": 9,
    "legend.fontsize": 7.5,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "axes.grid": True,
    "grid.alpha": 0.3,
    "grid.linewidth": 0.6,
    "svg.fonttype": "none",  # text stays text: searchable, editable
    "svg.hashsalt": "rprpr",  # reproducible ids
    "pdf.fonttype": 42,  # TrueType, not Type 3: what journals ask for
}


@dataclass(frozen=True)
class Motion:
    """One audited task, ready to draw: the audit and dense samples that include every
    singular instant exactly."""

    source: str
    result: AuditResult
    s: Samples

    @property
    def task(self) -> Task:
        return self.result.task

    @property
    def name(self) -> str:
        return self.result.task.name

    @property
    def duration(self) -> float:
        return float(self.s.t[-1])


def motion(result: AuditResult, source: str = "") -> Motion:
    """The audited task ``result``, ready to draw: its samples with its singular instants
    added to the grid and, about an unbounded one, the times t_s ± 10^-k t_f (k = 3..8),
    so that the curves visibly diverge however fine or coarse the grid."""
    s = result.samples
    tf = float(s.t[-1])
    tol = 1e-12 * max(1.0, tf)
    missing = [i.t for i in result.singularities if not np.any(np.abs(s.t - i.t) <= tol)]
    for i in result.singularities:
        if not i.torque_bounded:
            near = i.t + tf * np.outer([-1, 1], 10.0 ** -np.arange(3, 9)).ravel()
            missing += [float(v) for v in near if 0 < v < tf]
    m = Motion(source, result, s)
    if missing:
        m = Motion(source, result, resample(m, np.union1d(s.t, missing)))
    return m


def resample(m: Motion, t: np.ndarray) -> Samples:
    """The engine's samples of ``m``'s motion at the times ``t`` [s] (no new analysis)."""
    return m.result.resample(t)


def status(result: AuditResult, s: SingularInstant) -> str:
    """The audit's status of the singular instant ``s`` ("fail", "warn" or "ok")."""
    return result.status_of(s)


def order_text(s: SingularInstant) -> str:
    return f"order {s.order}, high-order" if s.order >= 2 else f"order {s.order}"


def verdict_text(result: AuditResult, s: SingularInstant) -> str:
    """Why a singular instant is marked as it is, in a few words."""
    why = []
    if not s.slope_principle.passed:
        why.append("slope principle fails")
    if not s.velocity_principle.passed:
        why.append("velocity principle fails")
    if not s.torque_bounded:
        why.append(f"T unbounded (pole {s.pole_order})")
    elif s.torque_at_singularity is not None:
        t1, t2 = s.torque_at_singularity
        why.append(f"T → ({t1:.4g}, {t2:.4g}) N m")
    return ", ".join(why)


def summary(m: Motion) -> str:
    """One line per task for the sheet's title: verdict, singular instants, torques."""
    r = m.result
    n = len(r.singularities)
    high = sum(s.order >= 2 for s in r.singularities)
    parts = [f"{n} singular instant{'' if n == 1 else 's'}"]
    if n:
        parts[0] += f" ({high} high-order)"
    if r.on_singular_line:
        parts.append("the path lies on the singular line")
    if r.kinematic_singularities:
        parts.append("inverse-kinematic singularity")
    unbounded = [s for s in r.singularities if not s.torque_bounded]
    if len(unbounded) > 4:
        parts.append(f"torques unbounded at {len(unbounded)} instants")
    elif unbounded:
        parts.append(
            "torques unbounded at t = " + ", ".join(f"{s.t:.4g}" for s in unbounded) + " s"
        )
    elif r.torque_peak is not None:
        parts.append(f"peak |T1|, |T2| = {r.torque_peak[0]:.4g}, {r.torque_peak[1]:.4g} N m")
    where = f" ({m.source})" if m.source else ""
    return f"{m.name}{where}: {r.verdict.upper()} — " + "; ".join(parts)


def _names(motions: Sequence[Motion]) -> str:
    if len(motions) == 1:
        return motions[0].name
    joined = " vs ".join(m.name for m in motions)
    return joined if len(joined) <= 90 else f"{len(motions)} tasks (see legend)"


def _short(name: str, n: int = 36) -> str:
    return name if len(name) <= n else name[: n - 1] + "…"


def _style(i: int) -> Any:
    return STYLES[i % len(STYLES)]


def _finite(v: np.ndarray) -> np.ndarray:
    return np.where(np.isfinite(v), v, np.nan)


# ---------------------------------------------------------------------------------------
# common pieces


def _title(sf: SubFigure, what: str, motions: Sequence[Motion]) -> None:
    sf.suptitle(f"{what} — {_names(motions)}", fontsize=10.5, fontweight="bold")


def _marker_kw(s: SingularInstant, st: str) -> dict[str, Any]:
    high = s.order >= 2
    return {
        "marker": "*" if high else "D",
        "markersize": 17 if high else 7.5,
        "markerfacecolor": STATUS_COLOUR[st],
        "markeredgecolor": "black",
        "markeredgewidth": 0.9,
        "linestyle": "none",
        "zorder": 6.5 if high else 6,  # a high-order mark stays on top of a coinciding one
    }


def _marker_handles(motions: Sequence[Motion]) -> list[Line2D]:
    seen: dict[tuple[bool, str], Line2D] = {}
    for m in motions:
        for s in m.result.singularities:
            st = status(m.result, s)
            key = (s.order >= 2, st)
            if key not in seen:
                kind = "high-order" if key[0] else "first-order"
                seen[key] = Line2D(
                    [],
                    [],
                    label=f"{kind} singular instant ({STATUS_WORD[st]})",
                    **_marker_kw(s, st),
                )
    return [seen[k] for k in sorted(seen, key=lambda k: (not k[0], k[1]))]


def _legend(
    ax: Axes,
    quantities: Sequence[tuple[str, str]],
    motions: Sequence[Motion],
    extra: Sequence[Any] = (),
    **kw: Any,
) -> None:
    """Quantities by colour; with several tasks, tasks by line style."""
    if len(motions) == 1:
        handles = [Line2D([], [], color=c, label=q) for q, c in quantities]
    elif len(quantities) == 1:
        c = quantities[0][1]
        handles = [
            Line2D([], [], color=c, ls=_style(i), label=m.name) for i, m in enumerate(motions)
        ]
    else:
        handles = [Line2D([], [], color=c, label=q) for q, c in quantities]
        handles += [
            Line2D([], [], color="#555555", ls=_style(i), label=m.name)
            for i, m in enumerate(motions)
        ]
    handles += list(extra)
    ax.legend(handles=handles, **{"loc": "best", "framealpha": 0.88, **kw})


_OUTSIDE = {
    "loc": "upper left",
    "bbox_to_anchor": (1.01, 1.0),
    "borderaxespad": 0,
}  # full-width panels


def _time_axes(ax: Axes, motions: Sequence[Motion], title: str, ylabel: str, name: str) -> None:
    """A time axis over [0, max t_f] with a line at each singular instant (gid
    ``<name>-tsline-<task>-<k>``) and each inverse-kinematic one."""
    ax.set_title(title)
    ax.set_xlabel("t [s]")
    ax.set_ylabel(ylabel)
    ax.set_xlim(0, max(m.duration for m in motions))
    for i, m in enumerate(motions):
        for k, s in enumerate(m.result.singularities):
            st = status(m.result, s)
            ax.axvline(
                s.t,
                color="#888888" if st == "ok" else STATUS_COLOUR[st],
                ls=(0, (4, 3)),
                lw=0.9,
                zorder=0.6 + 0.01 * _SEVERITY[st],
                gid=f"{name}-tsline-{i}-{k}",
            )
        for k, ks in enumerate(m.result.kinematic_singularities):
            ax.axvline(
                ks.t,
                color=STATUS_COLOUR["fail"],
                ls=":",
                lw=1.2,
                zorder=0.65,
                gid=f"{name}-kinematic-{i}-{k}",
            )


def _mark(
    ax: Axes,
    panel: str,
    motions: Sequence[Motion],
    value: Callable[[Motion, SingularInstant], float],
) -> None:
    """A marker at each singular instant at (t_s, value); gid panel-singular-task-k."""
    for i, m in enumerate(motions):
        for k, s in enumerate(m.result.singularities):
            ax.plot(
                [s.t],
                [value(m, s)],
                gid=f"{panel}-singular-{i}-{k}",
                **_marker_kw(s, status(m.result, s)),
            )


MAX_LABELS = 12  # singular instants labelled one by one; beyond, the markers speak alone


def _labelled(motions: Sequence[Motion]) -> bool:
    """Whether the singular instants get text labels (not when they would pile up)."""
    return sum(len(m.result.singularities) for m in motions) <= MAX_LABELS


def _at(m: Motion, t: float) -> int:
    return int(np.argmin(np.abs(m.s.t - t)))


def _degree_ticks(ax: Axes, lo: float, hi: float) -> None:
    span = max(hi - lo, 1e-9)
    for step in (5, 10, 15, 30, 45, 90, 180, 360, 720):
        if span / step <= 8:
            ax.yaxis.set_major_locator(ticker.MultipleLocator(step))
            return


# ---------------------------------------------------------------------------------------
# the workspace


def _view(motions: Sequence[Motion]) -> tuple[float, float, float, float]:
    xs = np.concatenate(
        [m.s.x for m in motions] + [np.array([0.0, float(m.task.robot.a1)]) for m in motions]
    )
    ys = np.concatenate([m.s.y for m in motions] + [np.zeros(1)])
    xs, ys = xs[np.isfinite(xs)], ys[np.isfinite(ys)]
    x0, x1 = float(xs.min()), float(xs.max())
    y0, y1 = float(ys.min()), float(ys.max())
    padx = 0.18 * (x1 - x0)  # room for the case 1 and case 2 stretches beyond A and B
    pady = max(0.12 * (y1 - y0), 0.08 * (x1 - x0))
    return min(x0, 0.0) - padx, x1 + padx, y0 - pady, y1 + pady


def _path_height(motions: Sequence[Motion]) -> float:
    x0, x1, y0, y1 = _view(motions)
    axes_width = WIDTH - 3.6  # the legend sits to the right
    return float(np.clip((y1 - y0) / (x1 - x0) * axes_width + 1.2, 3.2, 7.5))


def _ground(ax: Axes, x: float, size: float, label: str) -> None:
    """A base joint: a grounded triangle under a revolute joint at (x, 0)."""
    h = size
    ax.add_patch(
        Polygon(
            [(x, 0), (x - 0.6 * h, -h), (x + 0.6 * h, -h)],
            closed=True,
            facecolor="#BBBBBB",
            edgecolor="#333333",
            lw=0.8,
            zorder=3,
        )
    )
    ax.plot([x - 0.9 * h, x + 0.9 * h], [-h, -h], color="#333333", lw=1.2, zorder=3)
    for k in range(5):
        xx = x - 0.9 * h + k * 0.45 * h
        ax.plot([xx, xx - 0.35 * h], [-h, -1.4 * h], color="#333333", lw=0.7, zorder=3)
    ax.plot([x], [0], "o", ms=6, mfc="white", mec="#333333", mew=1.2, zorder=7)
    ax.annotate(
        label,
        (x, -1.4 * h),
        xytext=(0, -3),
        textcoords="offset points",
        ha="center",
        va="top",
        fontsize=10,
        fontweight="bold",
    )


def _robot(ax: Axes, m: Motion, i: int, alpha: float, gid: str) -> np.ndarray:
    """The robot at sample i: each leg a cylinder pivoting at its base and a rod to E.
    Returns points along the legs (for placing labels clear of them)."""
    s = m.s
    E = np.array([s.x[i], s.y[i]])
    along = np.linspace(0, 1, 24)[:, None]
    if not np.all(np.isfinite(E)):
        return np.empty((0, 2))
    pts = []
    a1 = float(m.task.robot.a1)
    for n, base, colour, lengths in ((1, (0.0, 0.0), LEG1, s.s1), (2, (a1, 0.0), LEG2, s.s2)):
        P = np.array(base)
        d = E - P
        length = float(np.hypot(*d))
        if length == 0:
            continue
        u = d / length
        finite = lengths[np.isfinite(lengths)]
        cyl = 0.45 * float(finite.min()) if finite.size else 0.3 * length
        cyl = min(cyl, 0.8 * length)
        C = P + cyl * u
        ax.plot(
            [P[0], C[0]],
            [P[1], C[1]],
            color=colour,
            lw=7,
            alpha=0.45 * alpha,
            solid_capstyle="butt",
            zorder=3.5,
            gid=f"{gid}-cylinder{n}",
        )
        ax.plot(
            [P[0], E[0]],
            [P[1], E[1]],
            color=colour,
            lw=2.2,
            alpha=alpha,
            solid_capstyle="round",
            zorder=3.6,
            gid=f"{gid}-leg{n}",
        )
        pts.append(P + along * (E - P))
    ax.plot([E[0]], [E[1]], "o", ms=6, mfc="white", mec=POINT, mew=1.3, alpha=alpha, zorder=5)
    return np.concatenate(pts) if pts else np.empty((0, 2))


def _place(
    text: str,
    at: tuple[float, float],
    obstacles: np.ndarray,
    boxes: list[tuple[float, float, float, float]],
    ppu: float,
    view: tuple[float, float, float, float],
    fontsize: float = 7.5,
) -> tuple[tuple[float, float], tuple[float, float, float, float]]:
    """An offset (points) for a label at ``at`` whose box covers the fewest obstacle
    points, overlaps no placed box and stays in the view; and that box (data units).
    ``ppu`` is points per data unit (an estimate: the layout is not yet done)."""
    lines = text.split("\n")
    w = (max(len(line) for line in lines) * 0.58 * fontsize + 8) / ppu
    h = (len(lines) * 1.25 * fontsize + 6) / ppu
    best: tuple[float, tuple[float, float], tuple[float, float, float, float]] | None = None
    rank = 0
    for dist in (16, 34, 60, 90):
        for sx, sy in ((1, -1), (-1, -1), (1, 1), (-1, 1)):
            dx, dy = 14 * sx, dist * sy
            bx = at[0] + dx / ppu
            by = at[1] + dy / ppu
            box = (
                min(bx, bx + sx * w),
                max(bx, bx + sx * w),
                min(by, by + sy * h),
                max(by, by + sy * h),
            )
            inside = np.sum(
                (obstacles[:, 0] >= box[0])
                & (obstacles[:, 0] <= box[1])
                & (obstacles[:, 1] >= box[2])
                & (obstacles[:, 1] <= box[3])
            )
            clash = sum(
                not (box[1] < b[0] or b[1] < box[0] or box[3] < b[2] or b[3] < box[2])
                for b in boxes
            )
            out = box[0] < view[0] or box[1] > view[1] or box[2] < view[2] or box[3] > view[3]
            score = float(inside) + 1000.0 * clash + 500.0 * out + 0.5 * rank
            rank += 1
            if best is None or score < best[0]:
                best = (score, (float(dx), float(dy)), box)
    assert best is not None
    return best[1], best[2]


def _case_label_x(lo: float, hi: float, avoid: np.ndarray) -> float:
    """Where along [lo, hi] a label sits farthest from the points ``avoid`` (x, y)."""
    cands = np.linspace(lo, hi, 11)
    if avoid.size == 0:
        return float(cands[len(cands) // 2])
    dist = np.min(np.hypot(cands[:, None] - avoid[None, :, 0], avoid[None, :, 1]), axis=1)
    return float(cands[int(np.argmax(dist))])


def _panel_path(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    _title(sf, "Workspace (paper Fig. 3)", motions)
    ax = sf.subplots()
    ax.set_title("end-point path, robot at start, end and singular instants")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    x0, x1, y0, y1 = _view(motions)
    # equal scales; the view grows to fill the axes (fixed limits would fight the aspect)
    ax.set_aspect("equal", adjustable="datalim")
    ax.margins(0)
    ax.update_datalim([(x0, y0), (x1, y1)])
    size = 0.028 * (x1 - x0)

    # the singular line and its three cases (Table 1)
    ax.axhline(0, color=LINE, lw=1.1, ls=(0, (7, 2, 1.5, 2)), zorder=1, gid="singular-line")
    a1 = float(motions[0].task.robot.a1)
    pts = np.concatenate(
        [np.column_stack([m.s.x, m.s.y])[:: max(1, len(m.s.t) // 200)] for m in motions]
    )
    pts = pts[np.all(np.isfinite(pts), axis=1)]
    pts = pts[np.abs(pts[:, 1]) < 0.25 * (y1 - y0)]
    span = x1 - x0
    sing = np.array([(s.x, 0.0) for m in motions for s in m.result.singularities]).reshape(-1, 2)
    avoid = np.concatenate([pts, sing])
    edge = 0.07 * span  # half a label's width, about
    for lo, hi, text in (
        (x0 + edge, -0.02 * span, "case 2\nθ1 = θ2 = π"),
        (0.2 * a1, 0.8 * a1, "case 3\nθ1 = 0, θ2 = π"),
        (a1 + 0.02 * span, x1 - edge, "case 1\nθ1 = θ2 = 0"),
    ):
        if hi <= lo:
            continue
        cx = _case_label_x(lo, hi, avoid)
        ax.annotate(
            text,
            (cx, 0),
            xytext=(0, 3),
            textcoords="offset points",
            ha="center",
            va="bottom",
            fontsize=7.5,
            color=LINE,
            gid=f"case-label-{text[5]}",
        )

    # the base joints, once per distinct a1
    _ground(ax, 0.0, size, "A")
    a1s = sorted({float(m.task.robot.a1) for m in motions})
    for a in a1s:
        _ground(ax, a, size, "B" if len(a1s) == 1 else f"B (a1 = {a:g} m)")

    # robots: start and end faint, singular instants solid
    labelled: set[tuple[float, float, str]] = set()
    obstacles = [np.array([(0.0, -size * k) for k in (0, 1, 2, 3)])]
    obstacles += [np.array([(a, -size * k) for k in (0, 1, 2, 3)]) for a in a1s]
    for i, m in enumerate(motions):
        n = len(m.s.t)
        obstacles.append(_robot(ax, m, 0, 0.45, f"robot-{i}-start"))
        obstacles.append(_robot(ax, m, n - 1, 0.45, f"robot-{i}-end"))
        for k, s in enumerate(m.result.singularities):
            obstacles.append(_robot(ax, m, _at(m, s.t), 0.9, f"robot-{i}-singular-{k}"))
        obstacles.append(np.column_stack([m.s.x, m.s.y])[:: max(1, n // 300)])
        for j, word in ((0, "start"), (n - 1, "end")):
            key = (round(float(m.s.x[j]), 6), round(float(m.s.y[j]), 6), word)
            if key in labelled or not np.isfinite(m.s.x[j]):
                continue
            labelled.add(key)
            obstacles.append(
                np.array(
                    [
                        (m.s.x[j] + size * k, m.s.y[j] + (-size if word == "start" else size))
                        for k in (1, 3, 5)
                    ]
                )
            )
            ax.annotate(
                f"{word}, t = {m.s.t[j]:.3g} s",
                (m.s.x[j], m.s.y[j]),
                xytext=(7, -7 if word == "start" else 5),
                textcoords="offset points",
                fontsize=7.5,
                color="#444444",
                va="top" if word == "start" else "bottom",
            )

    # the paths, with the direction of motion
    for i, m in enumerate(motions):
        ax.plot(m.s.x, m.s.y, color=POINT, ls=_style(i), lw=1.8, zorder=4, gid=f"path-{i}")
        x, y = m.s.x, m.s.y
        j = int(0.3 * (len(x) - 1))
        if np.all(np.isfinite([x[j], y[j], x[j + 1], y[j + 1]])):
            ax.annotate(
                "",
                xy=(x[j + 1], y[j + 1]),
                xytext=(x[j], y[j]),
                zorder=4,
                arrowprops={"arrowstyle": "-|>", "color": POINT, "lw": 1.2, "mutation_scale": 14},
            )

    # singular points: marker, and order and verdict beside it, where the label hides least
    obs = np.concatenate([o for o in obstacles if o.size])
    obs = obs[np.all(np.isfinite(obs), axis=1)]
    ppu = 72 * min((WIDTH - 3.9) / (x1 - x0), (_path_height(motions) - 1.3) / (y1 - y0))
    boxes: list[tuple[float, float, float, float]] = []
    for i, m in enumerate(motions):
        for k, s in enumerate(m.result.singularities):
            st = status(m.result, s)
            if s.order >= 2:  # a high-order point must stand out: a red ring around it
                ax.plot(
                    [s.x],
                    [0],
                    "o",
                    ms=30,
                    mfc="none",
                    mec=STATUS_COLOUR["fail"],
                    mew=2,
                    alpha=0.8,
                    zorder=5.5,
                    gid=f"path-ring-{i}-{k}",
                )
            ax.plot([s.x], [0], gid=f"path-singular-{i}-{k}", **_marker_kw(s, st))
            if not _labelled(motions):
                continue
            who = f"{_short(m.name)}\n" if len(motions) > 1 else ""
            text = (
                f"{who}t = {s.t:.4g} s: {order_text(s)} — {STATUS_WORD[st].upper()}\n"
                f"{verdict_text(m.result, s)}"
            )
            (dx, dy), box = _place(text, (s.x, 0.0), obs, boxes, ppu, (x0, x1, y0, y1))
            boxes.append(box)
            ax.annotate(
                text,
                (s.x, 0),
                xytext=(dx, dy),
                textcoords="offset points",
                fontsize=7.5,
                va="top" if dy < 0 else "bottom",
                ha="left" if dx > 0 else "right",
                multialignment="left",
                color="black",
                fontweight="bold" if st != "ok" else "normal",
                bbox={
                    "boxstyle": "round,pad=0.25",
                    "fc": "white",
                    "ec": STATUS_COLOUR[st] if st != "ok" else "#999999",
                    "alpha": 0.9,
                },
                arrowprops={
                    "arrowstyle": "-",
                    "color": "#666666",
                    "lw": 0.7,
                    "shrinkA": 0,
                    "shrinkB": 6,
                },
                zorder=8,
                gid=f"path-label-{i}-{k}",
            )
        for k, ks in enumerate(m.result.kinematic_singularities):
            ax.plot(
                [ks.x],
                [ks.y],
                "X",
                ms=11,
                mfc=STATUS_COLOUR["fail"],
                mec="black",
                zorder=6,
                gid=f"path-kinematic-{i}-{k}",
            )

    extra: list[Any] = [
        Line2D(
            [], [], color=LINE, lw=1.1, ls=(0, (7, 2, 1.5, 2)), label="singular line y = 0 (δ = 0)"
        ),
        Line2D([], [], color=LEG1, lw=2.2, label="leg 1 (A–E): θ1, s1"),
        Line2D([], [], color=LEG2, lw=2.2, label="leg 2 (B–E): θ2, s2"),
        *_marker_handles(motions),
    ]
    if any(m.result.kinematic_singularities for m in motions):
        extra.append(
            Line2D(
                [],
                [],
                marker="X",
                ms=9,
                mfc=STATUS_COLOUR["fail"],
                mec="black",
                ls="none",
                label="E at A or B (s = 0)",
            )
        )
    _legend(ax, [("end-point path", POINT)], motions, extra, **_OUTSIDE)
    return [ax]


# ---------------------------------------------------------------------------------------
# time panels


def _panel_x(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    _title(sf, "End-point coordinates (paper Fig. 2)", motions)
    ax_x, ax_y = sf.subplots(1, 2)
    _time_axes(ax_x, motions, "$x_E(t)$", "$x_E$ [m]", "x")
    _time_axes(ax_y, motions, "$y_E(t)$", "$y_E$ [m]", "y")
    ax_y.axhline(0, color=LINE, lw=1.0, ls=(0, (7, 2, 1.5, 2)), zorder=1)
    for i, m in enumerate(motions):
        ax_x.plot(m.s.t, _finite(m.s.x), color=POINT, ls=_style(i), lw=1.6, gid=f"x-{i}")
        ax_y.plot(m.s.t, _finite(m.s.y), color=POINT, ls=_style(i), lw=1.6, gid=f"y-{i}")
    _mark(ax_x, "x", motions, lambda m, s: s.x)
    _mark(ax_y, "y", motions, lambda m, s: 0.0)
    _legend(ax_x, [("$x_E$", POINT)], motions)
    _legend(
        ax_y,
        [("$y_E$", POINT)],
        motions,
        [Line2D([], [], color=LINE, lw=1.0, ls=(0, (7, 2, 1.5, 2)), label="singular line y = 0")],
    )
    return [ax_x, ax_y]


def _vanishing(order: int) -> str:
    """What vanishes at a singular instant of this order: δ and its first order-1 derivatives."""
    names = ["δ", "δ'", "δ''"]
    if order <= 3:
        return " = ".join(names[:order]) + " = 0"
    return f"δ = δ' = … = δ^({order - 1}) = 0"


class _Rows:
    """Stacks labels written beside points along a time axis so that none overlap: each
    label goes to the right of its time (to the left where only that has room), on the
    free level nearest the anchor, above or (with ``below``) under it. Widths are estimated
    from the character count: the layout is not done yet."""

    LINE = 10.5  # points per line of 7.5-point text, with leading

    def __init__(
        self,
        tmax: float,
        *,
        below: bool = False,
        axes_inches: float = WIDTH - 4.0,
        fontsize: float = 7.5,
    ) -> None:
        self.per_char = 0.62 * fontsize / 72 / axes_inches * tmax
        self.pad = 14 / 72 / axes_inches * tmax
        self.tmax = tmax
        self.sides = (1, -1) if below else (1,)
        self.placed: dict[int, list[tuple[float, float, float, float]]] = {1: [], -1: []}

    def place(self, t: float, text: str) -> tuple[int, float, bool]:
        """(side: 1 above, -1 below; level in points from the anchor; written to the left
        of t?) for a label at t."""
        lines = text.split("\n")
        width = self.per_char * max(len(line) for line in lines) + self.pad
        right = t + width > self.tmax and t - width >= 0  # else the right, overflowing
        lo, hi = (t - width, t) if right else (t, t + width)
        height = self.LINE * len(lines) + 3
        best: tuple[float, int] | None = None
        for side in self.sides:
            level = 0.0
            while True:
                hits = [
                    p
                    for p in self.placed[side]
                    if p[0] < hi and lo < p[1] and p[2] < level + height and level < p[3]
                ]
                if not hits:
                    break
                level = max(p[3] for p in hits)
            if best is None or level < best[0]:
                best = (level, side)
        assert best is not None
        level, side = best
        self.placed[side].append((lo, hi, level, level + height))
        return side, level, right


def _panel_delta(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    _title(sf, "Type II determinant (paper Fig. 4)", motions)
    ax = sf.subplots()
    _time_axes(
        ax, motions, r"$\delta(t) = \sin(\theta_1 - \theta_2)$, eq. (29)", r"$\delta$ [–]", "delta"
    )
    ax.axhspan(-NEAR_DELTA, NEAR_DELTA, color="#999999", alpha=0.12, lw=0, zorder=0.2)
    ax.axhline(0, color="#444444", lw=0.8, zorder=0.7)
    for i, m in enumerate(motions):
        ax.plot(m.s.t, _finite(m.s.delta), color=DELTA, ls=_style(i), lw=1.8, gid=f"delta-{i}")
    _mark(ax, "delta", motions, lambda m, s: 0.0)
    rows = _Rows(max(m.duration for m in motions), below=True)
    for i, m in enumerate(motions):
        for k, s in enumerate(m.result.singularities):
            st = status(m.result, s)
            if not _labelled(motions):
                continue
            if len(motions) == 1:
                text = f"t = {s.t:.4g} s: {order_text(s)} ({_vanishing(s.order)})"
            elif len(motions) == 2:
                text = f"{_short(m.name)}\nt = {s.t:.4g} s: {order_text(s)} ({_vanishing(s.order)})"
            else:  # many tasks: one line each, or the labels outgrow the axes
                text = f"{_short(m.name, 28)}: {order_text(s)}"
            side, level, right = rows.place(s.t, text)
            ax.annotate(
                text,
                (s.t, 0),
                ha="right" if right else "left",
                va="bottom" if side > 0 else "top",
                xytext=(-10 if right else 10, side * (8 + level)),
                textcoords="offset points",
                fontsize=7.5,
                color=STATUS_COLOUR["fail"] if st == "fail" else "black",
                fontweight="bold" if s.order >= 2 else "normal",
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.6},
                zorder=8,
                gid=f"delta-label-{i}-{k}",
            )
    extra = [
        *_marker_handles(motions),
        Line2D(
            [], [], color="#999999", alpha=0.35, lw=6, label=f"near singular: |δ| < {NEAR_DELTA:g}"
        ),
    ]
    _legend(ax, [("δ", DELTA)], motions, extra, **_OUTSIDE)
    return [ax]


def _panel_joints(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    _title(sf, "Actuated joints (paper Fig. 5) and leg lengths", motions)
    ax_t, ax_s = sf.subplots(1, 2)
    _time_axes(
        ax_t, motions, r"$\theta_1(t)$, $\theta_2(t)$ (continuous)", r"$\theta$ [deg]", "theta"
    )
    _time_axes(ax_s, motions, r"$s_1(t)$, $s_2(t)$", "$s$ [m]", "s")
    lo, hi = np.inf, -np.inf
    for i, m in enumerate(motions):
        for ax, v, c, name in (
            (ax_t, np.degrees(m.s.theta1), LEG1, "theta1"),
            (ax_t, np.degrees(m.s.theta2), LEG2, "theta2"),
            (ax_s, m.s.s1, LEG1, "s1"),
            (ax_s, m.s.s2, LEG2, "s2"),
        ):
            v = _finite(v)
            ax.plot(m.s.t, v, color=c, ls=_style(i), lw=1.7, gid=f"{name}-{i}")
            if ax is ax_t and np.any(np.isfinite(v)):
                lo, hi = min(lo, float(np.nanmin(v))), max(hi, float(np.nanmax(v)))
    if np.isfinite(lo):
        _degree_ticks(ax_t, lo, hi)
    _legend(ax_t, [(r"$\theta_1$ (joint A)", LEG1), (r"$\theta_2$ (joint B)", LEG2)], motions)
    _legend(ax_s, [("$s_1 = |AE|$", LEG1), ("$s_2 = |BE|$", LEG2)], motions)
    return [ax_t, ax_s]


def _torque_range(motions: Sequence[Motion]) -> tuple[float, float] | None:
    """The y-range of the bounded part of T1, T2: the samples farther than CLIP_WINDOW t_f
    from every unbounded instant, plus the finite limits at bounded instants."""
    vals = []
    for m in motions:
        t = m.s.t
        keep = np.ones(len(t), dtype=bool)
        for s in m.result.singularities:
            if not s.torque_bounded:
                keep &= np.abs(t - s.t) > CLIP_WINDOW * m.duration
        for v in (m.s.T1, m.s.T2):
            ok = keep & np.isfinite(v)
            if not np.any(ok):  # windows cover the motion: fall back on robust quantiles
                ok = np.isfinite(v)
                if np.any(ok):
                    vals += list(np.percentile(v[ok], [10, 90]))
                continue
            vals += [float(v[ok].min()), float(v[ok].max())]
        for s in m.result.singularities:
            if s.torque_at_singularity is not None:
                vals += [float(x) for x in s.torque_at_singularity if np.isfinite(x)]
    if not vals:
        return None
    lo, hi = min(vals), max(vals)
    pad = max(0.12 * (hi - lo), 0.05 * max(abs(lo), abs(hi)), 1e-6)
    return lo - pad, hi + pad


def _panel_torques(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    _title(sf, "Motor torques (eq. 28)", motions)
    ax = sf.subplots()
    _time_axes(ax, motions, r"$T_1(t)$, $T_2(t)$", "$T$ [N m]", "torques")
    extra: list[Any] = []
    rng = _torque_range(motions)
    lo, hi = rng if rng is not None else (-1.0, 1.0)
    scale = max(abs(lo), abs(hi))

    # torque limits, as bands beyond ±limit
    # the distinct limits, each with the tasks that set it
    owners: dict[tuple[float, float], list[str]] = {}
    for m in motions:
        if m.task.checks.torque_limit is not None:
            pair = (float(m.task.checks.torque_limit[0]), float(m.task.checks.torque_limit[1]))
            owners.setdefault(pair, []).append(m.name)
    limits = sorted(owners)
    notes = []
    shown: list[tuple[float, str, str, str]] = []  # limit, colour, who, gid tag
    for L1, L2 in limits:
        pairs = (
            [(L1, LINE, "|T1|, |T2|", "T")]
            if L1 == L2
            else [(L1, LEG1, "|T1|", "T1"), (L2, LEG2, "|T2|", "T2")]
        )
        whose = "" if len(owners[L1, L2]) == len(motions) else f" ({', '.join(owners[L1, L2])})"
        for L, colour, who, tag in pairs:
            if LIMIT_SHOWN * scale < L:
                notes.append(f"{who} limit {L:g} N m{whose}: above the plotted range")
                continue
            lo, hi = min(lo, -1.08 * L), max(hi, 1.08 * L)
            shown.append((L, colour, f"{who} limit ±{L:g} N m{whose}", f"{tag}-{L:g}"))
    for L, colour, who, tag in shown:
        ax.axhspan(
            L, hi, color=colour, alpha=0.09, lw=0, zorder=0.3, gid=f"torque-limit-{tag}-upper"
        )
        ax.axhspan(
            lo, -L, color=colour, alpha=0.09, lw=0, zorder=0.3, gid=f"torque-limit-{tag}-lower"
        )
        for v in (L, -L):
            ax.axhline(v, color=colour, lw=0.9, alpha=0.8, zorder=0.4)
        extra.append(Line2D([], [], color=colour, alpha=0.5, lw=6, label=f"beyond the {who}"))
    ax.set_ylim(lo, hi)

    for i, m in enumerate(motions):
        ax.plot(m.s.t, _finite(m.s.T1), color=LEG1, ls=_style(i), lw=1.6, gid=f"T1-{i}")
        ax.plot(m.s.t, _finite(m.s.T2), color=LEG2, ls=_style(i), lw=1.6, gid=f"T2-{i}")

    # bounded limits at the singular instants; unbounded instants marked where T diverges
    top = blended_transform_factory(ax.transData, ax.transAxes)
    rows = _Rows(max(m.duration for m in motions))
    diverging = False
    for i, m in enumerate(motions):
        for k, s in enumerate(m.result.singularities):
            if s.torque_at_singularity is not None:
                for v, c, q in zip(
                    s.torque_at_singularity, (LEG1, LEG2), ("T1", "T2"), strict=True
                ):
                    ax.plot(
                        [s.t],
                        [v],
                        "o",
                        ms=6,
                        mfc="white",
                        mec=c,
                        mew=1.6,
                        zorder=6,
                        gid=f"torques-limit-{i}-{k}-{q}",
                    )
                continue
            diverging = True
            ax.axvline(
                s.t,
                color=STATUS_COLOUR["fail"],
                lw=1.4,
                ls="--",
                zorder=5,
                gid=f"torques-unbounded-{i}-{k}",
            )
            if not _labelled(motions):
                continue
            who = f"{_short(m.name)}:\n" if len(motions) > 1 else ""
            note = f"{who}T → ∞ at t = {s.t:.4g} s (pole of order {s.pole_order})"
            _, level, right = rows.place(s.t, note)
            ax.annotate(
                note,
                (s.t, 1.0),
                xycoords=top,
                xytext=(-4 if right else 4, -4 - level),
                textcoords="offset points",
                ha="right" if right else "left",
                va="top",
                fontsize=7.5,
                color=STATUS_COLOUR["fail"],
                fontweight="bold",
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.85},
                zorder=9,
            )
            for series, c, q in ((m.s.T1, LEG1, "T1"), (m.s.T2, LEG2, "T2")):
                for tx, up in _exits(m.s.t, series, s.t, m.duration, lo, hi):
                    side = "before" if tx < s.t else "after"
                    ax.plot(
                        [tx],
                        [hi if up else lo],
                        marker="^" if up else "v",
                        ms=8,
                        color=c,
                        mec="black",
                        mew=0.6,
                        ls="none",
                        clip_on=False,
                        zorder=9,
                        gid=f"torques-exit-{i}-{k}-{q}-{side}",
                    )
    if any(s.torque_at_singularity is not None for m in motions for s in m.result.singularities):
        extra.append(
            Line2D(
                [],
                [],
                marker="o",
                ms=6,
                mfc="white",
                mec="#555555",
                mew=1.6,
                ls="none",
                label="finite limit at t_s",
            )
        )
    if diverging:
        extra.append(
            Line2D(
                [],
                [],
                marker="^",
                ms=7,
                color="#777777",
                mec="black",
                ls="none",
                label="leaves the axis: diverges",
            )
        )
    if rng is None:
        ax.text(
            0.5,
            0.5,
            "no bounded torque sample",
            transform=ax.transAxes,
            ha="center",
            color=STATUS_COLOUR["fail"],
        )
    for j, note in enumerate(notes):
        ax.text(0.01, 0.03 + 0.07 * j, note, transform=ax.transAxes, fontsize=7.5, color="#8B0000")
    _legend(ax, [("$T_1$ (joint A)", LEG1), ("$T_2$ (joint B)", LEG2)], motions, extra, **_OUTSIDE)
    return [ax]


def _exits(
    t: np.ndarray, v: np.ndarray, ts: float, duration: float, lo: float, hi: float
) -> list[tuple[float, bool]]:
    """Where, approaching t_s from each side, the curve v first leaves [lo, hi]:
    (time, leaves upwards?)."""
    out = []
    w = CLIP_WINDOW * duration
    for side in (-1, 1):
        idx = np.nonzero((side * (t - ts) > 0) & (np.abs(t - ts) <= w) & np.isfinite(v))[0]
        idx = idx[np.argsort(np.abs(t[idx] - ts))]  # nearest t_s first, then outwards
        out_of = (v[idx] > hi) | (v[idx] < lo)
        if idx.size == 0 or not out_of[0]:
            continue
        run = len(idx) if np.all(out_of) else int(np.argmin(out_of))
        j = idx[run - 1]  # the last sample outside the axis, walking away from t_s
        out.append((float(t[j]), bool(v[j] > hi)))
    return out


# ---------------------------------------------------------------------------------------
# the sheet


_DRAW: dict[str, Callable[[SubFigure, Sequence[Motion]], list[Axes]]] = {
    "path": _panel_path,
    "x": _panel_x,
    "delta": _panel_delta,
    "joints": _panel_joints,
    "torques": _panel_torques,
}
_HEIGHT: dict[str, Callable[[Sequence[Motion]], float]] = {
    "path": _path_height,
    "x": lambda ms: 3.0,
    "delta": lambda ms: 3.2,
    "joints": lambda ms: 3.0,
    "torques": lambda ms: 3.4,
}


def title(motions: Sequence[Motion]) -> str:
    """The sheet's title: rprpr's version, then one summary line per task."""
    return "\n".join([f"rprpr {__version__} audit sheet", *(summary(m) for m in motions)])


def render(
    motions: Sequence[Motion], panels: Sequence[str] = PANELS, *, figure: Figure | None = None
) -> Figure:
    """The audit sheet of ``motions`` (overlaid) with ``panels`` in order, on a new headless
    ``Figure`` or on ``figure`` (e.g. one of pyplot's, for --show). The layout is
    constrained and done when the sheet is saved or drawn (text extents depend on the
    resolution, so it is not fixed in advance)."""
    unknown = [p for p in panels if p not in _DRAW]
    if unknown or not panels:
        raise ValueError(f"unknown panels {unknown}; choose from {', '.join(PANELS)}")
    if not motions:
        raise ValueError("nothing to plot")
    with matplotlib.rc_context(RC):
        heights = [_HEIGHT[p](motions) for p in panels]
        size = (WIDTH, sum(heights) + 0.5 + 0.2 * len(motions))
        if figure is None:
            fig = Figure(figsize=size, layout="constrained")
        else:
            fig = figure
            fig.set_size_inches(*size)
            fig.set_layout_engine("constrained")
        fig.suptitle(title(motions), fontsize=10, linespacing=1.5)
        subs = fig.subfigures(len(panels), 1, height_ratios=heights, squeeze=False)[:, 0]
        for name, sf in zip(panels, subs, strict=True):
            sf.set_gid(f"panel-{name}")
            _DRAW[name](sf, motions)
    return fig


def format_of(path: str) -> str:
    """The sheet format from a file name's extension (raises ValueError if unsupported)."""
    from pathlib import Path

    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(f"unsupported sheet format {suffix!r}; use {', '.join(FORMATS)}")
    return FORMATS[suffix]


def _description(motions: Sequence[Motion]) -> str:
    out = []
    for m in motions:
        sings = "; ".join(
            f"t = {s.t:.6g} s order {s.order} {status(m.result, s)}" for s in m.result.singularities
        )
        out.append(f"{m.name}: {m.result.verdict}" + (f" ({sings})" if sings else ""))
    return " | ".join(out)


def metadata(motions: Sequence[Motion], fmt: str) -> dict[str, Any]:
    """File metadata naming the tasks: PNG tEXt chunks, SVG Dublin Core, PDF Info."""
    title = "rprpr audit sheet: " + "; ".join(m.name for m in motions)
    creator = f"rprpr {__version__} (matplotlib {matplotlib.__version__})"
    desc = _description(motions)
    if fmt == "png":
        return {"Title": title, "Software": creator, "Description": desc}
    if fmt == "svg":
        return {"Title": title, "Creator": creator, "Description": desc, "Date": None}
    return {"Title": title, "Creator": creator, "Subject": desc, "CreationDate": None}


def save(
    fig: Figure,
    target: str | IO[bytes],
    fmt: str,
    *,
    dpi: int = 150,
    motions: Sequence[Motion] = (),
) -> None:
    """Write the sheet as ``fmt`` ("png", "svg", "pdf") to a path or binary stream, with
    ``metadata(motions)`` when the motions are given."""
    meta = metadata(motions, fmt) if motions else None
    with matplotlib.rc_context(RC), warnings.catch_warnings():
        # a crowded sheet (dozens of instants) still draws; matplotlib's layout note
        # about it is no news to the user
        warnings.filterwarnings("ignore", message="constrained_layout not applied")
        fig.savefig(target, format=fmt, dpi=dpi, metadata=meta)


def can_show() -> bool:
    """Whether pyplot has an interactive backend (a window can open)."""
    import matplotlib.pyplot as plt
    from matplotlib.backends.registry import BackendFilter, backend_registry

    interactive = backend_registry.list_builtin(BackendFilter.INTERACTIVE)  # type: ignore[no-untyped-call]
    return plt.get_backend().lower() in interactive
