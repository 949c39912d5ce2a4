"""What the plot tests share (tests/render/test_sheet.py, test_sheet_layout.py, test_animation.py):
each task audited once and each sheet rendered once per test process, and a figure laid
out for measuring without painting a pixel. The shared figures are only read by the tests
that share them, never changed (``drawn`` sets the resolution text is measured at, which
every reader of a shared figure takes as it finds it)."""

from __future__ import annotations

import functools
import tempfile
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg
from matplotlib.figure import Figure

from rprpr.engine.audit import audit
from rprpr.io.loader import load_task
from rprpr.render import sheet as P

from .conftest import CONFIGS, run_cli

PATH1 = str(CONFIGS / "paper_path1.rprpr.yaml")
PATH2 = str(CONFIGS / "paper_path2.rprpr.yaml")
ZERO = str(CONFIGS / "zero_speed_crossing.rprpr.yaml")
# the shipped RPRPR tasks in the paper's form (one polynomial each); the piecewise ones
# and the 5R's apart
ALL_CONFIGS = sorted(str(p) for p in CONFIGS.glob("*.yaml"))
FIVE_BAR_FILES = [p for p in ALL_CONFIGS if load_task(p).robot.mechanism == "5R"]
CONFIG_FILES = [p for p in ALL_CONFIGS if not load_task(p).pieces and p not in FIVE_BAR_FILES]
PIECEWISE = [p for p in ALL_CONFIGS if p not in CONFIG_FILES + FIVE_BAR_FILES]
# each config alone, the paper's two paths overlaid, every paper-form config (small
# multiples), and the 5R's beside two RPRPR's (small multiples of both mechanisms)
MIXED = [*CONFIG_FILES[:2], *FIVE_BAR_FILES]
SETS = [[p] for p in ALL_CONFIGS] + [[PATH1, PATH2], CONFIG_FILES, MIXED]
SAMPLES = 101  # enough for every check on a shared sheet
DPI = 50  # enough to measure text; the sheet's sizes are in inches and points
SMALL_DPI = 20  # a picture a test writes but never looks at the pixels of


def small_pictures(monkeypatch: pytest.MonkeyPatch) -> None:
    """The sheets the commands write (``plot``, ``repair --plot``) at SMALL_DPI for the rest
    of the test: the same figure and code path, a fraction of the pixels to rasterize; a
    PDF with its text in Type 3 fonts, as ``P.RC`` would say with ``pdf.fonttype`` 3: the
    same page, without the TrueType subsetting that costs half a PDF's time (the sheet's
    fonts embedded as TrueType are tests/render/test_sheet.py's, which reads them)."""
    save = P.save

    def small(*args: Any, **kwargs: Any) -> None:
        save(*args, **{**kwargs, "dpi": SMALL_DPI})

    monkeypatch.setattr(P, "save", small)
    monkeypatch.setitem(P.RC, "pdf.fonttype", 3)


FEW_FRAMES = 12  # a GIF a test checks is animated (more than 10 frames), not its frames


def few_frames(monkeypatch: pytest.MonkeyPatch) -> None:
    """The GIFs the commands write (``plot --animate``) with FEW_FRAMES frames at SMALL_DPI
    for the rest of the test: the same writer and code path, an eighth of the frames to
    draw and a twentieth of their pixels (tests/render/test_animation.py tests the frame
    count and size themselves, and the real command's 100-frame GIF, marked slow)."""
    from rprpr.render import animation as A

    write_gif = A.write_gif

    def few(*args: Any, **kwargs: Any) -> int:
        return write_gif(*args, **{**kwargs, "frames": FEW_FRAMES, "dpi": SMALL_DPI})

    monkeypatch.setattr(A, "write_gif", few)


@dataclass(frozen=True)
class Gif:
    """A GIF ``animation.write_gif`` wrote: the frame count it returned, the file, and
    the ``Animation`` it drew the frames with (read, never changed)."""

    frames: int
    path: Path
    animation: Any


_GIFS = tempfile.TemporaryDirectory(prefix="rprpr-gifs-")  # removed at the process's end


@functools.cache
def gif(paths: tuple[str, ...], frames: int, dpi: int) -> Gif:
    """``write_gif(motions(paths), FILE, frames=frames, dpi=dpi)`` once per test process
    (its static parts drawn once, the frames once): the file, and the animation it drew."""
    from rprpr.render import animation as A

    seen: list[Any] = []
    init = A.Animation.__init__

    def spy(self: Any, *a: Any, **kw: Any) -> None:
        init(self, *a, **kw)
        seen.append(self)

    name = "+".join(Path(p).name.split(".")[0] for p in paths)
    out = Path(_GIFS.name) / f"{name}-{frames}-{dpi}.gif"
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(A.Animation, "__init__", spy)
        n = A.write_gif(motions(paths), str(out), frames=frames, dpi=dpi)
    (animation,) = seen
    return Gif(n, out, animation)


@functools.cache
def _motion(path: str, samples: int) -> P.Motion:
    return P.motion(audit(load_task(path), samples=samples), path)


def motions(paths: Sequence[str], samples: int = SAMPLES) -> list[P.Motion]:
    """The shipped tasks ``paths``, audited (once) with ``samples`` samples."""
    return [_motion(p, samples) for p in paths]


@functools.cache
def _sheet(paths: tuple[str, ...]) -> Figure:
    return _shared(P.render(motions(paths), pole_inset=True))


def sheet(paths: Sequence[str]) -> Figure:
    """The whole sheet of ``paths`` (every panel, with the pole inset), rendered once."""
    return _sheet(tuple(paths))


@functools.cache
def _renderer(dpi: int) -> RendererAgg:
    return RendererAgg(1, 1, dpi)  # type: ignore[no-untyped-call]


# The shared figures (``sheet``, ``repaired``; kept for the whole test process, so their ids
# are theirs alone) -> the resolution ``drawn`` last laid them out at (None: since then
# drawn otherwise, as by a save at another resolution). They are never changed, so a second
# layout at the same resolution would place everything where it is: it is skipped.
_LAID_OUT: dict[int, int | None] = {}


def _shared(fig: Figure) -> Figure:
    """``fig`` as a shared figure: any draw of it but ``drawn``'s forgets its layout."""
    draw = fig.draw

    def any_draw(renderer: Any) -> None:
        _LAID_OUT[id(fig)] = None
        draw(renderer)

    fig.draw = any_draw  # type: ignore[method-assign]
    _LAID_OUT[id(fig)] = None
    return fig


def drawn(fig: Figure, dpi: int = DPI) -> Any:
    """Lay ``fig`` out at ``dpi`` on an Agg canvas as a draw would (ticks, text, legends
    placed) without painting; returns the renderer to measure it with.

    As ``Figure.draw_without_rendering``, with one Agg renderer per ``dpi`` for every
    figure: a renderer caches the size of each text (and each mathtext parse) it has
    measured, and the sheets share most of theirs. What a draw places depends on the
    renderer's resolution only, never on its canvas size (not painted: it stays 1 x 1)."""
    renderer = _renderer(dpi)
    if _LAID_OUT.get(id(fig), 0) == dpi:  # a shared figure, laid out at dpi already
        return renderer
    fig.set_dpi(dpi)
    FigureCanvasAgg(fig)
    with renderer._draw_disabled():
        fig.draw(renderer)
    if id(fig) in _LAID_OUT:
        _LAID_OUT[id(fig)] = dpi
    return renderer


@dataclass(frozen=True)
class Repaired:
    """What ``rprpr repair TASK -o FILE --plot SHEET`` left: its exit status, standard
    output and error, whether it wrote the sheet file, and the figure it drew with its
    motions."""

    code: int
    out: str
    err: str
    sheet_written: bool
    fig: Figure
    motions: list[P.Motion]


@functools.cache
def repaired(task: str) -> Repaired:
    """``rprpr repair TASK --plot`` run once per test process (in a temporary folder, its
    PNG at SMALL_DPI), the figure it drew laid out by ``drawn``; read, never changed."""
    seen: list[tuple[Figure, list[P.Motion]]] = []
    render = P.render

    def spy(ms: list[P.Motion], *a: object, **kw: object) -> Figure:
        fig = render(ms, *a, **kw)  # type: ignore[arg-type]
        seen.append((fig, list(ms)))
        return fig

    with tempfile.TemporaryDirectory() as tmp, pytest.MonkeyPatch.context() as mp:
        mp.setattr(P, "render", spy)
        small_pictures(mp)
        sheet_file = Path(tmp) / "r.png"
        code, out, err = run_cli("repair", task, "-o", f"{tmp}/r.yaml", "--plot", str(sheet_file))
        written = sheet_file.exists()
    ((fig, ms),) = seen
    drawn(_shared(fig))
    return Repaired(code, out, err, written, fig, ms)
