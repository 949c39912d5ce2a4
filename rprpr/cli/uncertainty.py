"""The configuration's ``uncertainty`` default (``docs/robust.md``) and the rule that a
declared uncertainty needs a torque limit, checked once the configuration is applied.

In ``[tool.rprpr]`` (or ``rprpr.toml``), as in a task file::

    uncertainty = {links = "5%", acceleration = 0.01, period = 0.001}
    # or per link and quantity: links = {3 = {mass = "2%", r = "1%"}, 5 = {mass = "2%"}}

A task's own ``uncertainty:`` key wins over it, whole (the two are not merged). A window
is measured against a limit, so a task audited with an uncertainty (its own or the
configuration's) needs ``torque_limit`` (its own ``checks.torque_limit`` or the
configuration's): one located error line otherwise, exit 2.

Plain Python (fractions, re): reading the configuration imports neither numpy nor flint.
"""

from __future__ import annotations

import re
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from ..model.dataclass import dataclass
from ..model.defaults import LINK_QUANTITIES, MOVING_LINKS, PERCENT
from .errors import InputError

if TYPE_CHECKING:
    from ..model.task import Task

QUANTITIES = LINK_QUANTITIES
LINKS = MOVING_LINKS
_PERCENT = re.compile(PERCENT)
_EXPECTED = 'a percentage such as "5%" (0% <= value < 100%)'


@dataclass(frozen=True)
class UncertaintyDefault:
    """The configuration's ``uncertainty``: per link 2..5 the relative half-widths (mass,
    inertia, r), the acceleration tracking error bound [m/s^2], the controller's period
    [s]; ``origin`` is where the configuration writes it (``file:line``)."""

    links: dict[int, tuple[Fraction, Fraction, Fraction]]
    acceleration: Fraction
    period: Fraction
    origin: str = ""
    text: str = ""  # as written, for --show-settings


def read(raw: Any, where: str, number: Any, toml: Any) -> UncertaintyDefault:
    """The ``uncertainty`` value of the configuration (a TOML table); ``where`` names it
    (``file:line: uncertainty``) in every error; ``number(raw, where, positive=False)``
    reads a number by the task file's rules, ``toml`` writes a value back."""
    if not isinstance(raw, dict):
        raise InputError(
            f"{where}: expected a table {{links, acceleration, period}}, found {toml(raw)}"
        )
    for key in raw:
        if key not in ("links", "acceleration", "period"):
            raise InputError(f"{where}: unknown key {key!r} (known: links, acceleration, period)")
    zero = Fraction(0)
    every = raw.get("links", "0%")
    if isinstance(every, dict):
        links = _per_link(every, f"{where}.links", toml)
    else:
        p = _percent(every, f"{where}.links", toml)
        links = dict.fromkeys(LINKS, (p, p, p))
    a = (
        number(raw["acceleration"], f"{where}.acceleration", positive=False)
        if "acceleration" in raw
        else zero
    )
    if "period" not in raw:
        raise InputError(
            f"{where}: missing required key 'period' (the controller's sample period [s]:"
            " every saturation window is judged against it; period = 0 fails every window)"
        )
    period = number(raw["period"], f"{where}.period", positive=False)
    origin = where.rsplit(": ", 1)[0]
    return UncertaintyDefault(links, a, period, origin, toml(raw))


def _per_link(
    table: dict[str, Any], where: str, toml: Any
) -> dict[int, tuple[Fraction, Fraction, Fraction]]:
    zero = Fraction(0)
    links = dict.fromkeys(LINKS, (zero, zero, zero))
    for name, quantities in table.items():
        if name not in {str(i) for i in LINKS}:
            raise InputError(f"{where}: unknown link {name!r} (the moving links are 2, 3, 4, 5)")
        if not isinstance(quantities, dict):
            raise InputError(
                f"{where}.{name}: expected a table {{mass, inertia, r}}, found {toml(quantities)}"
            )
        values = []
        for q in QUANTITIES:
            v = quantities.get(q, "0%")
            values.append(_percent(v, f"{where}.{name}.{q}", toml))
        for q in quantities:
            if q not in QUANTITIES:
                raise InputError(f"{where}.{name}: unknown key {q!r} (known: mass, inertia, r)")
        links[int(name)] = (values[0], values[1], values[2])
    return links


def _percent(raw: Any, where: str, toml: Any) -> Fraction:
    """A percentage written as a TOML string ``"5%"`` (or the integer 0), as a fraction."""
    from ..io.expression import parse_decimal
    from ..model.errors import ExpressionError

    if raw == 0 and type(raw) is int:
        return Fraction(0)
    m = _PERCENT.fullmatch(raw) if type(raw) is str else None
    if m is None:
        hint = (
            " (write the percentage with %)"
            if isinstance(raw, int | float | str) and _numeric(raw)
            else ""
        )
        raise InputError(f"{where}: expected {_EXPECTED}, found {toml(raw)}{hint}")
    try:
        q = parse_decimal(m.group(1) + (m.group(2) or ""))
    except ExpressionError as e:
        raise InputError(f"{where}: {e.message}") from None
    value = Fraction(int(q.p), int(q.q)) / 100
    if value >= 1:
        raise InputError(
            f"{where}: expected {_EXPECTED}, found {toml(raw)}: a half-width of 100% or"
            " more leaves the mass or length unbounded below"
        )
    return value


def _numeric(raw: Any) -> bool:
    try:
        float(str(raw))
    except ValueError:
        return False
    return True


def apply(task: Task, d: UncertaintyDefault | None) -> Task:
    """``task`` with the configuration's uncertainty when the task declares none."""
    from dataclasses import replace

    from ..model.task import Uncertainty

    if d is None or task.uncertainty is not None:
        return task
    u = Uncertainty(dict(d.links), d.acceleration, d.period).exact()
    return replace(task, uncertainty=replace(u, origin=d.origin))


def needs_limit(task: Task) -> None:
    """A task audited with an uncertainty needs a torque limit (the window is measured
    against it): a ``TaskFileError`` at the task's ``uncertainty`` key, or naming the
    configuration that declares it, when there is none."""
    from ..model.errors import TaskFileError

    u = task.uncertainty
    if u is None or task.checks.torque_limit is not None:
        return
    fix = (
        "add checks: {torque_limit: [T1 max, T2 max]} to the task, or torque_limit ="
        " [T1, T2] to the configuration"
    )
    if u.origin:  # the configuration's
        raise TaskFileError(
            f"the uncertainty of the configuration ({u.origin}) needs a torque limit: the"
            f" saturation window around each singular instant is measured against the"
            f" actuators' limits ({fix})",
            file=task.source,
            key="checks.torque_limit",
        )
    line, column = u.where
    raise TaskFileError(
        "uncertainty needs checks.torque_limit: the saturation window around each singular"
        f" instant is measured against the actuators' limits ({fix})",
        file=task.source,
        line=line,
        column=column,
        key="uncertainty",
    )
