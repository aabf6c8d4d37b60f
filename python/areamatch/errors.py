"""The exceptions areamatch raises: one base, `areamatch.Error`, and a class per kind of library
error. Each also derives from the built-in exception it was before (ValueError, OSError,
RuntimeError), so `except ValueError` keeps working."""


class Error(Exception):
    """Base of every error the areamatch library raises."""


class ParameterError(Error, ValueError):
    """A parameter out of its range (a resolution <= 0, a door width <= 0, ...)."""


class FormatError(Error, ValueError):
    """A file or buffer that is not a valid map (corrupt image, bad YAML, bad occupancy values)."""


class LimitError(Error, ValueError):
    """A map beyond a resource limit (cells, Voronoi segments, areas)."""


class IoError(Error, OSError):
    """A file that cannot be read or written."""


class InternalError(Error, RuntimeError):
    """Any other library error."""
