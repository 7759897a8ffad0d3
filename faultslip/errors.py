"""Exceptions and warnings of faultslip.

Every error a user can cause derives from :class:`FaultslipError`; the CLI
turns it into one sentence on stderr and exit status 2.
"""

import difflib


class FaultslipError(Exception):
    """Base class of every error faultslip raises on purpose.

    Parameters
    ----------
    message : str
        One sentence for the user (every error faultslip raises on purpose): what went wrong, where, and what to do; the command line prints it
        alone and exits with status 2.
    """


class InputError(FaultslipError, ValueError):
    """Bad input: a wrong unit, an unknown name, a non-physical value.

    Parameters
    ----------
    message : str
        One sentence for the user (bad input): what went wrong, where, and what to do; the command line prints it
        alone and exits with status 2.
    """


class OutputError(FaultslipError):
    """An output cannot be written: a full disk, a folder without permission, a planted lock."""


class MethodError(FaultslipError):
    """A solution method was asked for outside its domain of validity.

    Parameters
    ----------
    message : str
        One sentence for the user (a method asked for outside its domain): what went wrong, where, and what to do; the command line prints it
        alone and exits with status 2.
    """


class SolverError(FaultslipError, RuntimeError):
    """A numerical method failed; the message names method, scene and remedy.

    Parameters
    ----------
    message : str
        One sentence for the user (a failed method): what went wrong, where, and what to do; the command line prints it
        alone and exits with status 2.
    """


class NoEventsError(SolverError):
    """A fault run found no earthquakes within its time limit: it creeps, or slips too slowly to count."""


class EvaluationBudgetError(SolverError):
    """An integration stopped at the right-hand-side evaluations it was allowed (a slip phase past its budget)."""


class OutOfDomainWarning(UserWarning):
    """A method was used where it is known to be inaccurate.

    Parameters
    ----------
    message : str
        One sentence for the user (a method used where it is known to be inaccurate): what went wrong, where, and what to do; the command line prints it
        alone and exits with status 2.
    """


def refusal(call) -> str | None:
    """The sentence with which ``call()`` refuses its input (an :class:`InputError`), or None where it takes it."""
    try:
        call()
    except InputError as exc:
        return str(exc)
    return None


def did_you_mean(name: str, allowed, n: int = 2, cutoff: float = 0.6) -> str:
    """``"; did you mean a, b?"`` for the close matches of ``name`` in ``allowed``, else ``""``."""

    close = difflib.get_close_matches(name, list(allowed), n=n, cutoff=cutoff)
    return f"; did you mean {', '.join(close)}?" if close else ""


def beside(value: float, reference: float, digits: int = 3) -> str:
    """``value`` with at least ``digits`` significant digits and as many more (up to 15) as tell it apart from
    ``reference`` in a message: K / K_c = 1.003 against 1, not "1 >= 1"."""
    for precision in range(digits, 16):
        text = f"{value:.{precision}g}"
        if value == reference or text != f"{reference:.{precision}g}":
            return text
    return repr(value)
