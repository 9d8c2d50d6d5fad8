"""Status codes (read from the library at import time) and the exceptions."""

import enum
import errno
import os
from typing import Union

from ._lib import lib, text

# The lowest status code looked for; the list in sinter.h ends well above it.
_LOWEST_STATUS = -64
_UNKNOWN_STATUS_TEXT = "unknown status"  # sinter_status_string() of an unknown code


class _StatusBase(enum.IntEnum):
    @property
    def message(self) -> str:
        """The library's static English text for this status."""
        return text(lib.sinter_status_string(self.value))


def _status_members():
    """[(name without 'SINTER_', value)] for 0, -1, ... until the first unknown code."""
    members = []
    for code in range(0, _LOWEST_STATUS - 1, -1):
        if text(lib.sinter_status_string(code)) == _UNKNOWN_STATUS_TEXT:
            break
        name = text(lib.sinter_status_name(code))
        members.append((name[len("SINTER_"):] if name.startswith("SINTER_") else name, code))
    return members


#: sinter_status as an IntEnum: Status.OK, Status.ERR_INVALID, ... (from the library).
Status = _StatusBase("Status", _status_members(), module=__name__)


class SinterError(RuntimeError):
    """A libsinter call failed.

    .status is the Status; .message the library's detail (sinter_last_error),
    or the status text when the library recorded none.
    """

    def __init__(self, status, message):
        super().__init__(status, message)
        self.status = status
        self.message = message

    def __str__(self):
        name = self.status.name if isinstance(self.status, Status) else str(self.status)
        return "%s [%s]" % (self.message, name)


class InvalidArgument(SinterError, ValueError):
    """SINTER_ERR_INVALID: an argument or a stored value is invalid."""


class BusyError(SinterError):
    """SINTER_ERR_BUSY: the particle set is locked by an outstanding view."""


class RangeError(SinterError, IndexError):
    """SINTER_ERR_RANGE: an index or count is out of range."""


class NotFound(SinterError, KeyError):
    """SINTER_ERR_NOT_FOUND: no such name or id."""


class Interrupted(SinterError):
    """SINTER_ERR_INTERRUPTED: a run stopped on request (Context.request_stop) after its
    current step; the last accepted state is kept, readable and checkpointable.

    Ctrl-C during Stepper.advance or Scene.run raises KeyboardInterrupt instead."""


class FileNotFound(SinterError, FileNotFoundError):
    """A file (or directory) a call reads does not exist: a FileNotFoundError that is also a
    SinterError. .filename is the path, .status the library's status (usually ERR_IO)."""

    def __init__(self, status, message, filename=None):
        FileNotFoundError.__init__(self, errno.ENOENT, message, filename)
        self.status = status
        self.message = message

    def __str__(self):
        return SinterError.__str__(self)


_ERROR_CLASSES = {
    "ERR_INVALID": InvalidArgument,
    "ERR_BUSY": BusyError,
    "ERR_RANGE": RangeError,
    "ERR_NOT_FOUND": NotFound,
    "ERR_INTERRUPTED": Interrupted,
}


def error(status, message):
    """The exception object for a non-zero status code."""
    try:
        status = Status(status)
    except ValueError:  # a code this library does not list: keep the number
        return SinterError(status, message)
    return _ERROR_CLASSES.get(status.name, SinterError)(status, message)


def check(status, ctx, function):
    """Raise the error for `status` (from C `function`) unless it is SINTER_OK.

    ctx is the sinter_ctx handle the call reported to (None for calls that
    have no context); its sinter_last_error() text becomes the message.
    """
    if status == 0:
        return
    message = ""
    if ctx and lib.sinter_last_status(ctx) == status:
        message = text(lib.sinter_last_error(ctx))
    if not message:
        message = "%s: %s" % (function, text(lib.sinter_status_string(status)))
    raise error(status, message)


def check_path(status: int, ctx, function: str, path: Union[str, bytes, "os.PathLike[str]"],
               directory: bool = False) -> None:
    """check() for a call that reads `path`: when the call failed and the path does not exist
    (or is not a directory, for `directory`), raise FileNotFound, a FileNotFoundError."""
    if status == 0:
        return
    exists = os.path.isdir(path) if directory else os.path.exists(path)
    if not exists:
        message = ""
        if ctx and lib.sinter_last_status(ctx) == status:
            message = text(lib.sinter_last_error(ctx))
        if not message:
            message = "%s: no such %s: %s" % (function, "directory" if directory else "file",
                                               os.fsdecode(path))
        try:
            code: Union[Status, int] = Status(status)
        except ValueError:
            code = status
        raise FileNotFound(code, message, os.fsdecode(path))
    check(status, ctx, function)
