"""Exception hierarchy of mdrvisc.

Every error raised by the library derives from :class:`MdrviscError`; errors caused by a
bad argument also derive from :class:`ValueError`, so ``except ValueError`` keeps working.
Results of limited accuracy are flagged by :class:`ResolutionWarning`.
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
