"""README's examples, kept true: every ```console block holds ``$ rprpr ...`` commands,
each followed by what it prints (standard output, then standard error), run from the
repository's root with a plain terminal (``conftest.run_cli``).

Rewrite the blocks after an intended change, and review the diff::

    .venv/bin/python -m tests.readme_examples
"""

from __future__ import annotations

import re
import shlex
from contextlib import chdir
from dataclasses import dataclass

from .conftest import ROOT, plain_terminal, run_cli

README = ROOT / "README.md"
BLOCK = re.compile(r"^```console\n(.*?)^```\n", re.S | re.M)


@dataclass(frozen=True)
class Example:
    command: str  # what follows "$ "
    output: str  # the lines after it, up to the next command or the block's end


def examples(block: str) -> list[Example]:
    """The commands of a console block, each with its output."""
    out: list[Example] = []
    for line in block.splitlines(keepends=True):
        if line.startswith("$ "):
            out.append(Example(line[2:].rstrip("\n"), ""))
        elif out:
            out[-1] = Example(out[-1].command, out[-1].output + line)
    return out


def run(command: str) -> str:
    """What ``command`` (an rprpr command line, no shell features) prints, from ROOT."""
    argv = shlex.split(command)
    assert argv[0] == "rprpr", f"README example is not an rprpr command: {command}"
    with plain_terminal(), chdir(ROOT):
        _, out, err = run_cli(*argv[1:])
    return out + err


def regenerate() -> bool:
    """Rewrite every console block with what rprpr prints now; whether anything changed."""
    text = README.read_text(encoding="utf-8")

    def fresh(m: re.Match[str]) -> str:
        body = "".join(f"$ {e.command}\n{run(e.command)}" for e in examples(m.group(1)))
        return f"```console\n{body}```\n"

    new = BLOCK.sub(fresh, text)
    if new != text:
        README.write_text(new, encoding="utf-8")
    return new != text


if __name__ == "__main__":
    print("README.md rewritten" if regenerate() else "README.md examples are up to date")
