"""Integers passed to C: checked against their C type, so that one too large or negative for
it raises OverflowError instead of wrapping (ctypes keeps the low bits: material_id=2**40
would become 0).

declare() in sinter._lib routes every function with an integer argument through
checked_function; struct fields set from Python use to_c.
"""

import ctypes
import numbers

# ctypes' format characters of the integer types; lower case are signed
_INTEGER_CODES = "bBhHiIlLqQnN"


def integer_ctype(ctype):
    """True when `ctype` (an argtypes entry) is a C integer type (not bool or char)."""
    return (isinstance(ctype, type) and issubclass(ctype, ctypes._SimpleCData)
            and getattr(ctype, "_type_", None) in tuple(_INTEGER_CODES))


def c_range(ctype):
    """(lowest, highest) value of the C integer type `ctype`."""
    bits = 8 * ctypes.sizeof(ctype)
    if ctype._type_.islower():
        return -(1 << (bits - 1)), (1 << (bits - 1)) - 1
    return 0, (1 << bits) - 1


def to_c(value, ctype, what):
    """`value` as an int that fits `ctype`; OverflowError naming `what` when it does not.

    Values that are not integers (a ctypes object, a float) are returned unchanged, for ctypes
    to accept or refuse as it does.
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        return value
    value = int(value)
    low, high = c_range(ctype)
    if not low <= value <= high:
        raise OverflowError("%s = %d does not fit the C type %s (%d to %d)"
                            % (what, value, ctype.__name__, low, high))
    return value


def checked_function(name, function):
    """`function` (a ctypes function with argtypes set), or a wrapper of it that checks its
    integer arguments with to_c first when it has any."""
    positions = [(k, t) for k, t in enumerate(function.argtypes or ()) if integer_ctype(t)]
    if not positions:
        return function

    def call(*args):
        for k, ctype in positions:
            if k < len(args):
                to_c(args[k], ctype, "%s argument %d" % (name, k + 1))
        return function(*args)

    call.__name__ = call.__qualname__ = name
    call.argtypes = function.argtypes
    call.restype = function.restype
    call.c_function = function
    return call
