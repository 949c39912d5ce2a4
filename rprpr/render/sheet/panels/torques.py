"""The ``torques`` panel: the motor torques T1, T2 (eq. 28).

Where a torque is unbounded the axis keeps the bounded part (the range outside
``CLIP_WINDOW`` t_f of each unbounded instant), a dashed line marks t_s and ▲/▼ mark
where each curve leaves the axes; at a bounded instant a ring marks each torque's finite
limit; ``checks.torque_limit`` is drawn as bands beyond ±limit."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import SubFigure
from matplotlib.lines import Line2D
from matplotlib.transforms import blended_transform_factory

from ....engine.singular import SingularInstant
from ....model.numbers import number
from ..axes import OUTSIDE, legend, panel_title, time_axes
from ..labels import Rows, labelled
from ..motion import Motion, finite
from ..style import LABEL_SIZE, LEG1, LEG2, LINE, STATUS_COLOUR, style
from ..words import instant_times, short

CLIP_WINDOW = 0.1  # fraction of t_f about an unbounded instant left out when scaling T
LIMIT_SHOWN = 10.0  # a torque limit beyond this multiple of the plotted range is only noted
TORQUES = ((LEG1, "T1"), (LEG2, "T2"))  # colour and name of each motor's torque

# the line at an unbounded instant t_s
_UNBOUNDED: dict[str, Any] = {"color": STATUS_COLOUR["fail"], "lw": 1.4, "ls": "--", "zorder": 5}

Limit = tuple[float, str, str, str]  # the limit [N m], colour, legend text, gid tag


def height(motions: Sequence[Motion]) -> float:
    return 3.4


def draw(sf: SubFigure, motions: Sequence[Motion]) -> list[Axes]:
    panel_title(sf, "Motor torques (eq. 28)", motions)
    ax = sf.subplots()
    time_axes(ax, motions, r"$T_1(t)$, $T_2(t)$", "$T$ [N m]", "torques")
    rng = torque_range(motions)
    lo, hi = rng if rng is not None else (-1.0, 1.0)
    shown, notes = _limits(motions, max(abs(lo), abs(hi)))
    for L, *_ in shown:  # a band drawn is a band seen
        lo, hi = min(lo, -1.08 * L), max(hi, 1.08 * L)
    extra = _limit_bands(ax, shown, lo, hi)
    ax.set_ylim(lo, hi)
    for i, m in enumerate(motions):
        for v, (c, q) in zip((m.s.T1, m.s.T2), TORQUES, strict=True):
            ax.plot(m.s.t, finite(v), color=c, ls=style(i), lw=1.6, gid=f"{q}-{i}")
    extra += _instants(ax, motions, lo, hi)
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
        ax.text(
            0.01,
            0.03 + 0.07 * j,
            note,
            transform=ax.transAxes,
            fontsize=LABEL_SIZE,
            color="#8B0000",
        )
    legend(ax, [("$T_1$ (joint A)", LEG1), ("$T_2$ (joint B)", LEG2)], motions, extra, **OUTSIDE)
    return [ax]


def torque_range(motions: Sequence[Motion]) -> tuple[float, float] | None:
    """The y-range of the bounded part of T1, T2: the samples farther than CLIP_WINDOW t_f
    from every unbounded instant, plus the finite limits at bounded instants."""
    vals = []
    for m in motions:
        keep = np.ones(len(m.s.t), dtype=bool)
        for s in m.result.singularities:
            if not s.torque_bounded:
                keep &= np.abs(m.s.t - s.t) > CLIP_WINDOW * m.duration
        for v in (m.s.T1, m.s.T2):
            vals += _bounded_extremes(v, keep)
        for s in m.result.singularities:
            if s.torque_at_singularity is not None:
                vals += [float(x) for x in s.torque_at_singularity if np.isfinite(x)]
    if not vals:
        return None
    lo, hi = min(vals), max(vals)
    pad = max(0.12 * (hi - lo), 0.05 * max(abs(lo), abs(hi)), 1e-6)
    return lo - pad, hi + pad


def _bounded_extremes(v: np.ndarray, keep: np.ndarray) -> list[float]:
    """The least and greatest finite ``v`` where ``keep``; where the windows cover the
    motion, robust quantiles of every finite ``v`` instead."""
    ok = keep & np.isfinite(v)
    if np.any(ok):
        return [float(v[ok].min()), float(v[ok].max())]
    ok = np.isfinite(v)
    return list(np.percentile(v[ok], [10, 90])) if np.any(ok) else []


def _limits(motions: Sequence[Motion], scale: float) -> tuple[list[Limit], list[str]]:
    """The torque limits to draw as bands, and notes on those far beyond ``scale`` (the
    largest |T| plotted): one limit for both torques where they are equal, each with the
    tasks that set it when not all do."""
    owners: dict[tuple[float, float], list[str]] = {}
    for m in motions:
        if m.task.checks.torque_limit is not None:
            pair = (float(m.task.checks.torque_limit[0]), float(m.task.checks.torque_limit[1]))
            owners.setdefault(pair, []).append(m.name)
    shown: list[Limit] = []
    notes = []
    for L1, L2 in sorted(owners):
        pairs = (
            [(L1, LINE, "|T1|, |T2|", "T")]
            if L1 == L2
            else [(L1, LEG1, "|T1|", "T1"), (L2, LEG2, "|T2|", "T2")]
        )
        who = owners[L1, L2]
        whose = "" if len(who) == len(motions) else f" ({', '.join(who)})"
        for L, colour, which, tag in pairs:
            if LIMIT_SHOWN * scale < L:
                notes.append(f"{which} limit {number(L)} N m{whose}: above the plotted range")
            else:
                text = f"{which} limit ±{number(L)} N m{whose}"
                shown.append((L, colour, text, f"{tag}-{number(L)}"))
    return shown, notes


def _limit_bands(ax: Axes, shown: list[Limit], lo: float, hi: float) -> list[Any]:
    """Each limit as bands beyond ±limit, up to the axis's ends; their legend entries."""
    extra: list[Any] = []
    for L, colour, text, tag in shown:
        band: dict[str, Any] = {"color": colour, "alpha": 0.09, "lw": 0, "zorder": 0.3}
        ax.axhspan(L, hi, gid=f"torque-limit-{tag}-upper", **band)
        ax.axhspan(lo, -L, gid=f"torque-limit-{tag}-lower", **band)
        for v in (L, -L):
            ax.axhline(v, color=colour, lw=0.9, alpha=0.8, zorder=0.4)
        extra.append(Line2D([], [], color=colour, alpha=0.5, lw=6, label=f"beyond the {text}"))
    return extra


def _instants(ax: Axes, motions: Sequence[Motion], lo: float, hi: float) -> list[Any]:
    """At each singular instant the torques' finite limits, or where they diverge; the
    legend entries of what was drawn."""
    rows = Rows(max(m.duration for m in motions))
    finite_limit = diverging = False
    for i, m in enumerate(motions):
        times = instant_times(m.result)
        for k, s in enumerate(m.result.singularities):
            if s.torque_at_singularity is not None:
                _finite_limits(ax, s, f"{i}-{k}")
                finite_limit = True
                continue
            diverging = True
            ax.axvline(s.t, gid=f"torques-unbounded-{i}-{k}", **_UNBOUNDED)
            if labelled(motions):
                who = f"{short(m.name)}:\n" if len(motions) > 1 else ""
                note = f"{who}T → ∞ at t = {times[k]} s (pole of order {s.pole_order})"
                _divergence_note(ax, note, s.t, rows)
                _exit_marks(ax, m, s, f"{i}-{k}", lo, hi)
    return _instant_handles(finite_limit, diverging)


def _instant_handles(finite_limit: bool, diverging: bool) -> list[Any]:
    """The legend entries of a finite limit's ring and of a divergence's ▲, if drawn."""
    extra: list[Any] = []
    if finite_limit:
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
    return extra


def _finite_limits(ax: Axes, s: SingularInstant, tag: str) -> None:
    """A ring at each torque's finite limit at t_s."""
    assert s.torque_at_singularity is not None
    for v, (c, q) in zip(s.torque_at_singularity, TORQUES, strict=True):
        ax.plot(
            [s.t],
            [v],
            "o",
            ms=6,
            mfc="white",
            mec=c,
            mew=1.6,
            zorder=6,
            gid=f"torques-limit-{tag}-{q}",
        )


def _divergence_note(ax: Axes, note: str, t: float, rows: Rows) -> None:
    """``note`` at the top of the axes beside t, stacked clear of the other notes."""
    _, level, right = rows.place(t, note)
    ax.annotate(
        note,
        (t, 1.0),
        xycoords=blended_transform_factory(ax.transData, ax.transAxes),
        xytext=(-4 if right else 4, -4 - level),
        textcoords="offset points",
        ha="right" if right else "left",
        va="top",
        fontsize=LABEL_SIZE,
        color=STATUS_COLOUR["fail"],
        fontweight="bold",
        bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.85},
        zorder=9,
    )


def _exit_marks(ax: Axes, m: Motion, s: SingularInstant, tag: str, lo: float, hi: float) -> None:
    """▲ or ▼ on the axis's edge where each torque leaves it approaching t_s."""
    for v, (c, q) in zip((m.s.T1, m.s.T2), TORQUES, strict=True):
        for tx, up in exits(m.s.t, v, s.t, m.duration, lo, hi):
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
                gid=f"torques-exit-{tag}-{q}-{side}",
            )


def exits(
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
