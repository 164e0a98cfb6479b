"""Exception hierarchy of mdrvisc.

Every error raised by the library derives from :class:`MdrviscError`; errors caused by a
bad argument also derive from :class:`ValueError`, so ``except ValueError`` keeps working.
Results of limited accuracy are flagged by :class:`ResolutionWarning`, fitted parameters
the data do not determine by :class:`IdentifiabilityWarning`.
"""


class MdrviscError(Exception):
    """Base class of all mdrvisc errors."""


class InvalidInputError(MdrviscError, ValueError):
    """An argument is out of range, of the wrong type or shape, or not finite."""


class ConvergenceError(MdrviscError, RuntimeError):
    """An iterative solver stopped before reaching its tolerance.

    Attributes
    ----------
    iterations : int
        Iterations performed.
    residual : float
        Relative residual when the solver stopped.
    """

    def __init__(self, message: str, iterations: int = 0, residual: float = float("nan")) -> None:
        super().__init__(message)
        self.iterations = iterations
        self.residual = residual


class DomainError(MdrviscError):
    """The solution left the region a method can represent (e.g. contact reached the edge of
    the BEM grid of an unbounded indenter)."""


class ResolutionWarning(UserWarning):
    """A result whose accuracy is limited by its resolution or by the method's reach (e.g. a
    contact that spans fewer than 10 elements): the message says where and what to change.
    The same messages are kept in ``Result.warnings``."""


class DataError(InvalidInputError):
    """Measured data that cannot be fitted: not finite, times not strictly increasing,
    arrays of different lengths, no contact at all, fewer usable points than free
    parameters. The message names the array and the first offending entry."""


class IdentifiabilityWarning(UserWarning):
    """A fitted parameter the data do not determine: its standard error is comparable to
    its value, or it is almost fully correlated with another. The message names it; the
    same messages are kept in ``FitResult.warnings``."""
