"""The error hierarchy of rprpr (the exit-code policy is ``report.exit``).

The core and the loader raise; only the command line renders and exits.
"""

from __future__ import annotations


class RprprError(Exception):
    """Base class of every error rprpr raises on purpose."""


class TaskFileError(RprprError, ValueError):
    """A task file that cannot be audited: names the file, the line, the column and the key.

    ``key`` is a dotted key path such as ``robot.links.3.mass`` ('' for the whole file).
    ``errors`` holds every error found in the file, by line and column, this one first: a
    file with three independent mistakes raises one ``TaskFileError`` (the first) whose
    ``errors`` names all three.
    """

    def __init__(
        self,
        message: str,
        *,
        file: str = "",
        line: int = 0,
        column: int = 0,
        key: str = "",
        errors: tuple[TaskFileError, ...] = (),
    ) -> None:
        super().__init__(message)
        self.message = message
        self.file = file
        self.line = line
        self.column = column
        self.key = key
        self.errors: tuple[TaskFileError, ...] = errors or (self,)

    def naming(self, file: str) -> TaskFileError:
        """This error alone (``errors`` just itself), naming ``file``."""
        return TaskFileError(
            self.message, file=file, line=self.line, column=self.column, key=self.key
        )

    def __str__(self) -> str:
        where = self.file or "<task>"
        if self.line:
            where += f":{self.line}"
            if self.column:
                where += f":{self.column}"
        key = f" {self.key}:" if self.key else ""
        return f"{where}:{key} {self.message}"


class ExpressionError(RprprError, ValueError):
    """A polynomial expression that is not allowed; ``offset`` is the 0-based character."""

    def __init__(self, message: str, offset: int = 0) -> None:
        super().__init__(message)
        self.message = message
        self.offset = offset
