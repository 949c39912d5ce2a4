"""Exact polynomials from text: a small, safe parser (nothing is ever evaluated).

Conventions: polynomials are ``flint.fmpq_poly`` (exact rational coefficients,
low degree first, as in ``numpy.polynomial``). A decimal literal is taken by its
text: ``0.8`` is exactly 4/5 and ``1e-3`` exactly 1/1000.

Grammar (one variable, given by the caller)::

    expr   := term (("+" | "-") term)*
    term   := unary (("*" | "/") unary)*       # "/" only by a nonzero constant
    unary  := ("+" | "-") unary | power
    power  := atom (("^" | "**") INTEGER)?     # 0 <= INTEGER <= MAX_DEGREE
    atom   := NUMBER | VARIABLE | "(" expr ")"
"""

from __future__ import annotations

import re

from flint import fmpq, fmpq_poly

from ..model.errors import ExpressionError
from .messages import shorten

MAX_DEGREE = 60  # cap on the degree of every polynomial and of the composition y(x(t))
MAX_LENGTH = 4000  # characters in one expression
MAX_DEPTH = 50  # nesting of parentheses and unary signs
MAX_DIGITS = 40  # significant characters in one number literal
MAX_EXP10 = 30  # |e| in a literal such as 1.5e-3
MAX_BITS = 16384  # bits of any numerator or the common denominator of a parsed polynomial

# ASCII digits only: "\d" would also take Arabic-Indic or full-width digits.
_NUMBER = re.compile(r"([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?")
_NAME = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")
_EXPONENT = re.compile(r"[0-9]+")


def height(p: fmpq_poly) -> int:
    """Bits of the largest integer in ``p`` = (integer polynomial) / (common denominator)."""
    return max(p.numer().height_bits(), p.denom().bit_length())


def _bits_of(n: int) -> int:
    return max(n, 1).bit_length()


def parse_decimal(text: str) -> fmpq:
    """The exact rational of a decimal literal such as ``-0.1``, ``3`` or ``2.5e-3``.

    Raises ``ExpressionError`` for anything else: nan, inf and fractions (``4/25`` is an
    expression, for ``parse_polynomial``).
    """
    s = text.strip()
    negative = False
    if s.startswith(("+", "-")):  # not s[:1] in "+-": "" is in every string
        negative = s[0] == "-"
        s = s[1:].strip()
    if not _NUMBER.fullmatch(s):
        raise ExpressionError(f"expected a number, found {_shown(text.strip())!r}")
    value = _literal(s)
    return -value if negative else value


def parse_fraction(text: str) -> fmpq:
    """The exact rational of ``text``: a decimal (``parse_decimal``) or a fraction of two
    decimals, ``-2/3`` or ``1.5 / 4``. Raises ``ExpressionError`` for anything else and
    for a zero denominator."""
    numerator, slash, denominator = text.partition("/")
    value = parse_decimal(numerator)
    if not slash:
        return value
    d = text.strip()
    below = parse_decimal(denominator) if denominator.strip()[:1] not in "+-" else None
    if below is None:
        raise ExpressionError(f"expected a fraction such as -2/3, found {_shown(d)!r}")
    if below == 0:
        raise ExpressionError(f"division by zero in {_shown(d)!r}")
    return value / below


def _shown(text: str, n: int = 24) -> str:
    """``text`` for a message: abbreviated beyond ``n`` characters (``messages.shorten``;
    the parser's messages keep one character fewer than the loader's)."""
    return shorten(text, n, cut=4)


def _literal(text: str) -> fmpq:
    """The exact value of a literal matching ``_NUMBER``, within the digit and exponent caps.

    The digits counted are those after the integer part's leading zeros: ``0.05`` has
    two, so a value below 10^-(MAX_DIGITS + MAX_EXP10) cannot be written either. Every
    ``int()`` here sees at most that many digits (leading zeros, of the number or of its
    exponent, are stripped first, whatever their count), so Python's limit on converting
    long digit strings is never reached.
    """
    mantissa, _, exp = text.lower().partition("e") if "e" in text or "E" in text else (text, "", "")
    whole, _, frac = mantissa.partition(".")
    digits = whole.lstrip("0") + frac
    if len(digits) > MAX_DIGITS:
        raise ExpressionError(f"number {_shown(text)!r} has more than {MAX_DIGITS} digits")
    if not exp:  # the common case: no exponent
        return fmpq(int(digits or "0"), 10 ** len(frac))
    exp_digits = exp.lstrip("+-").lstrip("0")
    if len(exp_digits) > 3 or int(exp_digits or "0") > MAX_EXP10:
        raise ExpressionError(f"number {_shown(text)!r} has an exponent beyond ±{MAX_EXP10}")
    e = -int(exp_digits or "0") if exp.startswith("-") else int(exp_digits or "0")
    num = int(digits.lstrip("0") or "0")
    scale = e - len(frac)  # value = num * 10^scale
    return fmpq(num * 10**scale) if scale >= 0 else fmpq(num, 10**-scale)


class _Parser:
    def __init__(self, text: str, variable: str) -> None:
        self.text = text
        self.var = variable
        self.pos = 0
        self.depth = 0
        self.peeked = (-1, "")  # (position after the blanks, the token there): _peek's

    # -- lexing --------------------------------------------------------------
    def _skip(self) -> None:
        while self.pos < len(self.text) and self.text[self.pos] in " \t\r\n":
            self.pos += 1

    def _peek(self) -> str:
        at, token = self.peeked
        if self.pos == at:  # peeked here already (the text does not change)
            return token
        self._skip()
        pos = self.pos
        token = "**" if self.text.startswith("**", pos) else self.text[pos : pos + 1]
        self.peeked = (self.pos, token)
        return token

    def _error(self, message: str, at: int | None = None) -> ExpressionError:
        return ExpressionError(message, self.pos if at is None else at)

    def _found(self) -> str:
        self._skip()
        if self.pos >= len(self.text):
            return "end of expression"
        m = _NAME.match(self.text, self.pos)
        if m:
            return f"name {_shown(m.group(0), 40)!r}"
        return repr(self.text[self.pos])

    # -- grammar -------------------------------------------------------------
    def parse(self) -> fmpq_poly:
        p = self.expr()
        self._skip()
        if self.pos != len(self.text):
            rest = self.text[self.pos :]
            m = _NAME.match(rest, 1)
            if rest[0] == "." and m:
                raise self._error(
                    f"attribute access ('.{_shown(m.group(0), 40)}') is not allowed: only numbers,"
                    f" {self.var}, + - * / ^ ** and parentheses"
                )
            if rest[0] == "(":
                raise self._error(
                    "a call (a name or value followed by '(') is not allowed: write"
                    " multiplication as '*'"
                )
            raise self._error(f"expected an operator, found {self._found()}")
        return p

    def expr(self) -> fmpq_poly:
        p = self.term()
        while (op := self._peek()) in ("+", "-"):
            self.pos += 1
            at = self.pos - 1
            q = self.term()
            p = self._bounded(p + q if op == "+" else p - q, at)
        return p

    def term(self) -> fmpq_poly:
        p = self.unary()
        while (op := self._peek()) in ("*", "/"):  # not "**", a power
            at = self.pos
            self.pos += 1
            q = self.unary()
            if op == "*":
                if p.degree() + q.degree() > MAX_DEGREE:
                    raise self._error(
                        f"degree {p.degree() + q.degree()} exceeds the cap of {MAX_DEGREE}", at
                    )
                p = self._bounded(p * q, at)
            else:
                if q.degree() > 0:
                    raise self._error(
                        f"division by a non-constant (by a polynomial of degree {q.degree()} in"
                        f" {self.var}): only division by a nonzero number is allowed",
                        at,
                    )
                if q.is_zero():
                    raise self._error("division by zero", at)
                p = self._bounded(p / q[0], at)
        return p

    def _bounded(self, p: fmpq_poly, at: int) -> fmpq_poly:
        if height(p) > MAX_BITS:
            raise self._error(f"numbers too large: coefficients beyond {MAX_BITS} bits", at)
        return p

    def unary(self) -> fmpq_poly:
        op = self._peek()
        if op in ("+", "-"):
            self.pos += 1
            self._enter()
            p = self.unary()
            self.depth -= 1
            return -p if op == "-" else p
        return self.power()

    def _enter(self) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise self._error(f"expression nested deeper than {MAX_DEPTH} levels")

    def power(self) -> fmpq_poly:
        base = self.atom()
        op = self._peek()
        if op in ("^", "**"):
            at = self.pos
            self.pos += len(op)
            self._skip()
            m = _EXPONENT.match(self.text, self.pos)
            if not m:
                if self._peek() == "-":
                    raise self._error(
                        f"negative exponent: exponents must be integers 0..{MAX_DEGREE}", at
                    )
                raise self._error(
                    f"expected a non-negative integer exponent (0..{MAX_DEGREE}),"
                    f" found {self._found()}",
                    at,
                )
            end = m.end()
            if end < len(self.text) and self.text[end] in ".eE":
                raise self._error(
                    f"fractional exponent: exponents must be integers 0..{MAX_DEGREE}", at
                )
            digits = m.group(0).lstrip("0") or "0"
            if len(digits) > 3 or int(digits) > MAX_DEGREE:
                shown = digits if len(digits) <= 12 else digits[:8] + "..."
                raise self._error(f"exponent {shown} exceeds the cap of {MAX_DEGREE}", at)
            n = int(digits)
            self.pos = end
            if base.degree() > 0 and base.degree() * n > MAX_DEGREE:
                raise self._error(f"degree {base.degree() * n} exceeds the cap of {MAX_DEGREE}", at)
            if self._peek() in ("^", "**"):
                raise self._error("chained exponents are ambiguous: use parentheses", self.pos)
            # bound the result before computing it: height(b^n) <= n * (height(b) + log2 len(b))
            if n * (height(base) + _bits_of(len(base.coeffs()))) > MAX_BITS:
                raise self._error(f"numbers too large: coefficients beyond {MAX_BITS} bits", at)
            return base**n
        return base

    def atom(self) -> fmpq_poly:
        self._skip()
        start = self.pos
        c = self.text[self.pos : self.pos + 1]
        if c == "(":
            self.pos += 1
            self._enter()
            p = self.expr()
            self.depth -= 1
            if self._peek() != ")":
                raise self._error(f"expected ')', found {self._found()}")
            self.pos += 1
            return p
        m = _NUMBER.match(self.text, self.pos)
        if m:
            self.pos = m.end()
            if self.pos < len(self.text) and (
                self.text[self.pos].isalpha() or self.text[self.pos] in "_("
            ):
                raise self._error(
                    f"expected an operator after {_shown(m.group(0))!r}, found {self._found()}"
                    " (write multiplication as '*')"
                )
            try:
                return self._bounded(fmpq_poly([_literal(m.group(0))]), start)
            except ExpressionError as e:
                raise self._error(e.message, start) from None
        m = _NAME.match(self.text, self.pos)
        if m:
            name = m.group(0)
            if name == self.var:
                self.pos = m.end()
                return fmpq_poly([0, 1])
            raise self._error(
                f"unknown name {_shown(name, 40)!r}: only numbers, {self.var}, + - * / ^ **"
                " and parentheses are allowed",
                start,
            )
        if not c:
            raise self._error("expected a number, the variable or '(', found end of expression")
        raise self._error(
            f"unexpected character {c!r}: only numbers, {self.var}, + - * / ^ ** and"
            " parentheses are allowed"
        )


def parse_polynomial(text: str, variable: str) -> fmpq_poly:
    """Parse ``text`` as an exact polynomial in ``variable`` (e.g. ``"x"`` or ``"t"``).

    Raises ``ExpressionError`` (with the character offset) for anything outside the grammar.
    """
    if len(text) > MAX_LENGTH:
        raise ExpressionError(f"expression longer than {MAX_LENGTH} characters")
    if not text.strip():
        raise ExpressionError("empty expression")
    return _Parser(text, variable).parse()


def poly_text(p: fmpq_poly, variable: str) -> str:
    """``p`` written back as an expression in ``variable`` that ``parse_polynomial`` reads."""
    terms = []
    for k, c in reversed(list(enumerate(p.coeffs()))):
        if c == 0:
            continue
        cs = str(c)
        mono = "" if k == 0 else (variable if k == 1 else f"{variable}^{k}")
        if not mono:
            terms.append(cs)
        elif c == 1:
            terms.append(mono)
        elif c == -1:
            terms.append("-" + mono)
        else:
            terms.append(f"{cs}*{mono}")
    return " + ".join(terms).replace("+ -", "- ") if terms else "0"
