"""The ``torques`` panel: the motor torques T1, T2 (eq. 28).

The axis is scaled to the bounded part of the torques (the samples farther than
``CLIP_WINDOW`` t_f from every unbounded instant, and the finite limits at bounded
instants). A task's torque limit is drawn as lines at ±limit in that task's colour when
it lies near that range; when far outside it is marked at the axis's right edge instead
(▲ ▼), never stretching the axis. Where the certified check finds |T_i| above its limit
(``AuditResult.torque_limit`` windows, around an unbounded instant the
``AuditResult.saturation`` ones) the curve's excess over the limit is shaded. At an
unbounded instant a dashed line marks t_s and ▲/▼ where each curve leaves the axis; at a
bounded one a ring marks each torque's finite limit. Each instant is keyed by number at
the axis's top; the lane says what, and with ``pole_inset`` shows log|T| against
log|t - t_s| near the first unbounded instant: the slope is minus the pole's order."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.lines import Line2D
from matplotlib.transforms import blended_transform_factory

from ....engine.bounds.verdicts import Window
from ....engine.exact.singular import SingularInstant
from ....model.actuation import REVOLUTE, SCHEMES
from ....model.numbers import number
from ..axes import handles, instant_lines, knot_handles, look
from ..drawing import RPRPR_DRAWING, drawing
from ..markers import arrow_mark, badge, mark_handle, nest
from ..motion import Motion, finite
from ..page import Indexed, Sheet
from ..style import LEG1, LEG2, STATUS_COLOUR, pt, task_colour

ROW = 2.2  # in
CLIP_WINDOW = 0.1  # fraction of t_f about an unbounded instant left out when scaling T
LIMIT_NEAR = 1.6  # a limit within this multiple of the largest |T| shown is drawn as lines
TORQUES = ((LEG1, "T1"), (LEG2, "T2"))  # colour and name of each motor's torque
LIMIT_DASH: Any = (0, (6, 2, 1.2, 2))

# the line at an unbounded instant t_s
_UNBOUNDED: dict[str, Any] = {"color": STATUS_COLOUR["fail"], "lw": 1.2, "ls": "--", "zorder": 5}


def efforts(motions: Sequence[Motion]) -> tuple[str, str, tuple[str, str]]:
    """The panel's heading, y label and legend names for the motions' actuation schemes:
    the motor torques T [N m] (the paper), the legs' forces F [N] (all prismatic), or
    both named when the sheet overlays the two schemes."""
    kinds = {m.task.robot.actuation for m in motions}
    if kinds <= {REVOLUTE}:
        paper = "" if RPRPR_DRAWING not in map(drawing, motions) else ", eq. (28)"
        return f"Motor torques T1, T2{paper}", "$T$ [N m]", ("$T_1$ (joint A)", "$T_2$ (joint B)")
    if REVOLUTE not in kinds:
        return (
            "Leg forces F1, F2 (prismatic actuation)",
            "$F$ [N]",
            ("$F_1$ (leg A)", "$F_2$ (leg B)"),
        )
    return (
        "Actuator efforts: torques T [N m] (revolute), forces F [N] (prismatic)",
        "$T$ [N m], $F$ [N]",
        ("$T_1$, $F_1$ (leg A)", "$T_2$, $F_2$ (leg B)"),
    )


def draw(sheet: Sheet, pole_inset: bool = False) -> list[Axes]:
    heading, _, names = efforts(sheet.motions)
    sheet.heading(heading)
    # N m and N never on one y axis: small multiples share y only among columns in one
    # unit; overlaid, a second scheme's efforts take a second y axis, on the right
    parts = [_by_scheme(col) for col in sheet.columns]
    groups = [p[0][0] for p in parts]
    (row,) = sheet.rows("torques", (ROW,), groups=groups)
    ranges = {
        k: _axis([m for p in parts for kk, sub in p if kk == k for _, m in sub])
        for k in dict.fromkeys(k for p in parts for k, _ in p)
    }
    scales = {i: ranges[k][2] for p in parts for k, sub in p for i, _ in sub}
    for n, (ax, col, p) in enumerate(zip(row, sheet.columns, parts, strict=True)):
        instant_lines(ax, col, "torques")
        for j, (k, sub) in enumerate(p):
            on = ax
            if j:
                on = ax.twinx()
                on.set_gid("panel-torques-twin")
                on.grid(False)
            lo, hi, scale, bounded = ranges[k]
            if j or n == groups.index(k):
                on.set_ylim(lo, hi)
            if j or n == 0 or groups[n - 1] != k:  # each run of columns in one unit says it
                on.set_ylabel(efforts([m for _, m in sub])[1])
            _efforts(sheet, on, sub, lo, hi, scale)
            if not bounded:
                on.text(0.5, 0.5, "no bounded torque sample", transform=on.transAxes, ha="center")
    legend = [*handles(sheet, [(names[0], LEG1), (names[1], LEG2)])]
    legend += [*_extra_handles(sheet), *knot_handles(sheet)]
    pole = _first_pole(sheet.motions) if pole_inset else None
    inset = sheet.lane(row[-1], legend, notes(sheet, scales), inset=pole is not None)
    if inset is not None and pole is not None:
        pole_plot(inset, *pole)
    return row


def _by_scheme(col: Indexed) -> list[tuple[str, Indexed]]:
    """A column's tasks by actuation scheme, in the order the schemes first appear; a 5R's
    apart from the RPRPR's (robots of another size: small multiples share y only within
    one mechanism)."""
    out: dict[str, Indexed] = {}
    for i, m in col:
        d = drawing(m)
        key = m.task.robot.actuation + ("" if d is RPRPR_DRAWING else f" {d.name}")
        out.setdefault(key, []).append((i, m))
    return list(out.items())


def _efforts(sheet: Sheet, ax: Axes, col: Indexed, lo: float, hi: float, scale: float) -> None:
    """The efforts of the tasks ``col`` (one scheme) on ``ax`` over [lo, hi]: the curves,
    the limits, the saturation, the instants and the knots' jumps."""
    for i, m in col:
        for j, (v, (c, q)) in enumerate(zip((m.s.T1, m.s.T2), TORQUES, strict=True)):
            kw = look(sheet, i, c, j, pair=True)
            ax.plot(m.s.t, finite(v), lw=1.5, gid=f"{q}-{i}", **kw)
    _limit_lines(sheet, ax, col, scale, lo, hi)
    _saturation(sheet, ax, col, lo, hi)
    _robust(sheet, ax, col, lo, hi)
    _instants(sheet, ax, col, lo, hi)
    _jumps(ax, col, sheet)


def _axis(motions: Sequence[Motion]) -> tuple[float, float, float, bool]:
    """The y-limits of the efforts of ``motions`` (their bounded part, and the limits
    near it), the largest |effort| shown, and whether any sample is bounded."""
    rng = torque_range(motions)
    lo, hi = rng if rng is not None else (-1.0, 1.0)
    scale = max(abs(lo), abs(hi))
    for _, L in _limits(motions):
        if LIMIT_NEAR * scale >= L:
            lo, hi = min(lo, -1.07 * L), max(hi, 1.07 * L)
    return lo, hi, scale, rng is not None


def _limits(motions: Sequence[Motion]) -> list[tuple[int, float]]:
    """(task, limit [N m]) of every torque limit set."""
    out = []
    for i, m in enumerate(motions):
        if m.task.checks.torque_limit is not None:
            out += [(i, float(v)) for v in m.task.checks.torque_limit]
    return out


def _limit_colour(sheet: Sheet, i: int, j: int, m: Motion) -> str:
    """A limit's colour: its task's in an overlay, else its leg's (grey when both are
    equal)."""
    if sheet.overlay:
        return task_colour(i)
    L = m.task.checks.torque_limit
    assert L is not None
    return "#444444" if L[0] == L[1] else TORQUES[j][0]


def _limit_lines(sheet: Sheet, ax: Axes, col: Indexed, scale: float, lo: float, hi: float) -> None:
    """Each task's limits as lines at ±limit, or as ▲ ▼ on the right edge when far off."""
    edge = blended_transform_factory(ax.transAxes, ax.transData)
    for i, m in col:
        L = m.task.checks.torque_limit
        if L is None:
            continue
        for j, v in enumerate(sorted({float(L[0]), float(L[1])})):
            colour = _limit_colour(sheet, i, j if L[0] != L[1] else 0, m)
            if v <= LIMIT_NEAR * scale:
                for sign in (1, -1):
                    ax.axhline(
                        sign * v,
                        color=colour,
                        lw=1.0,
                        ls=LIMIT_DASH,
                        zorder=0.8,
                        gid=f"torque-limit-{i}-{j}-{'upper' if sign > 0 else 'lower'}",
                    )
            else:
                for y, up, end in ((hi, True, "upper"), (lo, False, "lower")):
                    gid = f"torque-limit-{i}-{j}-edge-{end}"
                    arrow_mark(ax, 1.0, y, up, colour, gid, 7, transform=edge)


def _saturation(sheet: Sheet, ax: Axes, col: Indexed, lo: float, hi: float) -> None:
    """Where the certified check finds |T_j| > limit: the curve's excess shaded."""
    for i, m in col:
        checks = m.result.torque_limit
        if checks is None:
            continue
        for j, check in enumerate(checks):
            colour = look(sheet, i, TORQUES[j][0], j, pair=True)["color"]
            for n, w in enumerate(check.windows):
                t = _window_times(m, w)
                v = getattr(m.result.resample(t), TORQUES[j][1])
                shown = np.clip(np.where(np.isfinite(v), v, np.sign(v) * hi), lo, hi)
                over = np.abs(v) > check.limit
                ax.fill_between(
                    t,
                    np.sign(v) * check.limit,
                    shown,
                    where=over,
                    color=colour,
                    alpha=0.28,
                    lw=0,
                    zorder=0.9,
                    gid=f"torques-saturation-{i}-{j}-{n}",
                )


def _robust(sheet: Sheet, ax: Axes, col: Indexed, lo: float, hi: float) -> None:
    """With declared uncertainty, about each singular instant: the band every effort the
    box allows lies in (``engine.robust.worst``, proven), and the proven saturation window
    shaded (gids ``torques-band-<task>-<k>-T1``, ``torques-window-<task>-<k>``)."""
    from ....engine.robust.worst import effort_bands

    for i, m in col:
        if m.task.uncertainty is None or not m.result.robust:
            continue
        for k, (s, r) in enumerate(zip(m.result.singularities, m.result.robust, strict=False)):
            half = CLIP_WINDOW * m.duration
            t = s.t + np.outer([-1, 1], half * np.logspace(0, -6, 120)).ravel()
            t = np.sort(t[(t >= 0) & (t <= m.duration)])
            bands = effort_bands(m.result.task, m.result.parts, t)
            for j, (b_lo, b_hi) in enumerate(bands):
                colour = look(sheet, i, TORQUES[j][0], j, pair=True)["color"]
                ax.fill_between(
                    t,
                    np.clip(b_lo, lo, hi),
                    np.clip(b_hi, lo, hi),
                    color=colour,
                    alpha=0.12,
                    lw=0,
                    zorder=0.7,
                    gid=f"torques-band-{i}-{k}-{TORQUES[j][1]}",
                )
            if r.span is not None:
                ax.axvspan(
                    *r.span,
                    color=STATUS_COLOUR["fail"],
                    alpha=0.25,
                    lw=0.6,
                    zorder=0.75,
                    gid=f"torques-window-{i}-{k}",
                )


def _window_times(m: Motion, w: Window) -> np.ndarray:
    """Times over a window, denser towards an unbounded instant inside it."""
    t = np.linspace(w.start_lo, w.end_hi, 240)
    for s in m.result.singularities:
        if not s.torque_bounded and w.start_lo < s.t < w.end_hi:
            near = s.t + np.outer([-1, 1], (w.end_hi - w.start_lo) * np.logspace(-1, -6, 30))
            t = np.union1d(t, near.ravel())
    return t[(t >= 0) & (t <= m.duration)]


def _instants(sheet: Sheet, ax: Axes, col: Indexed, lo: float, hi: float) -> None:
    """At each singular instant its key at the axis's top; the torques' finite limits,
    or the line at t_s and where the curves leave the axis."""
    pts = [((i, k), s.t, 0.0, 0.0) for i, m in col for k, s in enumerate(m.result.singularities)]
    placed = nest(pts, (0.01 * sheet.duration, 1.0))
    for i, m in col:
        colours = [look(sheet, i, c, j, pair=True)["color"] for j, (c, _) in enumerate(TORQUES)]
        for k, s in enumerate(m.result.singularities):
            if s.torque_at_singularity is not None:
                _finite_limits(ax, s, f"{i}-{k}", colours)
            else:
                ax.axvline(s.t, gid=f"torques-unbounded-{i}-{k}", **_UNBOUNDED)
                _exit_marks(ax, m, s, f"{i}-{k}", lo, hi, colours)
            if (i, k) in sheet.keys:
                key = sheet.keys[i, k]
                badge(ax, key, (s.t, hi), placed[i, k].dx + 8, -10, f"torques-key-{i}-{k}")


JUMP: dict[str, Any] = {"lw": 2.4, "marker": "_", "ms": 9, "mew": 2.0, "zorder": 5.5}


def jumps(m: Motion) -> list[tuple[float, tuple[float, float], tuple[float, float]]]:
    """(t_k, (T1, T2) before, (T1, T2) after) at each knot where the audit finds RPR204
    (the acceleration, and so the torques, jump) with the torques defined on both sides."""
    at = {f.t for f in m.result.findings if f.rule == "RPR204"}
    out = []
    for k in m.result.knot_jumps:
        before, after = k.torques
        if k.t in at and before is not None and after is not None:
            out.append((k.t, before, after))
    return out


def _jumps(ax: Axes, col: Indexed, sheet: Sheet) -> None:
    """Each RPR204 torque jump at a knot: a bar from each torque's value just before the
    knot to its value just after, at t_k, in the torque's colour (gid
    ``torques-jump-<task>-<n>-T1``)."""
    for i, m in col:
        colours = [look(sheet, i, c, j, pair=True)["color"] for j, (c, _) in enumerate(TORQUES)]
        for n, (t, before, after) in enumerate(jumps(m)):
            for j, (_, q) in enumerate(TORQUES):
                ax.plot(
                    [t, t],
                    [before[j], after[j]],
                    color=colours[j],
                    gid=f"torques-jump-{i}-{n}-{q}",
                    **JUMP,
                )


def _extra_handles(sheet: Sheet) -> list[Any]:
    """The legend entries of the limits, the saturation, a finite limit's ring, and a
    divergence's ▲, where drawn."""
    out: list[Any] = []
    ms = sheet.motions
    limited = [m for m in ms if m.task.checks.torque_limit is not None]
    if limited:
        out.append(
            Line2D([], [], color="#444444", lw=1.0, ls=LIMIT_DASH, label=limit_label(limited))
        )
    over = [
        m for m in ms if m.result.torque_limit and any(c.windows for c in m.result.torque_limit)
    ]
    if over:
        letters = "|".join(dict.fromkeys(SCHEMES[m.task.robot.actuation].letter for m in over))
        label = f"|{letters}| > L (certified)"
        out.append(Line2D([], [], color="#999999", alpha=0.5, lw=6, label=label))
    if any(m.result.robust for m in ms):
        out.append(Line2D([], [], color="#999999", alpha=0.3, lw=6, label="over the box (proven)"))
        window = Line2D([], [], color=STATUS_COLOUR["fail"], alpha=0.4, lw=6)
        window.set_label("saturation window (proven)")
        out.append(window)
    if any(s.torque_at_singularity is not None for m in ms for s in m.result.singularities):
        out.append(mark_handle("finite limit at t_s", "o", "white", "#555555", mew=1.6))
    if any(not s.torque_bounded for m in ms for s in m.result.singularities):
        out.append(mark_handle("leaves the axis: diverges", "^", "#777777", "black", 7))
    if any(jumps(m) for m in ms):
        letters = "|".join(dict.fromkeys(SCHEMES[m.task.robot.actuation].letter for m in ms))
        label = f"{letters} jump at a knot (RPR204)"
        out.append(Line2D([], [], color="#555555", label=label, **{**JUMP, "zorder": 1}))
    return out


def limit_label(motions: Sequence[Motion]) -> str:
    """The limit lines' legend entry, in the words of the tasks' actuation schemes: a
    torque limit [N m] (revolute), a force limit [N] (prismatic), or both."""
    kinds = [SCHEMES[k] for k in dict.fromkeys(m.task.robot.actuation for m in motions)]
    if len(kinds) == 1:
        e = kinds[0]
        return f"{'torque' if e.letter == 'T' else 'force'} limit ±L [{e.unit}]"
    return "limit ±L (T in N m, F in N)"


def notes(sheet: Sheet, scales: dict[int, float]) -> list[str]:
    """The keys of the instants (finite limits, or where T diverges and how long |T|
    stays above its limit) and each task's limit (beyond its axis when above
    ``LIMIT_NEAR`` times the largest |T| task i's axis shows, ``scales[i]``)."""
    out = []
    for i, m in enumerate(sheet.motions):
        scale = scales[i]
        who = sheet.who(m)
        e = SCHEMES[m.task.robot.actuation]  # T [N m] or F [N]
        T, u = e.letter, e.unit
        for key, s, t in sheet.keyed(i):
            if s.torque_at_singularity is not None:
                t1, t2 = (number(v, 4) for v in s.torque_at_singularity)
                out.append(f"{key}  {who}{T} → ({t1}, {t2}) {u} at t = {t} s (ring)")
            else:
                out.append(f"{key}  {who}{T} → ∞ at t = {t} s: pole of order {s.pole_order}")
        for tk, before, after in jumps(m):
            d1, d2 = (number(b - a, 4) for a, b in zip(before, after, strict=True))
            out.append(
                f"-  {who}{T}1, {T}2 jump by {d1}, {d2} {u} at the knot t = {number(tk, 4)} s"
                " (RPR204: the acceleration jumps there)"
            )
        L = m.task.checks.torque_limit
        if L is not None:
            lim = f" {u}, ".join(dict.fromkeys(number(float(v)) for v in L)) + f" {u}"
            far = all(float(v) > LIMIT_NEAR * scale for v in L)
            where = "beyond the axis, ▲\u00a0▼ at its right edge" if far else "dash-dot lines"
            out.append(f"-  {who}limits |{T}1|, |{T}2| ≤ {lim}: {where}")
        for k, r in enumerate(m.result.robust):
            if r.joint is not None and L is not None:
                at = number(m.result.singularities[k].t, 4)
                out.append(
                    f"    over the box: |{T}{r.joint}| > {number(float(L[r.joint - 1]))} {u}"
                    f" for at most {number(r.window, 3, 1, 3)} ms around t = {at} s (shaded)"
                )
        if m.result.torque_limit is not None:
            for j, check in enumerate(m.result.torque_limit):
                for w in check.windows:
                    out.append(f"    |{T}{j + 1}| > {number(check.limit)} {u} over {_span(w)} s")
    return out + sheet.crowded()


def _span(w: Window) -> str:
    """A window's times, each end as bracketed when its bracket is wider than shown."""
    return f"{_when(w.start_lo, w.start_hi)} – {_when(w.end_lo, w.end_hi)}"


def _when(lo: float, hi: float) -> str:
    a, b = number(lo, 4), number(hi, 4)
    return a if a == b else f"[{a}, {b}]"


def _first_pole(motions: Sequence[Motion]) -> tuple[Motion, SingularInstant] | None:
    """The first task's first unbounded instant, if any."""
    for m in motions:
        for s in m.result.singularities:
            if not s.torque_bounded:
                return m, s
    return None


def pole_plot(ax: Axes, m: Motion, s: SingularInstant) -> None:
    """log10 |T_j| against log10 |t - t_s| on both sides of the unbounded instant ``s``,
    with a line of slope -(pole order): near t_s the curves run parallel to it."""
    dt = m.duration * np.logspace(-1, -6, 26)
    p = s.pole_order or 1
    anchor = None
    for side, fill in ((-1, True), (1, False)):
        t = s.t + side * dt
        ok = (t > 0) & (t < m.duration)
        f = m.result.resample(t[ok])
        for (c, q), v in zip(TORQUES, (f.T1, f.T2), strict=True):
            y = np.log10(np.abs(v))
            x = np.log10(dt[ok])
            ax.plot(
                x,
                y,
                "o-",
                ms=2.5,
                lw=0.8,
                color=c,
                mfc=c if fill else "white",
                gid=f"inset-{q}-{'before' if side < 0 else 'after'}",
            )
            good = np.isfinite(y)
            if anchor is None and np.any(good):
                anchor = (float(x[good][-1]), float(y[good][-1]))
    if anchor is not None:
        x0, y0 = anchor
        xs = np.array([x0, x0 + 3.0])
        ax.plot(xs, y0 - p * (xs - x0), color="black", lw=1.0, ls=":", gid="inset-slope")
    ax.set_xlabel("log10 |t − t_s| [s]", fontsize=pt(7), labelpad=1)
    e = SCHEMES[m.task.robot.actuation]
    ax.set_ylabel(f"log10 |{e.letter}| [{e.unit}]", fontsize=pt(7), labelpad=1)
    ax.tick_params(labelsize=pt(6.5))
    ax.set_title(f"near t_s = {number(s.t, 4)} s: slope −{p} (dotted)", fontsize=pt(7))
    ax.grid(True, alpha=0.3)


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


def _finite_limits(ax: Axes, s: SingularInstant, tag: str, colours: Sequence[str]) -> None:
    """A ring at each torque's finite limit at t_s, in its curve's colour."""
    assert s.torque_at_singularity is not None
    for v, c, (_, q) in zip(s.torque_at_singularity, colours, TORQUES, strict=True):
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


def _exit_marks(
    ax: Axes,
    m: Motion,
    s: SingularInstant,
    tag: str,
    lo: float,
    hi: float,
    colours: Sequence[str],
) -> None:
    """▲ or ▼ on the axis's edge, in the curve's colour, where each torque leaves it
    approaching t_s."""
    for v, c, (_, q) in zip((m.s.T1, m.s.T2), colours, TORQUES, strict=True):
        for tx, up in exits(m.s.t, v, s.t, m.duration, lo, hi):
            side = "before" if tx < s.t else "after"
            gid = f"torques-exit-{tag}-{q}-{side}"
            arrow_mark(ax, tx, hi if up else lo, up, c, gid, 8)


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
