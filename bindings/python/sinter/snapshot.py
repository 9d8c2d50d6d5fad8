"""Snapshots of a stepper's contacts and quasi-static links (sinter_snapshot_create).

    snap = stepper.snapshot()          # after a step or an advance
    snap.contacts["normal_force"]      # one value per contact [N], pair contacts first
    snap.contacts["wall"]              # -1 for a particle pair, else the wall index
    snap.links["neck_ratio"]           # quasi-static stepper: x / min(r_a, r_b) per link

The arrays are copies (NumPy arrays, or memoryviews where NumPy is absent or
sinter.particles.USE_NUMPY is false): the snapshot stays valid whatever the
stepper does next. Units are SI (see the sinter_contact_data and
sinter_link_data constants of sinter.h).
"""

import ctypes
import enum

from . import particles as _particles
from ._errors import check
from ._lib import SnapshotPtr, c_enum, lib

#: Per-contact arrays, in the order of sinter_contact_data (SINTER_CONTACT_DATA_*).
CONTACT_DATA = ("id_a", "id_b", "wall", "normal", "overlap", "radius", "area", "normal_force",
                "tangential_force", "heat_flow", "current")
#: Per-link arrays, in the order of sinter_link_data (SINTER_LINK_DATA_*).
LINK_DATA = ("id_a", "id_b", "neck_radius", "neck_ratio", "approach", "age", "phase",
             "sintering_force", "beam_force", "beam_moment", "correction")

class ContactData(enum.IntEnum):
    """sinter_contact_data: the per-contact arrays of a snapshot."""
    ID_A = 0
    ID_B = 1
    WALL = 2
    NORMAL = 3
    OVERLAP = 4
    RADIUS = 5
    AREA = 6
    NORMAL_FORCE = 7
    TANGENTIAL_FORCE = 8
    HEAT_FLOW = 9
    CURRENT = 10


class LinkData(enum.IntEnum):
    """sinter_link_data: the per-link arrays of a snapshot (quasi-static stepper)."""
    ID_A = 0
    ID_B = 1
    NECK_RADIUS = 2
    NECK_RATIO = 3
    APPROACH = 4
    AGE = 5
    PHASE = 6
    SINTERING_FORCE = 7
    BEAM_FORCE = 8
    BEAM_MOMENT = 9
    CORRECTION = 10


_FORMATS = {0: "d", 1: "i", 2: "I", 3: "Q"}  # sinter_dtype


def _copy(address, count, components, fmt):
    """A copy of count*components elements at `address`: NumPy array or memoryview."""
    itemsize = ctypes.sizeof(_particles._CTYPES[fmt])
    size = count * components
    raw = bytearray(ctypes.string_at(address, size * itemsize)) if size else bytearray()
    shape = (count, components) if components > 1 else (count,)
    numpy = _particles.numpy
    if _particles.USE_NUMPY and numpy is not None:
        return numpy.frombuffer(raw, dtype=fmt).reshape(shape)
    buffer = memoryview(raw)
    return buffer.cast(fmt, shape) if size > 0 else buffer.cast(fmt)


class Snapshot:
    """The contacts and links of a stepper's state when it was taken (Stepper.snapshot).

    Attributes: time [s], pair_contacts, wall_contacts, link_count, and the dicts
    `contacts` (CONTACT_DATA, pair contacts then wall contacts) and `links` (LINK_DATA).
    """

    def __init__(self, time, pair_contacts, wall_contacts, link_count, contacts, links):
        self.time = time
        self.pair_contacts = pair_contacts
        self.wall_contacts = wall_contacts
        self.link_count = link_count
        self.contacts = contacts
        self.links = links

    def __repr__(self):
        return ("Snapshot(time=%g, pair_contacts=%d, wall_contacts=%d, links=%d)"
                % (self.time, self.pair_contacts, self.wall_contacts, self.link_count))


def take(stepper):
    """Snapshot of `stepper`'s current state (see Stepper.snapshot)."""
    ctx = stepper.context._handle
    handle = SnapshotPtr()
    stepper._call(lib.sinter_snapshot_create, ctypes.byref(handle), stepper._ptr)
    try:
        pairs, walls, links = ctypes.c_size_t(), ctypes.c_size_t(), ctypes.c_size_t()
        time = ctypes.c_double()
        check(lib.sinter_snapshot_counts(handle, ctypes.byref(pairs), ctypes.byref(walls),
                                         ctypes.byref(links), ctypes.byref(time)),
              ctx, "sinter_snapshot_counts")

        def arrays(c_function, names):
            out = {}
            for index, name in enumerate(names):
                data, count = ctypes.c_void_p(), ctypes.c_size_t()
                components, dtype = ctypes.c_size_t(), c_enum()
                check(c_function(handle, index, ctypes.byref(data), ctypes.byref(count),
                                 ctypes.byref(components), ctypes.byref(dtype)),
                      ctx, c_function.__name__)
                out[name] = _copy(data.value, count.value, components.value,
                                  _FORMATS[dtype.value])
            return out

        contacts = arrays(lib.sinter_snapshot_contacts, CONTACT_DATA)
        link_arrays = arrays(lib.sinter_snapshot_links, LINK_DATA)
    finally:
        lib.sinter_snapshot_destroy(handle)
    return Snapshot(time.value, pairs.value, walls.value, links.value, contacts, link_arrays)
