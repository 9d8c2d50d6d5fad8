"""Status codes (read from the library at import time) and the exceptions."""

import enum

from ._lib import lib, text

# The lowest status code looked for; the list in sinter.h ends well above it.
_LOWEST_STATUS = -64
_UNKNOWN_STATUS_TEXT = "unknown status"  # sinter_status_string() of an unknown code


class _StatusBase(enum.IntEnum):
    @property
    def message(self):
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


_ERROR_CLASSES = {
    "ERR_INVALID": InvalidArgument,
    "ERR_BUSY": BusyError,
    "ERR_RANGE": RangeError,
    "ERR_NOT_FOUND": NotFound,
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
