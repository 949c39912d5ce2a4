"""README runs as written: every console, sh, python and YAML block, in order, in a fresh
working directory (``tests/readme_examples.py`` says how each kind is run); and every
relative link of README.md and docs/*.md reaches a file (and a heading, with ``#``)."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest

from .conftest import ROOT
from .readme_examples import (
    README,
    SKIP,
    Block,
    Outcome,
    blocks,
    commands,
    session,
    without_comment,
)

TEXT = README.read_text(encoding="utf-8")
BLOCKS = blocks(TEXT)
RUN = {"console", "sh", "python", "yaml", "toml"}
SHOWN = {"json", "text", "xml", ""}  # reports, messages, file layouts: shown only


SMALL_DPI = 20  # the pictures README's commands write: nobody looks at their pixels here
SMALL_FRAMES = 3  # and their GIF (tests/render/test_animation.py tests the frames themselves)


@pytest.fixture(scope="module")
def outcomes(tmp_path_factory: pytest.TempPathFactory) -> dict[int, Outcome]:
    """Every block's outcome, README's pictures written at SMALL_DPI and its GIF with
    SMALL_FRAMES frames at SMALL_DPI (the same commands, the same code path, a fraction of
    the pixels), its PDF with Type 3 fonts (nobody reads its fonts here: the sheet's
    TrueType embedding is tests/render/test_sheet.py's)."""
    from rprpr.render import animation as A
    from rprpr.render import sheet as P

    save, write_gif = P.save, A.write_gif

    def small_save(*args: Any, **kwargs: Any) -> None:
        save(*args, **{**kwargs, "dpi": SMALL_DPI})

    def small_gif(*args: Any, **kwargs: Any) -> int:
        return write_gif(*args, **{**kwargs, "frames": SMALL_FRAMES, "dpi": SMALL_DPI})

    here = tmp_path_factory.mktemp("readme")
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(P, "save", small_save)
        mp.setattr(A, "write_gif", small_gif)
        mp.setitem(P.RC, "pdf.fonttype", 3)
        return {block.line: outcome for block, outcome in session(TEXT, here)}


def test_every_block_is_of_a_known_kind() -> None:
    assert {b.lang for b in BLOCKS} <= RUN | SHOWN
    kinds = [b.lang for b in BLOCKS]
    assert kinds.count("console") >= 8 and kinds.count("sh") >= 5
    assert kinds.count("python") >= 3 and kinds.count("yaml") >= 8


def test_the_tour_comes_first_and_has_seven_steps() -> None:
    tour = TEXT.split("## A tour in seven steps", 1)[1].split("\n## ", 1)[0]
    steps = re.findall(r"^### (\d)\. ", tour, flags=re.M)
    assert steps == [str(i) for i in range(1, 8)]
    assert TEXT.index("## A tour in seven steps") < TEXT.index("## The task file")
    for word in ("rprpr init", "rprpr check", "rprpr repair", "rprpr plot", "FAIL"):
        assert word in tour


@pytest.mark.parametrize("block", [b for b in BLOCKS if b.lang in RUN], ids=lambda b: b.id)
def test_a_readme_block_runs_as_written(block: Block, outcomes: dict[int, Outcome]) -> None:
    got = outcomes[block.line]
    assert not got.problems, (
        f"{block.id} does not run as written (after an intended change to an output, "
        ".venv/bin/python -m tests.readme_examples):\n" + "\n".join(got.problems)
    )


def test_only_the_commands_that_install_or_recurse_are_skipped(
    outcomes: dict[int, Outcome],
) -> None:
    in_readme = {without_comment(c) for b in BLOCKS if b.lang == "sh" for c in commands(b.body)}
    assert set(SKIP) <= in_readme  # no stale entry
    skipped = {c for o in outcomes.values() for c, _ in o.skipped}
    assert skipped == set(SKIP)
    ran = in_readme - skipped
    assert {c.split()[0] for c in ran} == {"rprpr"}  # every rprpr command in a sh block ran
    assert sum(len(o.fresh) for o in outcomes.values()) >= 10


# -- links ------------------------------------------------------------------------------------
DOCS = [README, *sorted((ROOT / "docs").glob("*.md"))]
LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)\)")


def slug(heading: str) -> str:
    """GitHub's anchor of a heading: lower case, punctuation dropped, spaces to hyphens."""
    return re.sub(r"[^\w\- ]", "", heading.strip().lower()).replace(" ", "-")


def anchors(path: Path) -> set[str]:
    text = re.sub(r"^```.*?^```", "", path.read_text(encoding="utf-8"), flags=re.S | re.M)
    return {slug(h) for h in re.findall(r"^#{1,6} (.+)$", text, flags=re.M)}


def links(path: Path) -> list[str]:
    text = re.sub(r"^ *```.*?^ *```", "", path.read_text(encoding="utf-8"), flags=re.S | re.M)
    return [t for t in LINK.findall(text) if not re.match(r"[a-z]+:", t)]


def test_slug_is_githubs() -> None:
    assert slug("The JSON report (`--format json`)") == "the-json-report---format-json"
    assert slug("Piecewise motions: what planners emit") == "piecewise-motions-what-planners-emit"


@pytest.mark.parametrize("doc", DOCS, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_relative_link_reaches_a_file_and_its_heading(doc: Path) -> None:
    found = links(doc)
    assert found or doc.name == "prismatic.md"
    for target in found:
        name, _, anchor = target.partition("#")
        path = (doc.parent / name).resolve() if name else doc
        assert path.exists(), f"{doc.name}: {target}: no such file"
        assert ROOT in path.parents or path == ROOT, f"{doc.name}: {target} leaves the clone"
        if anchor:
            assert anchor in anchors(path), f"{doc.name}: {target}: no such heading"


def test_readme_links_every_docs_page() -> None:
    linked = {Path(t.partition("#")[0]).name for t in links(README)}
    assert {p.name for p in DOCS[1:]} <= linked


def test_the_task_file_example_is_the_shipped_example_2() -> None:
    from rprpr import load_task, parse_task

    section = TEXT.split("\n## The task file\n", 1)[1]
    match = re.search(r"```yaml\n(.*?)```", section, flags=re.S)
    assert match is not None
    mine = parse_task(match[1], file="example.rprpr.yaml")
    shipped = load_task(ROOT / "configs" / "paper_path2.rprpr.yaml")
    for name in ("name", "robot", "path", "x_of_t", "duration", "checks", "law"):
        assert getattr(mine, name) == getattr(shipped, name), name


def test_every_picture_the_gallery_lists_is_there() -> None:
    """docs/gallery/README.md names each sheet by its file: every one is in the
    repository (a clone has only what git tracks), and no picture is left unlisted."""
    gallery = ROOT / "docs" / "gallery"
    listed = set(re.findall(r"`([\w-]+\.png)`", (gallery / "README.md").read_text("utf-8")))
    assert len(listed) >= 10
    assert listed == {p.name for p in gallery.glob("*.png")}
