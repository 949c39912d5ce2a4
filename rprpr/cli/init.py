"""``rprpr init [PATH]``: write a commented task file to start from, the paper's Example 2
(path 2, eq. 51, with the quintic timing of eq. 49), which ``rprpr check`` passes.

PATH defaults to ``task.rprpr.yaml`` (a folder: that name inside it; ``-``: standard
output). An existing file is never overwritten. The first line is the schema modeline
that editors with a YAML language server read for completion and validation.
"""

from __future__ import annotations

import os

import click

from ..model.defaults import SCHEMA_MODELINE
from ..report.exit import ExitCode
from .config import TASK_GLOBS, FileSelection
from .errors import InputError
from .output import say

DEFAULT_NAME = "task.rprpr.yaml"

TEMPLATE = f"""\
{SCHEMA_MODELINE}
# (offline: `rprpr schema > task.schema.json`, then point the line above at that file)
#
# An rprpr task: a robot, the end point's path y = p(x) and its timing x(t). This one is
# Example 2 of the paper (Section 4): path 2, eq. (51), crosses the singular line y = 0
# at (3, 0) with slope 0.2, at t = 2.5 s of the quintic timing, eq. (49). That Type II
# singularity is of first order, and `rprpr check` passes it.
# Every key: `rprpr schema`. Every rule a finding can name: `rprpr rule`.
name: Example 2 of the paper, path 2

robot:
  a1: 6                      # |AB| [m]: A = (0, 0), B = (a1, 0)
  gravity: 9.81              # [m/s^2], along -y (the default)
  links:                     # mass [kg], centroidal inertia [kg m^2], r [m] (Section 2)
    # The paper gives no mass data; these are illustrative. The two legs are alike
    # (2 = 4, 3 = 5), which with the symmetric quintic makes the equations of motion
    # consistent at the singular instant (eq. 34): the torques stay bounded there.
    2: {{mass: 2.0, inertia: 0.10, r: 0.5}}   # r2 = |AG2|
    3: {{mass: 1.0, inertia: 0.05, r: 0.5}}   # r3 = |EG3|
    4: {{mass: 2.0, inertia: 0.10, r: 0.5}}   # r4 = |BG4|
    5: {{mass: 1.0, inertia: 0.05, r: 0.5}}   # r5 = |EG5|

path:
  y: 0.8*x^3 - 7.2*x^2 + 21.8*x - 22.2      # eq. (51): numbers, x, + - * / ^ ( )
  from: [2, -1]              # start point [x, y] [m], on the path
  to: [4, 1]                 # end point [x, y] [m], on the path

timing:
  duration: 5                # t_f [s]
  law: quintic               # rest to rest from `from` to `to` (eq. 49); or x: <x(t)>

checks:
  torque_limit: [300, 300]   # |T1|, |T2| limits [N m]: a warning, a failure if strict
  # min_slope: 0.1           # |dy/dx| at a singular point must exceed this
  # min_speed: 0.1           # end-point speed [m/s] at a singular instant, likewise
  # strict: true             # fail on every finding
  # peak: true               # the certified torque peak in the report (= --peak)
  # ignore:                  # silence a rule for this task, saying why:
  #   RPR202: the drives are rated for the peak
"""


@click.command()
@click.argument("path", required=False, default=DEFAULT_NAME, type=click.Path())
def init(path: str) -> ExitCode:
    """Write a commented task file to start from (the paper's Example 2) at PATH
    (default: task.rprpr.yaml; a folder: that name in it; -: standard output). An
    existing file is never overwritten."""
    if path == "-":
        click.echo(TEMPLATE, nl=False)
        return ExitCode.PASSED
    if os.path.isdir(path):
        path = os.path.join(path, DEFAULT_NAME)
    try:
        with open(path, "x", encoding="utf-8", newline="\n") as out:
            out.write(TEMPLATE)
    except FileExistsError:
        raise InputError(f"{path} already exists: not overwritten") from None
    except OSError as e:
        raise InputError(f"cannot write {path}: {e.strerror or e}") from None
    say(f"rprpr: wrote {path}; audit it with: rprpr check {path}")
    if not FileSelection().included(path):
        say(
            f"rprpr: note: a folder search finds task files named {' or '.join(TASK_GLOBS)};"
            f" {os.path.basename(path)} is found only when named (or by the include setting)"
        )
    return ExitCode.PASSED
