"""The exceptions towride raises (the Rust side creates them by these names)."""

from typing import Any, Optional


class TowrideError(Exception):
    """Any error of the towride library; the message is the one the CLI prints."""


class InputError(TowrideError, ValueError):
    """A bad input file or value: where it is (file, line, column, field) and what is wrong.

    ``str(e)`` reads as the CLI's ``error:`` line, e.g.
    ``vehicles/fabia.toml:12:3: field `spring.stiffness_n_m`: ...``.
    """

    def __init__(
        self,
        text: str,
        file: str,
        line: Optional[int],
        column: Optional[int],
        field: str,
        message: str,
    ) -> None:
        super().__init__(text)
        self.file = file
        self.line = line
        self.column = column
        self.field = field
        self.message = message


class SolverError(TowrideError):
    """The solver stopped a run before its end time.

    ``time`` is the time reached [s]; ``result`` holds everything computed up to it (the
    CLI writes the same partial result to outputs.csv).
    """

    def __init__(self, message: str, time: float, result: Any) -> None:
        super().__init__(f"run stopped at t = {time:.6f} s: {message}")
        self.message = message
        self.time = time
        self.result = result
