"""Errors a user can act on. The dnarod command prints the message and exits 2.

Messages name the file, the key or atom, and what is allowed."""


class DnarodError(Exception):
    """Base of every error dnarod reports to a user as one clear message."""


class InputError(DnarodError):
    """Bad input: a file, a key, a structure, an argument."""


class ExternalToolError(DnarodError):
    """An external program (gmx) failed; the message quotes its relevant lines.
    returncode: the program's exit status where known (negative: killed by that signal)."""

    def __init__(self, message: str, returncode: int | None = None):
        super().__init__(message)
        self.returncode = returncode


class NumericalError(DnarodError, FloatingPointError):
    """The rod solver stopped on bad numbers (NaN, energy drift, a folded rod, step-size
    underflow). Also a FloatingPointError, like rodcore.NumericalError it comes from."""
