"""``rprpr check --format html``: one self-contained page (render.html), its sheets drawn
by the workers (cli.check's attachments), every outside text escaped, and a real
browser's view of it (headless Chromium, marked slow)."""

from __future__ import annotations

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import replace
from html.parser import HTMLParser
from pathlib import Path

import pytest

from rprpr.cli.check import _OutOfTime, _source_lines, _time_limit, check_one
from rprpr.cli.options import CheckOptions
from rprpr.model.options import AuditOptions
from rprpr.render.html import inline_svg, render
from rprpr.report.run import INPUT, REPORT, Attachment, Run
from tests.cli.forked import fresh_probe
from tests.conftest import BAD_A1, ROOT, run_cli

P1 = "configs/paper_path1.rprpr.yaml"  # fails RPR101 (slope) and RPR201 (unbounded)
P2 = "configs/paper_path2.rprpr.yaml"  # passes, no finding
HTML = CheckOptions(AuditOptions(samples=101), format="html", sheets=False)
HOSTILE = '<script>alert("x")</script> & \x1b[2J\r\nverdict: PASS \u202e'


@pytest.fixture(autouse=True)
def _in_repo(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.chdir(ROOT)


class Page(HTMLParser):
    """A page parsed back: its elements (tag, attributes), ids and visible text."""

    def __init__(self, text: str) -> None:
        super().__init__(convert_charrefs=True)
        self.elements: list[tuple[str, dict[str, str | None]]] = []
        self.chunks: list[str] = []
        self.feed(text)
        self.close()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        self.elements.append((tag, dict(attrs)))

    def handle_data(self, data: str) -> None:
        self.chunks.append(data)

    @property
    def text(self) -> str:
        return "".join(self.chunks)

    def ids(self) -> list[str]:
        return [a["id"] for _, a in self.elements if a.get("id")]  # type: ignore[misc]

    def tags(self, name: str) -> list[dict[str, str | None]]:
        return [a for t, a in self.elements if t == name]


def page_of(*paths: str, options: CheckOptions = HTML, quiet: bool = False) -> str:
    run = Run()
    for p in paths:
        run.add(*check_one(p, options))
    return render(run, quiet=quiet)


def test_the_page_holds_summary_verdicts_findings_and_instants() -> None:
    page = Page(page_of(P1, P2))
    text = page.text
    assert "2 tasks: 1 passed, 1 failed, 0 errors" in text
    assert "Example 1 of the paper, path 1" in text and "Example 2 of the paper, path 2" in text
    assert text.count("FAIL") >= 2 and "PASS" in text  # the badges (contents and headings)
    assert "RPR101" in text and "RPR201" in text and "slope-principle" in text
    assert "Fix: Reshape path.y so that it crosses y = 0 with a nonzero slope" in text
    assert len(page.tags("th")) == 11 * 2  # the text report's columns, for each task's instants
    assert "2.5" in text and "3 crossing" in text


def test_each_finding_links_to_its_line_and_quotes_it() -> None:
    html = page_of(P1)
    page = Page(html)
    lines = (ROOT / P1).read_text(encoding="utf-8").split("\n")
    links = [a["href"] for a in page.tags("a") if (a.get("href") or "").startswith("#task-1-L")]
    assert links, "no finding linked"
    ids = set(page.ids())
    for href in links:
        assert href is not None
        assert href[1:] in ids  # the anchor is in the page: the listing's line
        n = int(href.rsplit("L", 1)[1])
        assert f"{P1}:{n}" in page.text
        quoted = re.search(rf'<span class="ln">{n}</span>([^<]*)</pre>', html)
        assert quoted is not None
        assert quoted[1] == lines[n - 1].replace("&", "&amp;").replace("<", "&lt;")
    assert len(re.findall(r'<span id="task-1-L\d+"', html)) == len(lines) - 1  # every line


def test_the_page_is_self_contained_and_has_no_script() -> None:
    page = Page(page_of(P1, P2))
    assert not page.tags("script") and not page.tags("link") and not page.tags("img")
    for _, attrs in page.elements:
        for name in ("src", "href"):
            value = attrs.get(name)
            assert value is None or value.startswith("#"), (name, value)
    csp = [a for a in page.tags("meta") if a.get("http-equiv") == "Content-Security-Policy"]
    assert csp and "default-src 'none'" in (csp[0]["content"] or "")
    assert any(a.get("name") == "viewport" for a in page.tags("meta"))


def test_quiet_leaves_passing_tasks_out() -> None:
    text = Page(page_of(P1, P2, quiet=True)).text
    assert "Example 1 of the paper, path 1" in text
    assert "Example 2 of the paper, path 2" not in text
    assert "2 tasks: 1 passed, 1 failed" in text  # the summary still counts every task


def test_a_bad_task_file_quotes_only_the_lines_its_errors_name(tmp_path: Path) -> None:
    bad = tmp_path / "bad.rprpr.yaml"
    bad.write_text(BAD_A1 + "# a secret comment\n", encoding="utf-8")
    html = page_of(str(bad))
    text = Page(html).text
    assert "bad task file" in text and "RPR001" in text
    assert f"{bad}:3:7" in text and "a1: -1" in text  # the line of the error, quoted
    assert "a secret comment" not in text  # no listing of a file that could not be read


def test_hostile_names_and_lines_are_escaped() -> None:
    rep = {
        "task": "evil\udcff<b>.yaml",  # a file name whose bytes are not UTF-8
        "name": HOSTILE,
        "verdict": "fail",
        "strict": False,
        "singularities": [],
        "kinematic_singularities": [],
        "on_singular_line": False,
        "knots": [],
        "torque_peak": None,
        "closest_approach": None,
        "beyond_double_range": [],
        "findings": [
            {
                "rule": "RPR101",
                "name": "slope-principle",
                "severity": "error",
                "message": HOSTILE,
                "t": 1.0,
                "key": "path",
                "line": 1,
            }
        ],
    }
    run = Run()
    run.add(REPORT, rep, 0.0, Attachment(source=(f"name: {HOSTILE}\udc80",)))
    run.add(
        INPUT,
        {"task": HOSTILE, "errors": [{"line": 1, "column": 1, "key": "", "message": HOSTILE,
                                      "rule": "RPR001", "text": HOSTILE}]},
        0.0,
        Attachment(source=(HOSTILE,)),
    )  # fmt: skip
    html = render(run)
    html.encode("utf-8")  # no lone surrogate left: the bytes that are not UTF-8 are escaped
    assert "<script" not in html and "<b>" not in html
    assert "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt; &amp; \\x1b[2J\\r\\n" in html
    assert "\\u202e" in html and "\u202e" not in html  # no bidirectional override
    assert "evil\\xff&lt;b&gt;.yaml" in html and "\\x80" in html
    assert "\x1b" not in html and "\r" not in html
    page = Page(html)
    assert not page.tags("script") and not page.tags("b")


def test_source_lines_are_numbered_as_yaml_numbers_them(tmp_path: Path) -> None:
    f = tmp_path / "t.yaml"
    f.write_bytes(b"\xef\xbb\xbfa: 1\r\nb: 2\rc: \xff\nd: \xc2\x85e\ne: \xe2\x80\xa8f\n\x0cg\n")
    lines = _source_lines(None, str(f))
    assert lines == ("a: 1", "b: 2", "c: \udcff", "d: ", "e", "e: ", "f", "\x0cg")
    assert _source_lines(b"x\ny", "-") == ("x", "y")
    assert _source_lines(None, str(tmp_path)) is None  # a directory
    assert _source_lines(None, str(tmp_path / "missing")) is None
    assert _source_lines(b"#" * ((1 << 20) + 1), "-") is None  # beyond the loader's cap


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this platform")
def test_a_fifo_is_never_read_twice(tmp_path: Path) -> None:
    fifo = tmp_path / "task.fifo"
    os.mkfifo(fifo)
    assert _source_lines(None, str(fifo)) is None  # at once: it never waits for a writer


SVG = (
    '<?xml version="1.0" encoding="utf-8" standalone="no"?>\n'
    '<!DOCTYPE svg PUBLIC "-//W3C//DTD SVG 1.1//EN"\n'
    '  "http://www.w3.org/Graphics/SVG/1.1/DTD/svg11.dtd">\n'
    '<svg xmlns:xlink="http://www.w3.org/1999/xlink" width="792pt" height="100pt" '
    'viewBox="0 0 792 100" xmlns="http://www.w3.org/2000/svg" version="1.1">\n'
    " <title>t</title>\n <metadata><rdf:RDF><dc:type rdf:resource="
    '"http://purl.org/dc/dcmitype/StillImage"/></rdf:RDF></metadata>\n'
    ' <defs><clipPath id="p1"><rect/></clipPath><path id="m2" d="M 0 0"/></defs>\n'
    ' <g id="figure_1" clip-path="url(#p1)"><use xlink:href="#m2" x="1"/></g>\n</svg>\n'
)


def test_inline_svg_prefixes_every_id_and_drops_prolog_size_and_metadata() -> None:
    out = inline_svg(SVG, "s3-")
    assert out.startswith("<svg ") and "<?xml" not in out and "DOCTYPE" not in out
    assert "<metadata>" not in out and "http://purl.org" not in out
    head = out[: out.index(">")]
    assert 'width="' not in head and 'height="' not in head and 'viewBox="0 0 792 100"' in head
    assert set(re.findall(r'id="([^"]+)"', out)) == {"s3-p1", "s3-m2", "s3-figure_1"}
    assert "url(#s3-p1)" in out and 'xlink:href="#s3-m2"' in out


@pytest.mark.parametrize(
    "active",
    ['<script>alert(1)</script>', '<image href="https://example.com/x.png"/>',
     '<g onload="alert(1)"/>', "<foreignObject/>"],
)  # fmt: skip
def test_inline_svg_refuses_active_content(active: str) -> None:
    out = inline_svg(SVG.replace("</svg>", active + "</svg>"), "s1-")
    assert "<svg" not in out and "left out" in out


def test_sheets_are_inline_svg_drawn_from_the_audit_with_ids_apart() -> None:
    pytest.importorskip("matplotlib")
    # no budget: a busy machine's wall clock never leaves the sheet out here (the budget's
    # own test is test_a_sheet_out_of_budget_is_a_note_not_a_budget_error)
    options = replace(HTML, sheets=True, budget=None)
    run = Run()
    for p in (P1, P2):
        kind, item, seconds, attachment = check_one(p, options)
        assert attachment is not None and attachment.sheet is not None
        assert attachment.sheet.lstrip().startswith("<?xml")
        run.add(kind, item, seconds, attachment)
    html = render(run)
    page = Page(html)
    svgs = page.tags("svg")
    assert len(svgs) == 2 and all(s.get("viewbox") for s in svgs)
    ids = page.ids()
    assert len(ids) == len(set(ids))  # two sheets, no id shared
    assert all(i.startswith(("task-", "s1-", "s2-")) for i in ids)
    for n in (1, 2):  # every panel of each sheet
        for panel in ("path", "x", "delta", "joints", "torques"):
            assert f"s{n}-panel-{panel}" in ids
    for ref in re.findall(r'href="#([^"]+)"|url\(#([^)]+)\)', html):
        assert (ref[0] or ref[1]) in ids  # every reference resolves within the page
    titles = re.findall(r"<title>([^<]*)</title>", html)
    assert "rprpr audit sheet: Example 1 of the paper, path 1" in titles
    assert "rprpr audit sheet: Example 2 of the paper, path 2" in titles
    assert "t = 2.5 s" in page.text  # the sheet's words are text


def test_a_sheet_out_of_budget_is_a_note_not_a_budget_error() -> None:
    kind, item, _, attachment = check_one(P1, replace(HTML, sheets=True, budget=1e-9))
    assert kind == REPORT and item["verdict"] == "fail"
    assert attachment is not None and attachment.sheet is None
    assert attachment.note is not None and "budget" in attachment.note
    assert "budget" in Page(render_one(kind, item, attachment)).text


def render_one(kind: str, item: dict[str, object], attachment: Attachment) -> str:
    run = Run()
    run.add(kind, item, 0.0, attachment)  # type: ignore[arg-type]
    return render(run)


def test_without_matplotlib_the_page_says_how_to_get_the_sheets(
    monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    import importlib.util

    real = importlib.util.find_spec
    monkeypatch.setattr(
        importlib.util, "find_spec", lambda n, *a: None if n == "matplotlib" else real(n, *a)
    )
    out = tmp_path / "report.html"
    code, _, err = run_cli("check", "--format", "html", "--samples", "101", "-o", str(out), P1)
    assert code == 1, err
    html = out.read_text(encoding="utf-8")
    assert "<svg" not in html
    notes = re.findall(r'<p class="note">([^<]*)</p>', html)
    assert notes == ["The audit sheets are left out: they need matplotlib (pip install "
                     "&#x27;rprpr[plot]&#x27;)."]  # fmt: skip
    assert "html report written to" in err


# a start-up probe (``tests.cli.forked.fresh_probe``): a fresh process in an empty folder
fresh_probe(
    "test_html no sheets",
    "numpy, flint, yaml, click, rich.console",
    "import sys\n"
    "from rprpr.cli.main import main\n"
    "try:\n"
    f"    main(['check', '--format', 'html', '--no-sheets', '--samples', '101', "
    f"{str(ROOT / P2)!r}])\n"
    "except SystemExit as e:\n"
    "    code = e.code\n"
    "loaded = sorted(m for m in sys.modules if m.split('.')[0] in ('matplotlib', 'PIL'))\n"
    "sys.stderr.write(f'EXIT={code} LOADED={loaded}\\n')\n",
)


def test_check_html_without_sheets_imports_no_matplotlib(
    fresh: dict[str, tuple[int, str, str]],
) -> None:
    done = subprocess.CompletedProcess("probe", *fresh["test_html no sheets"])
    assert done.stderr.strip().splitlines()[-1] == "EXIT=0 LOADED=[]", done.stderr


def test_the_configuration_may_name_html(tmp_path: Path) -> None:
    (tmp_path / "rprpr.toml").write_text('format = "html"\n', encoding="utf-8")
    code, out, _ = run_cli(
        "check", "--config", str(tmp_path / "rprpr.toml"), "--no-sheets", "--samples", "101", P2
    )
    assert code == 0 and out.startswith("<!DOCTYPE html>")


# ------------------------------------------------------------------ in a real browser

CHROMIUM = next((c for c in ("chromium", "chromium-browser") if shutil.which(c)), None)


def chromium(page: Path, profile: Path, *args: str) -> subprocess.CompletedProcess[str]:
    """Headless Chromium on ``page`` with every host name unresolvable (nothing could be
    fetched even if asked for) and its network activity logged to ``profile``/net.json."""
    assert CHROMIUM is not None
    command = [
        CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
        "--no-first-run", "--disable-background-networking", "--disable-component-update",
        "--disable-sync", "--hide-scrollbars", f"--user-data-dir={profile}",
        "--host-resolver-rules=MAP * ~NOTFOUND", f"--log-net-log={profile / 'net.json'}",
        *args, page.as_uri(),
    ]  # fmt: skip
    return subprocess.run(command, capture_output=True, text=True, timeout=180)


def page_requests(profile: Path) -> list[str]:
    """The URLs the page asked for, from the browser's network log: the requests made
    on behalf of a file:// page (the browser's own, to its update and account services,
    are not the page's)."""
    text = (profile / "net.json").read_text(encoding="utf-8", errors="replace").rstrip()
    try:
        events = json.loads(text)["events"]
    except json.JSONDecodeError:  # a log the browser left unterminated
        events = json.loads(text.rstrip(",") + "]}")["events"]
    urls = []
    for e in events:
        params = e.get("params", {})
        if "url" in params and str(params.get("network_isolation_key", "")).startswith("file:"):
            urls.append(params["url"])
    return urls


@pytest.mark.slow
@pytest.mark.skipif(
    CHROMIUM is None, reason="no Chromium installed (Debian: apt-get install chromium)"
)
def test_a_real_browser_shows_the_page_and_fetches_nothing(tmp_path: Path) -> None:
    pytest.importorskip("matplotlib")
    # the network log sees a page's request: a page that asks for one image
    canary = tmp_path / "canary.html"
    canary.write_text('<img src="http://rprpr-canary.invalid/x.png">', encoding="utf-8")
    chromium(canary, tmp_path / "profile-0", "--dump-dom")
    assert "http://rprpr-canary.invalid/x.png" in page_requests(tmp_path / "profile-0")

    report = tmp_path / "report.html"
    # no budget: its wall time never leaves a sheet out on a busy machine
    code, _, err = run_cli("check", "--format", "html", "--budget", "0", "-o", str(report), P1, P2)
    assert code == 1, err
    shot = tmp_path / "report.png"
    size = "--window-size=390,2000"  # a phone's width
    # one browser draws the page (the screenshot) and gives the document it drew (the DOM)
    dom = chromium(report, tmp_path / "profile-1", f"--screenshot={shot}", size, "--dump-dom")
    assert shot.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", dom.stderr[-2000:]
    page = Page(dom.stdout)
    text = page.text
    assert "2 tasks: 1 passed, 1 failed, 0 errors" in text
    assert "FAIL" in text and "PASS" in text and "RPR101" in text and "RPR201" in text
    assert f"{P1}:19" in text  # the finding's place, linked to its line
    assert "Example 1 of the paper, path 1" in text and "t = 2.5 s" in text
    assert len(page.tags("svg")) == 2  # both sheets, inline
    for _, attrs in page.elements:  # nothing the page refers to lies outside it
        for name in ("src", "href", "xlink:href"):
            value = attrs.get(name)
            assert value is None or value.startswith("#"), (name, value)
    # and the page asked for nothing
    assert [u for u in page_requests(tmp_path / "profile-1") if not u.startswith("file:")] == []


def test_inline_svg_makes_bidi_overrides_and_stray_bytes_visible() -> None:
    out = inline_svg(SVG.replace("<title>t</title>", "<title>a\u202eb\udcff</title>"), "s1-")
    assert "<title>a\\u202eb\\xff</title>" in out
    out.encode("utf-8")


def test_hostile_file_and_task_names_through_the_command(tmp_path: Path) -> None:
    text = (ROOT / P1).read_text(encoding="utf-8")
    text = text.replace(
        "name: Example 1 of the paper, path 1", 'name: "<script>x</script> \\u202e & co"'
    )
    folder = os.fsdecode(os.fsencode(tmp_path) + b"/d\xff")
    os.mkdir(folder)
    with open(folder + os.fsdecode(b"/e\xfe<b>.rprpr.yaml"), "w", encoding="utf-8") as fh:
        fh.write(text)
    out = tmp_path / "report.html"
    code, _, err = run_cli(
        "check", "--format", "html", "--no-sheets", "-o", str(out), str(tmp_path)
    )
    assert code == 1, err
    html = out.read_bytes().decode("utf-8")  # UTF-8 throughout: the stray bytes escaped
    assert "<script" not in html and "\u202e" not in html and "<b>" not in html
    assert "&lt;script&gt;x&lt;/script&gt; \\u202e &amp; co" in html
    assert "/d\\xff/e\\xfe&lt;b&gt;.rprpr.yaml:19" in html  # the finding's place


def test_a_task_on_standard_input_is_listed(monkeypatch: pytest.MonkeyPatch) -> None:
    import io

    data = (ROOT / P2).read_bytes()
    monkeypatch.setattr(sys, "stdin", io.TextIOWrapper(io.BytesIO(data)))
    code, out, _ = run_cli(
        "check", "--format", "html", "--no-sheets", "--stdin-filename", "p2.rprpr.yaml", "-"
    )
    assert code == 0
    page = Page(out)
    assert "p2.rprpr.yaml" in page.text and "Task file (27 lines)" in page.text
    assert "task-1-L27" in page.ids()


def test_quiet_when_every_task_passed_says_so() -> None:
    text = Page(page_of(P2, quiet=True)).text
    assert "1 task: 1 passed, 0 failed, 0 errors" in text
    assert "Every task passed" in text and "Example 2 of the paper" not in text


@pytest.mark.skipif(not hasattr(signal, "setitimer"), reason="no interval timers here")
def test_the_sheets_time_limit_interrupts_and_restores() -> None:
    before = signal.getsignal(signal.SIGALRM)
    with pytest.raises(_OutOfTime), _time_limit(0.01):
        time.sleep(30)  # interrupted by the limit, long before
    assert signal.getsignal(signal.SIGALRM) == before
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)  # nothing left armed
    with _time_limit(None):  # no budget: no limit
        pass


@pytest.mark.skipif(not hasattr(signal, "setitimer"), reason="no interval timers here")
def test_the_sheets_time_limit_rings_again_when_a_ring_is_swallowed() -> None:
    # Under load the first ring can land where Python swallows exceptions (a weakref
    # callback): the block must still be stopped, by the next ring.
    swallowed = 0
    before = signal.getsignal(signal.SIGALRM)
    with pytest.raises(_OutOfTime), _time_limit(0.01):
        try:
            time.sleep(30)
        except _OutOfTime:
            swallowed += 1  # as an unraisable-exception context would
        time.sleep(30)  # interrupted by the next ring, long before
    assert swallowed == 1
    assert signal.getsignal(signal.SIGALRM) == before
    assert signal.getitimer(signal.ITIMER_REAL) == (0.0, 0.0)


def test_a_sheet_that_fails_to_draw_is_a_note_and_the_report_stands(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    sheet = pytest.importorskip("rprpr.render.sheet")

    def broken(*args: object, **kwargs: object) -> str:
        raise RuntimeError("no")

    monkeypatch.setattr(sheet, "svg", broken)
    kind, item, _, attachment = check_one(P1, replace(HTML, sheets=True))
    assert kind == REPORT and item["verdict"] == "fail"
    assert attachment is not None and attachment.sheet is None and attachment.source
    assert attachment.note == "The audit sheet could not be drawn (RuntimeError)."
