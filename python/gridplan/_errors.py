"""gridplan's exception classes, raised by the native module with the command line's messages."""

from typing import Optional, Tuple


class GridplanError(Exception):
    """Base class of every error gridplan raises (besides ValueError and TypeError for
    arguments of the wrong value or type)."""


class ConfigError(GridplanError):
    """An experiment config that cannot be read: ``file:line:column: message``."""

    def __init__(self, message: str, *, file: str = "", line: int = 0, column: int = 0) -> None:
        super().__init__(message)
        #: The config file.
        self.file = file
        #: 1-based line, 0 when the error concerns the whole file.
        self.line = line
        #: 1-based column.
        self.column = column


class MapError(GridplanError):
    """A map or scenario file that cannot be read: ``file:line:column: message``."""

    def __init__(self, message: str, *, file: str = "", line: int = 0, column: int = 0) -> None:
        super().__init__(message)
        #: The map or scenario file.
        self.file = file
        #: 1-based line, 0 when the error concerns the whole file.
        self.line = line
        #: 1-based column, 0 when the error concerns the whole line.
        self.column = column


class OutputError(GridplanError):
    """A results directory gridplan may not replace (not its own, a file, read-only,
    locked by another run); nothing was written."""


class DeterminismError(GridplanError):
    """A run repeated to record its expanded cells (``figures_expanded``) did not give the
    timed run's status, counters and path: a bug in a planner; nothing was written."""


class ProblemError(GridplanError, ValueError):
    """A start or goal outside the grid or on a blocked cell."""

    def __init__(self, message: str, *, endpoint: str = "", cell: Tuple[int, int] = (0, 0)) -> None:
        super().__init__(message)
        #: ``"start"`` or ``"goal"``.
        self.endpoint = endpoint
        #: The cell ``(x, y)``.
        self.cell = cell


class ParameterError(GridplanError, ValueError):
    """A planner name, parameter or budget that is unknown or invalid; ``key`` names it."""

    def __init__(self, message: str, *, key: Optional[str] = None) -> None:
        super().__init__(message)
        #: The parameter's key (``"planner"`` for an unknown planner name).
        self.key = key


class GridplanWarning(UserWarning):
    """What gridplan read but doubted or ignored (a ROS map's second YAML document, a
    scenario file naming another map, a planner label that is not admissible), raised
    through :mod:`warnings` as the command line prints it on stderr."""
