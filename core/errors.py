"""Errors the painter reports to a person: one sentence naming the file and the problem."""


class PaintReliefError(Exception):
    """A failure caused by input or settings; its message is one complete sentence."""


class InputError(PaintReliefError):
    """An input file is missing, unreadable, empty, too large or holds invalid values."""


class OutputError(PaintReliefError):
    """An output file or folder cannot be written."""


class ParameterError(PaintReliefError):
    """A parameter is outside its allowed range."""


class Cancelled(PaintReliefError):
    """The caller asked to stop; nothing partial was written."""
