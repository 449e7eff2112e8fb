"""The exceptions dem2d raises; their messages are the command line's (`dem2d: ...` without the
prefix)."""


class Error(Exception):
    """Every error dem2d raises derives from this."""


class InputError(Error, ValueError):
    """Bad input: a case, a state file or an argument. `field` names the case's field (such as
    `bodies[2].shape.a`) when the error is about one, else None."""

    field = None


class RunError(Error, RuntimeError):
    """A run could not go on."""


class BlowupError(RunError):
    """The run blew up: `step`, `time` (s), `body` (its index) and `reason` say where and why."""

    step = None
    time = None
    body = None
    reason = None


class OutputError(Error, OSError):
    """A file of the run could not be written (the message names it)."""


for _cls in (Error, InputError, RunError, BlowupError, OutputError):
    _cls.__module__ = "dem2d"
