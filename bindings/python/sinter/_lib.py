"""Finding and loading libsinter, and the one table of its C signatures.

Every function of the public headers sinter.h, sinter_submodel.h and sinter_domain.h is declared in SIGNATURES
below (restype and argtypes), with the structs and callback types they use;
no other module sets argtypes. The tests compare this table with the headers.
"""

import ctypes
import ctypes.util
import os

from ._integers import checked_function


class LibraryNotFound(OSError):
    """libsinter could not be loaded; the message lists every place tried."""


# --- C types -------------------------------------------------------------

def _opaque(name):
    """A pointer type to an incomplete struct, so that handles are not mixed up."""
    return ctypes.POINTER(type(name, (ctypes.Structure,), {"_cname": name}))


CtxPtr = _opaque("sinter_ctx")
MaterialPtr = _opaque("sinter_material")
ParticlesPtr = _opaque("sinter_particles")
WallsPtr = _opaque("sinter_walls")
ForceModelPtr = _opaque("sinter_force_model")
StepperPtr = _opaque("sinter_stepper")
ScenePtr = _opaque("sinter_scene")
SeriesPtr = _opaque("sinter_series")
HeatModelPtr = _opaque("sinter_heat_model")
NeckModelPtr = _opaque("sinter_neck_model")
ElectricModelPtr = _opaque("sinter_electric_model")
SnapshotPtr = _opaque("sinter_snapshot")

_P = ctypes.POINTER
_str = ctypes.c_char_p
_int = ctypes.c_int
_size = ctypes.c_size_t
_double = ctypes.c_double
_u64 = ctypes.c_uint64

c_status = _int  # enum sinter_status (int-sized, negative = error)
c_enum = _int  # the other enums: sinter_material_param, sinter_field, sinter_dtype, ...

LogFn = ctypes.CFUNCTYPE(None, _int, _str, ctypes.c_void_p)
AllocFn = ctypes.CFUNCTYPE(ctypes.c_void_p, _size, ctypes.c_void_p)
ReallocFn = ctypes.CFUNCTYPE(ctypes.c_void_p, ctypes.c_void_p, _size, ctypes.c_void_p)
FreeFn = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)
WallMotionFn = ctypes.CFUNCTYPE(_int, _double, _P(_double), _P(_double), ctypes.c_void_p)
ObserverFn = ctypes.CFUNCTYPE(_int, StepperPtr, _double, ctypes.c_void_p)
ProgressFn = ctypes.CFUNCTYPE(_int, _double, _double, ctypes.c_void_p)
SofteningFn = ctypes.CFUNCTYPE(_double, _double, ctypes.c_void_p)


class Allocator(ctypes.Structure):
    """struct sinter_allocator; struct_size = ctypes.sizeof(Allocator)."""

    _cname = "sinter_allocator"
    _fields_ = [("struct_size", _size), ("alloc", AllocFn), ("realloc", ReallocFn),
                ("free", FreeFn), ("user", ctypes.c_void_p)]


# sinter_domain.h (issue 43): ghosts of other subdomains and the host's collective operations
ReduceFn = ctypes.CFUNCTYPE(_int, ctypes.c_void_p, _size, _int, _int, ctypes.c_void_p)
ExscanFn = ctypes.CFUNCTYPE(_int, _u64, _P(_u64), _P(_u64), ctypes.c_void_p)
RedistributeFn = ctypes.CFUNCTYPE(_int, StepperPtr, ctypes.c_void_p)
DestroyUserFn = ctypes.CFUNCTYPE(None, ctypes.c_void_p)


class GhostFields(ctypes.Structure):
    """struct sinter_ghost_fields: one layer of ghosts (SI units, arrays borrowed)."""

    _cname = "sinter_ghost_fields"
    _fields_ = [("struct_size", _size), ("count", _size), ("id", _P(_u64)),
                ("position", _P(_double)), ("velocity", _P(_double)), ("spin", _P(_double)),
                ("rotation", _P(_double)), ("radius", _P(_double)), ("mass", _P(_double)),
                ("inertia", _P(_double)), ("temperature", _P(_double)),
                ("material", _P(ctypes.c_int32)), ("flags", _P(ctypes.c_uint32)),
                ("owner", _P(ctypes.c_int32))]


class Halo(ctypes.Structure):
    """struct sinter_halo: one exchange of per-particle rows."""

    _cname = "sinter_halo"
    _fields_ = [("struct_size", _size), ("direction", _int), ("width", _size),
                ("data", _P(_double)), ("id", _P(_u64)), ("owned", _size), ("ghosts", _size)]


HaloFn = ctypes.CFUNCTYPE(_int, _P(Halo), ctypes.c_void_p)


class DomainOps(ctypes.Structure):
    """struct sinter_domain_ops: the host's collective operations."""

    _cname = "sinter_domain_ops"
    _fields_ = [("struct_size", _size), ("reduce", ReduceFn), ("exscan", ExscanFn),
                ("halo", HaloFn), ("redistribute", RedistributeFn),
                ("destroy_user", DestroyUserFn)]


class StepperStats(ctypes.Structure):
    """struct sinter_stepper_stats (times in s)."""

    _cname = "sinter_stepper_stats"
    _fields_ = [("struct_size", _size), ("steps", _u64), ("rejected", _u64),
                ("neighbor_builds", _u64), ("contacts", _u64), ("wall_contacts", _u64),
                ("time", _double), ("dt", _double), ("seconds_neighbor", _double),
                ("seconds_force", _double), ("seconds_integrate", _double),
                ("seconds_total", _double), ("iterations", _u64), ("evaluations", _u64),
                ("contraction", _double), ("bonds_broken", _u64)]


class SinteringStats(ctypes.Structure):
    """struct sinter_sintering_stats (lengths in m)."""

    _cname = "sinter_sintering_stats"
    _fields_ = [("struct_size", _size), ("links", _u64), ("neck_mean", _double),
                ("neck_min", _double), ("neck_max", _double), ("neck_ratio_mean", _double),
                ("shrinkage", _double * 3), ("relative_density", _double),
                ("coordination", _double), ("pcg_iterations", _u64)]


class VtuArray(ctypes.Structure):
    """struct sinter_vtu_array: an extra per-particle array for a VTU frame."""

    _cname = "sinter_vtu_array"
    _fields_ = [("name", _str), ("data", _P(_double)), ("components", _size)]


class PackingOptions(ctypes.Structure):
    """struct sinter_packing_options (lengths in m, temperature in K)."""

    _cname = "sinter_packing_options"
    _fields_ = [("struct_size", _size), ("box_min", _double * 3), ("box_max", _double * 3),
                ("distribution", _int), ("radius_mean", _double), ("radius_spread", _double),
                ("radius_min", _double), ("radius_max", _double), ("gap", _double),
                ("seed", _u64), ("max_attempts", _u64), ("material", ctypes.c_int32),
                ("temperature", _double),
                # appended in issue 38
                ("radius_median", _double), ("radius_gsd", _double),
                ("table_diameter", _P(_double)), ("table_cumulative", _P(_double)),
                ("table_points", _size), ("table_basis", _int), ("mixture_count", _size),
                ("mixture_materials", _P(ctypes.c_int32)),
                ("mixture_mass_fractions", _P(_double)),
                # appended in issue 38: sizes per material (mixture_count structs like this)
                ("mixture_sizes", ctypes.c_void_p)]


class InsertionOptions(ctypes.Structure):
    """struct sinter_insertion_options (mass rate in kg/s, times in s, velocity in m/s)."""

    _cname = "sinter_insertion_options"
    _fields_ = [("struct_size", _size), ("region", _int), ("mass_rate", _double),
                ("start", _double), ("end", _double), ("interval", _double),
                ("velocity", _double * 3)]


class CompactionOptions(ctypes.Structure):
    """struct sinter_compaction_options (lengths in m, speed in m/s, stress in Pa, energy in J)."""

    _cname = "sinter_compaction_options"
    _fields_ = [("struct_size", _size), ("box_min", _double * 3), ("box_max", _double * 3),
                ("volume_fraction", _double), ("friction", _double), ("restitution", _double),
                ("velocity", _double), ("max_pressure", _double), ("stop_at_jamming", _int),
                ("ke_per_particle", _double), ("relax_time_max", _double), ("dt", _double)]


class CoarseOptions(ctypes.Structure):
    """struct sinter_coarse_options: a regular grid and a Gaussian kernel (lengths in m)."""

    _cname = "sinter_coarse_options"
    _fields_ = [("struct_size", _size), ("origin", _double * 3), ("spacing", _double * 3),
                ("points", _size * 3), ("width", _double), ("cutoff", _double)]


class CompactionResult(ctypes.Structure):
    """struct sinter_compaction_result: what sinter_pack_compact achieved (SI units)."""

    _cname = "sinter_compaction_result"
    _fields_ = [("struct_size", _size), ("box_min", _double * 3), ("box_max", _double * 3),
                ("volume_fraction", _double), ("jammed", _int), ("coordination", _double),
                ("contacts", _u64), ("max_overlap", _double), ("max_overlap_ratio", _double),
                ("max_wall_overlap_ratio", _double), ("pressure", _double),
                ("kinetic_energy", _double), ("time", _double), ("relax_time", _double),
                ("dt", _double), ("steps", _u64)]


class NeckStats(ctypes.Structure):
    """struct sinter_neck_stats: work of the last sinter_neck_two_particles call (seconds in s)."""

    _cname = "sinter_neck_stats"
    _fields_ = [("struct_size", _size), ("steps", _u64), ("rhs_evaluations", _u64),
                ("jacobian_evaluations", _u64), ("error_test_failures", _u64),
                ("nonlinear_iterations", _u64), ("nonlinear_failures", _u64),
                ("segments", _u64), ("seconds", _double)]


# --- sinter_submodel.h: host submodels ------------------------------------
# Data pointers of the two borrowed structs are declared c_void_p: reading such
# a field gives the address as an int (or None), which is what the zero-copy
# array wrappers of sinter._callbacks need, without a ctypes.cast per field.

class StateView(ctypes.Structure):
    """struct sinter_state_view: the state a host submodel reads (borrowed during a callback)."""

    _cname = "sinter_state_view"
    _fields_ = [("count", _size), ("position", ctypes.c_void_p), ("velocity", ctypes.c_void_p),
                ("spin", ctypes.c_void_p), ("radius", ctypes.c_void_p),
                ("mass", ctypes.c_void_p), ("inertia", ctypes.c_void_p),
                ("temperature", ctypes.c_void_p), ("material", ctypes.c_void_p),
                ("wall_count", _size), ("wall_point", ctypes.c_void_p),
                ("wall_normal", ctypes.c_void_p), ("wall_velocity", ctypes.c_void_p),
                ("time", _double), ("dt", _double)]


class ContactBatch(ctypes.Structure):
    """struct sinter_contact_batch: active contacts as arrays (borrowed during a callback)."""

    _cname = "sinter_contact_batch"
    _fields_ = [("count", _size), ("kind", _int), ("i", ctypes.c_void_p), ("j", ctypes.c_void_p),
                ("normal", ctypes.c_void_p), ("overlap", ctypes.c_void_p),
                ("distance", ctypes.c_void_p), ("contact_radius", ctypes.c_void_p),
                ("area", ctypes.c_void_p), ("branch", ctypes.c_void_p),
                ("history_size", _size), ("history", ctypes.c_void_p),
                ("history_trial", ctypes.c_void_p), ("force", ctypes.c_void_p),
                ("torque_i", ctypes.c_void_p), ("torque_j", ctypes.c_void_p)]


ContactsFn = ctypes.CFUNCTYPE(_int, _P(StateView), _P(ContactBatch), ctypes.c_void_p)
# The double * outputs of these two are c_void_p too: the callback receives their address.
BodyFn = ctypes.CFUNCTYPE(_int, _P(StateView), ctypes.c_void_p, ctypes.c_void_p, ctypes.c_void_p)
PowerFn = ctypes.CFUNCTYPE(_int, _P(StateView), _P(ContactBatch), _P(ContactBatch),
                           ctypes.c_void_p, ctypes.c_void_p)
DestroyUserFn = ctypes.CFUNCTYPE(None, ctypes.c_void_p)
# The electric model's conductance law and Joule split: (state, batch, const double * in,
# double * out, user), the arrays as addresses.
ConductanceFn = ctypes.CFUNCTYPE(_int, _P(StateView), _P(ContactBatch), ctypes.c_void_p,
                                 ctypes.c_void_p, ctypes.c_void_p)
JouleSplitFn = ctypes.CFUNCTYPE(_int, _P(StateView), _P(ContactBatch), ctypes.c_void_p,
                                ctypes.c_void_p, ctypes.c_void_p)


class ForceCallbacks(ctypes.Structure):
    """struct sinter_force_callbacks (struct_size = ctypes.sizeof(ForceCallbacks))."""

    _cname = "sinter_force_callbacks"
    _fields_ = [("struct_size", _size), ("history_size", _size), ("contacts", ContactsFn),
                ("particles", BodyFn), ("destroy_user", DestroyUserFn)]


class HeatCallbacks(ctypes.Structure):
    """struct sinter_heat_callbacks (struct_size = ctypes.sizeof(HeatCallbacks))."""

    _cname = "sinter_heat_callbacks"
    _fields_ = [("struct_size", _size), ("power", PowerFn), ("destroy_user", DestroyUserFn)]


class ElectricCallbacks(ctypes.Structure):
    """struct sinter_electric_callbacks (struct_size = ctypes.sizeof(ElectricCallbacks))."""

    _cname = "sinter_electric_callbacks"
    _fields_ = [("struct_size", _size), ("conductance", ConductanceFn),
                ("joule_split", JouleSplitFn), ("destroy_user", DestroyUserFn)]


class NeckLawBatch(ctypes.Structure):
    """struct sinter_neck_law_batch: the quasi-static stepper's links (borrowed during a call)."""

    _cname = "sinter_neck_law_batch"
    _fields_ = [("count", _size), ("time", _double), ("dt", _double),
                ("schedule_count", _size), ("schedule_time", ctypes.c_void_p),
                ("schedule_temperature", ctypes.c_void_p), ("a", ctypes.c_void_p),
                ("b", ctypes.c_void_p), ("material", ctypes.c_void_p),
                ("radius_a", ctypes.c_void_p), ("radius_b", ctypes.c_void_p),
                ("state", ctypes.c_void_p)]


NeckLawFn = ctypes.CFUNCTYPE(_int, _P(NeckLawBatch), ctypes.c_void_p)


class NeckLawCallbacks(ctypes.Structure):
    """struct sinter_neck_law_callbacks (struct_size = ctypes.sizeof(NeckLawCallbacks))."""

    _cname = "sinter_neck_law_callbacks"
    _fields_ = [("struct_size", _size), ("advance", NeckLawFn), ("destroy_user", DestroyUserFn)]


# name: (restype, argtypes), in the order of sinter.h. `const T x[3]` is a T pointer.
SIGNATURES = {
    # status codes and version
    "sinter_status_string": (_str, [_int]),
    "sinter_status_name": (_str, [_int]),
    "sinter_version_number": (ctypes.c_uint, []),
    "sinter_version_string": (_str, []),
    # context
    "sinter_ctx_create": (c_status, [_P(CtxPtr), _P(Allocator)]),
    "sinter_ctx_destroy": (None, [CtxPtr]),
    "sinter_last_error": (_str, [CtxPtr]),
    "sinter_last_status": (c_status, [CtxPtr]),
    "sinter_clear_error": (c_status, [CtxPtr]),
    "sinter_ctx_set_log": (c_status, [CtxPtr, LogFn, _int, ctypes.c_void_p]),
    "sinter_ctx_set_threads": (c_status, [CtxPtr, _int]),
    "sinter_ctx_request_stop": (c_status, [CtxPtr]),
    "sinter_ctx_get_threads": (c_status, [CtxPtr, _P(_int)]),
    # materials
    "sinter_material_create": (c_status, [_P(MaterialPtr), CtxPtr, _str]),
    "sinter_material_destroy": (None, [MaterialPtr]),
    "sinter_material_clone": (c_status, [_P(MaterialPtr), MaterialPtr]),
    "sinter_material_set": (c_status, [MaterialPtr, c_enum, _double]),
    "sinter_material_get": (c_status, [MaterialPtr, c_enum, _P(_double)]),
    "sinter_material_name": (_str, [MaterialPtr]),
    "sinter_material_param_info": (
        c_status, [c_enum, _P(_str), _P(_str), _P(_str), _P(_double), _P(_double), _P(_double)]),
    "sinter_material_param_find": (c_status, [_str, _P(c_enum)]),
    # particle sets
    "sinter_field_info": (c_status, [c_enum, _P(_str), _P(_str), _P(c_enum), _P(_size)]),
    "sinter_particles_create": (c_status, [_P(ParticlesPtr), CtxPtr]),
    "sinter_particles_destroy": (None, [ParticlesPtr]),
    "sinter_particles_count": (c_status, [ParticlesPtr, _P(_size)]),
    "sinter_particles_owned_count": (c_status, [ParticlesPtr, _P(_size)]),
    "sinter_particles_capacity": (c_status, [ParticlesPtr, _P(_size)]),
    "sinter_particles_reserve": (c_status, [ParticlesPtr, _size]),
    "sinter_particles_set_material": (c_status, [ParticlesPtr, ctypes.c_int32, MaterialPtr]),
    "sinter_particles_set_softening_curve": (c_status, [ParticlesPtr, ctypes.c_int32, _size, _P(_double), _P(_double)]),
    "sinter_particles_set_softening_callback": (c_status, [ParticlesPtr, ctypes.c_int32, SofteningFn, ctypes.c_void_p]),
    "sinter_particles_set_property_table": (c_status, [ParticlesPtr, ctypes.c_int32, c_enum, _size, _P(_double), _P(_double)]),
    "sinter_particles_property": (c_status, [ParticlesPtr, ctypes.c_int32, c_enum, _double, _P(_double)]),
    "sinter_particles_specific_enthalpy": (c_status, [ParticlesPtr, ctypes.c_int32, _double, _P(_double)]),
    "sinter_particles_get_material": (c_status, [ParticlesPtr, ctypes.c_int32, _P(MaterialPtr)]),
    "sinter_particles_add": (
        c_status, [ParticlesPtr, _size, _P(_double), _P(_double), ctypes.c_int32, _double,
                   _P(_size)]),
    "sinter_particles_add_with_ids": (
        c_status, [ParticlesPtr, _size, _P(_u64), _P(_double), _P(_double), ctypes.c_int32,
                   _double, _P(_size)]),
    "sinter_particles_remove": (c_status, [ParticlesPtr, _size, _P(_size)]),
    "sinter_particles_view": (
        c_status, [ParticlesPtr, c_enum, _P(ctypes.c_void_p), _P(_size), _P(_size)]),
    "sinter_particles_view_read": (
        c_status, [ParticlesPtr, c_enum, _P(ctypes.c_void_p), _P(_size), _P(_size)]),
    "sinter_particles_release": (c_status, [ParticlesPtr, c_enum]),
    "sinter_particles_views_out": (c_status, [ParticlesPtr, _P(_size)]),
    "sinter_particles_validate": (c_status, [ParticlesPtr, _P(_size)]),
    "sinter_particles_find_id": (c_status, [ParticlesPtr, _u64, _P(_size)]),
    "sinter_particles_sort_spatial": (c_status, [ParticlesPtr]),
    # walls
    "sinter_walls_create": (c_status, [_P(WallsPtr), CtxPtr]),
    "sinter_walls_destroy": (None, [WallsPtr]),
    "sinter_walls_count": (c_status, [WallsPtr, _P(_size)]),
    "sinter_walls_add_plane": (
        c_status, [WallsPtr, _P(_double), _P(_double), MaterialPtr, _P(_size)]),
    "sinter_walls_set_material": (c_status, [WallsPtr, _size, MaterialPtr]),
    "sinter_walls_set_velocity": (c_status, [WallsPtr, _size, _P(_double)]),
    "sinter_walls_set_schedule": (c_status, [WallsPtr, _size, _size, _P(_double), _P(_double)]),
    "sinter_walls_set_sine": (c_status, [WallsPtr, _size, _P(_double), _double]),
    "sinter_walls_set_callback": (c_status, [WallsPtr, _size, WallMotionFn, ctypes.c_void_p]),
    "sinter_walls_set_motion_start": (c_status, [WallsPtr, _size, _double]),
    "sinter_walls_set_temperature": (c_status, [WallsPtr, _size, _double]),
    "sinter_walls_set_temperature_schedule": (c_status, [WallsPtr, _size, _size, _P(_double), _P(_double)]),
    "sinter_walls_get_state": (c_status, [WallsPtr, _size, _P(_double), _P(_double)]),
    "sinter_walls_get_normal": (c_status, [WallsPtr, _size, _P(_double)]),
    "sinter_walls_get_force": (c_status, [WallsPtr, _size, _P(_double)]),
    "sinter_walls_add_rectangle": (
        c_status, [WallsPtr, _P(_double), _P(_double), _P(_double), _double, _double, MaterialPtr,
                   _P(_size)]),
    "sinter_walls_add_disc": (
        c_status, [WallsPtr, _P(_double), _P(_double), _double, MaterialPtr, _P(_size)]),
    "sinter_walls_add_cylinder": (
        c_status, [WallsPtr, _P(_double), _P(_double), _double, _double, _int, MaterialPtr,
                   _P(_size)]),
    "sinter_walls_add_mesh": (
        c_status, [WallsPtr, _str, _double, _P(_double), _P(_double), _int, _double, MaterialPtr,
                   _P(_size)]),
    "sinter_walls_get_kind": (c_status, [WallsPtr, _size, _P(_int)]),
    "sinter_walls_get_shape": (c_status, [WallsPtr, _size, _P(_double), _P(_double), _P(_double)]),
    "sinter_walls_set_spin": (c_status, [WallsPtr, _size, _double]),
    "sinter_walls_set_rotation": (
        c_status, [WallsPtr, _size, _P(_double), _P(_double), _double]),
    "sinter_walls_get_moment": (c_status, [WallsPtr, _size, _P(_double)]),
    "sinter_walls_set_moment": (c_status, [WallsPtr, _size, _int]),
    "sinter_walls_set_servo": (
        c_status, [WallsPtr, _size, _size, _P(_double), _P(_double), _double, _double, _double]),
    "sinter_walls_get_servo": (c_status, [WallsPtr, _size, _P(_double), _P(_double), _P(_double)]),
    # force submodels
    "sinter_force_model_create": (c_status, [_P(ForceModelPtr), CtxPtr, _str]),
    "sinter_force_model_destroy": (None, [ForceModelPtr]),
    "sinter_force_model_name": (_str, [ForceModelPtr]),
    "sinter_force_model_set": (c_status, [ForceModelPtr, _str, _double]),
    "sinter_force_model_get": (c_status, [ForceModelPtr, _str, _P(_double)]),
    # steppers
    "sinter_stepper_create": (
        c_status, [_P(StepperPtr), CtxPtr, c_enum, ParticlesPtr, WallsPtr]),
    "sinter_stepper_destroy": (None, [StepperPtr]),
    "sinter_stepper_add_force": (c_status, [StepperPtr, ForceModelPtr]),
    "sinter_stepper_set_dt": (c_status, [StepperPtr, _double]),
    "sinter_stepper_set_skin": (c_status, [StepperPtr, _double]),
    "sinter_stepper_set_domain": (c_status, [StepperPtr, _P(_double), _P(_double)]),
    "sinter_stepper_set_periodic": (c_status, [StepperPtr, _int, _double, _double]),
    "sinter_stepper_get_periodic": (c_status, [StepperPtr, _int, _P(_int), _P(_double),
                                               _P(_double)]),
    "sinter_stepper_set_option": (c_status, [StepperPtr, _str, _double]),
    "sinter_stepper_get_option": (c_status, [StepperPtr, _str, _P(_double)]),
    # output (implemented in src/io)
    "sinter_write_vtu": (c_status, [ParticlesPtr, _str, _P(VtuArray), _size]),
    "sinter_write_pvd": (c_status, [CtxPtr, _str, _size, _P(_double), _P(_str)]),
    "sinter_series_create": (c_status, [_P(SeriesPtr), CtxPtr, _size, _P(_str), _P(_str)]),
    "sinter_series_destroy": (None, [SeriesPtr]),
    "sinter_series_append": (c_status, [SeriesPtr, _P(_double)]),
    "sinter_series_read_csv": (c_status, [_P(SeriesPtr), CtxPtr, _str]),
    "sinter_series_rows": (c_status, [SeriesPtr, _P(_size)]),
    "sinter_series_get": (c_status, [SeriesPtr, _size, _size, _P(_double)]),
    "sinter_series_write_csv": (c_status, [SeriesPtr, _str]),
    "sinter_series_write_svg": (c_status, [SeriesPtr, _str, _str, _size, _size, _P(_size), _P(_size)]),
    # heat submodels
    "sinter_heat_model_create": (c_status, [_P(HeatModelPtr), CtxPtr, _str]),
    "sinter_heat_model_destroy": (None, [HeatModelPtr]),
    "sinter_heat_model_name": (_str, [HeatModelPtr]),
    "sinter_heat_model_set": (c_status, [HeatModelPtr, _str, _double]),
    "sinter_heat_model_get": (c_status, [HeatModelPtr, _str, _P(_double)]),
    "sinter_heat_model_output": (c_status, [HeatModelPtr, _str, _P(_double)]),
    "sinter_heat_model_set_schedule": (c_status, [HeatModelPtr, _str, _size, _P(_double), _P(_double)]),
    "sinter_heat_model_set_scan_path": (c_status, [HeatModelPtr, _size, _P(_double), _double]),
    "sinter_heat_model_scan_end": (c_status, [HeatModelPtr, _P(_double)]),
    "sinter_scan_hatch": (
        c_status, [CtxPtr, _P(_double), _P(_double), _double, _double, _double, _double,
                   ctypes.c_int, _P(_double), _size, _P(_size)]),
    "sinter_stepper_add_heat": (c_status, [StepperPtr, HeatModelPtr]),
    "sinter_stepper_set_thermal_scheme": (c_status, [StepperPtr, _int]),
    "sinter_stepper_stable_dt_thermal": (c_status, [StepperPtr, _P(_double)]),
    "sinter_stepper_stable_step": (c_status, [StepperPtr, _P(_double)]),
    "sinter_stepper_heat_energy": (c_status, [StepperPtr, _size, _P(_double)]),
    # electric submodels
    "sinter_walls_set_electric": (c_status, [WallsPtr, _size, _int, _double]),
    "sinter_walls_set_electric_schedule": (c_status, [WallsPtr, _size, _size, _P(_double), _P(_double)]),
    "sinter_walls_set_electric_pulse": (c_status, [WallsPtr, _size, _double, _double]),
    "sinter_walls_set_electric_limit": (c_status, [WallsPtr, _size, _double]),
    "sinter_walls_set_thermal": (c_status, [WallsPtr, _size, _int, _double]),
    "sinter_electric_model_create": (c_status, [_P(ElectricModelPtr), CtxPtr, _str]),
    "sinter_electric_model_destroy": (None, [ElectricModelPtr]),
    "sinter_electric_model_name": (_str, [ElectricModelPtr]),
    "sinter_electric_model_set": (c_status, [ElectricModelPtr, _str, _double]),
    "sinter_electric_model_get": (c_status, [ElectricModelPtr, _str, _P(_double)]),
    "sinter_electric_model_power": (c_status, [ElectricModelPtr, _P(_double), _P(_double)]),
    "sinter_stepper_set_electric": (c_status, [StepperPtr, ElectricModelPtr]),
    "sinter_stepper_electric_iterations": (c_status, [StepperPtr, _P(_u64)]),
    # scenes and checkpoints
    "sinter_scene_load": (c_status, [_P(ScenePtr), CtxPtr, _str]),
    "sinter_scene_destroy": (None, [ScenePtr]),
    "sinter_scene_run": (c_status, [ScenePtr, _str, ProgressFn, ctypes.c_void_p]),
    "sinter_scene_get_stepper": (c_status, [ScenePtr, _P(StepperPtr)]),
    "sinter_scene_get_particles": (c_status, [ScenePtr, _P(ParticlesPtr)]),
    "sinter_scene_get_walls": (c_status, [ScenePtr, _P(WallsPtr)]),
    "sinter_scene_end_time": (c_status, [ScenePtr, _P(_double)]),
    "sinter_scene_set_end_time": (c_status, [ScenePtr, _double]),
    "sinter_scene_checkpoint_write": (c_status, [ScenePtr, _str]),
    "sinter_scene_restart": (c_status, [ScenePtr, _str]),
    "sinter_plot_run": (c_status, [CtxPtr, _str, _str]),
    "sinter_plot_csv": (c_status, [CtxPtr, _str, _str, _str, _str, _P(_str), _size]),
    "sinter_scene_check": (c_status, [ScenePtr]),
    "sinter_scene_compact": (c_status, [ScenePtr]),
    "sinter_checkpoint_write": (c_status, [StepperPtr, _str]),
    "sinter_checkpoint_read": (c_status, [StepperPtr, _str]),
    "sinter_stepper_export_size": (c_status, [StepperPtr, _size, _P(_size), _P(_size)]),
    "sinter_stepper_export": (
        c_status, [StepperPtr, _size, _P(_size), ctypes.c_void_p, _size, _P(_size), _int]),
    "sinter_stepper_remove": (c_status, [StepperPtr, _size, _P(_size)]),
    "sinter_stepper_import": (c_status, [StepperPtr, ctypes.c_void_p, _size, _P(_size)]),
    "sinter_stepper_save_global": (c_status, [StepperPtr, ctypes.c_void_p, _size, _P(_size)]),
    "sinter_stepper_load_global": (c_status, [StepperPtr, ctypes.c_void_p, _size]),
    "sinter_stepper_set_furnace": (c_status, [StepperPtr, _size, _P(_double), _P(_double)]),
    "sinter_stepper_set_observer": (c_status, [StepperPtr, ObserverFn, ctypes.c_void_p]),
    "sinter_stepper_advance": (c_status, [StepperPtr, _double]),
    "sinter_stepper_step": (c_status, [StepperPtr, _u64]),
    "sinter_stepper_time": (c_status, [StepperPtr, _P(_double)]),
    "sinter_stepper_get_stats": (c_status, [StepperPtr, _P(StepperStats)]),
    "sinter_stepper_evaluate": (c_status, [StepperPtr]),
    "sinter_stable_dt_hertz": (c_status, [ParticlesPtr, WallsPtr, _double, _P(_double)]),
    "sinter_damping_ratio_from_restitution": (c_status, [_double, _P(_double)]),
    # neck (7DOF) submodel
    "sinter_neck_model_create": (c_status, [_P(NeckModelPtr), CtxPtr]),
    "sinter_neck_model_destroy": (None, [NeckModelPtr]),
    "sinter_neck_model_set": (c_status, [NeckModelPtr, _str, _double]),
    "sinter_neck_model_get": (c_status, [NeckModelPtr, _str, _P(_double)]),
    "sinter_neck_two_particles": (
        c_status, [NeckModelPtr, MaterialPtr, _double, _double, _size, _P(_double), _P(_double),
                   _size, _P(_double), _P(_double), _P(_double), _P(_double)]),
    "sinter_neck_get_stats": (c_status, [NeckModelPtr, _P(NeckStats)]),
    "sinter_neck_sensitivities": (
        c_status, [CtxPtr, NeckModelPtr, MaterialPtr, _double, _double, _size, _P(_double),
                   _P(_double), _size, _P(c_enum), _size, _P(_double), _P(_double), _P(_double),
                   _P(_double), _P(_double)]),
    "sinter_pair_run": (c_status, [CtxPtr, _str, _str, _str]),
    # packing helpers
    "sinter_stepper_sintering_stats": (c_status, [StepperPtr, _P(SinteringStats)]),
    # snapshots
    "sinter_snapshot_create": (c_status, [_P(SnapshotPtr), StepperPtr]),
    "sinter_snapshot_destroy": (None, [SnapshotPtr]),
    "sinter_snapshot_counts": (
        c_status, [SnapshotPtr, _P(_size), _P(_size), _P(_size), _P(_double)]),
    "sinter_snapshot_contacts": (
        c_status, [SnapshotPtr, c_enum, _P(ctypes.c_void_p), _P(_size), _P(_size), _P(c_enum)]),
    "sinter_snapshot_links": (
        c_status, [SnapshotPtr, c_enum, _P(ctypes.c_void_p), _P(_size), _P(_size), _P(c_enum)]),
    # coarse-grained fields
    "sinter_coarse_options_init": (c_status, [_P(CoarseOptions), _size]),
    "sinter_coarse_quantity_info": (c_status, [c_enum, _P(_str), _P(_str), _P(_size)]),
    "sinter_coarse_grain": (
        c_status, [ParticlesPtr, SnapshotPtr, _P(CoarseOptions), c_enum, _P(_double), _size]),
    "sinter_lamina_profile": (
        c_status, [ParticlesPtr, _int, _P(_double), _P(_double), _size, _P(_double),
                   _P(_double)]),
    "sinter_packing_options_init": (c_status, [_P(PackingOptions), _size]),
    "sinter_pack_random": (c_status, [ParticlesPtr, _P(PackingOptions), _size, _P(_size)]),
    "sinter_particles_size_quantiles": (
        c_status, [ParticlesPtr, _size, _size, _int, _size, _P(_double), _P(_double)]),
    "sinter_psd_read_csv": (
        c_status, [CtxPtr, _str, _double, _int, _P(_double), _P(_double), _size, _P(_size)]),
    "sinter_pack_lattice": (
        c_status, [ParticlesPtr, _P(_double), _P(_double), _double, _double, ctypes.c_int32,
                   _double, _P(_size)]),
    "sinter_pack_pour": (c_status, [StepperPtr, _double, _double, _double]),
    "sinter_insertion_options_init": (c_status, [_P(InsertionOptions), _size]),
    "sinter_stepper_set_insertion": (
        c_status, [StepperPtr, _P(PackingOptions), _P(InsertionOptions)]),
    "sinter_stepper_get_insertion": (
        c_status, [StepperPtr, _P(_double), _P(_double), _P(_u64), _P(_u64)]),
    "sinter_stepper_get_insertion_mixture": (
        c_status, [StepperPtr, _P(_double), _size, _P(_size)]),
    "sinter_compaction_options_init": (c_status, [_P(CompactionOptions), _size]),
    "sinter_pack_compact": (
        c_status, [ParticlesPtr, _P(CompactionOptions), _P(CompactionResult)]),
    # sinter_submodel.h: host submodels
    "sinter_force_model_create_host": (
        c_status, [_P(ForceModelPtr), CtxPtr, _str, _P(ForceCallbacks), ctypes.c_void_p]),
    "sinter_heat_model_create_host": (
        c_status, [_P(HeatModelPtr), CtxPtr, _str, _P(HeatCallbacks), ctypes.c_void_p]),
    "sinter_electric_model_set_host": (
        c_status, [ElectricModelPtr, _P(ElectricCallbacks), ctypes.c_void_p]),
    "sinter_electric_model_electrode_heat": (c_status, [ElectricModelPtr, _P(_double)]),
    "sinter_stepper_set_neck_law": (
        c_status, [StepperPtr, _P(NeckLawCallbacks), ctypes.c_void_p]),
    # sinter_domain.h: libsinter on one subdomain of the host's decomposition
    "sinter_particles_set_ghosts": (c_status, [ParticlesPtr, _P(GhostFields)]),
    "sinter_stepper_set_domain_ops": (c_status, [StepperPtr, _P(DomainOps), ctypes.c_void_p]),
    "sinter_stepper_ghost_cutoff": (c_status, [StepperPtr, _P(_double)]),
    "sinter_walls_get_force_local": (c_status, [WallsPtr, _size, _P(_double)]),
    "sinter_stepper_get_stats_global": (c_status, [StepperPtr, _P(StepperStats)]),
    "sinter_stepper_heat_energy_global": (c_status, [StepperPtr, _size, _P(_double)]),
    "sinter_coarse_sums": (
        c_status, [ParticlesPtr, SnapshotPtr, _P(CoarseOptions), _P(_double), _size]),
    "sinter_write_vti_sums": (
        c_status, [CtxPtr, _str, _P(CoarseOptions), _P(_double), _size, _int]),
    "sinter_lamina_sums": (
        c_status, [ParticlesPtr, _int, _P(_double), _P(_double), _size, _P(_double)]),
}


# --- loading -------------------------------------------------------------

def _bundled_library():
    """libsinter.so inside this package: where a wheel (bindings/python/setup.py) puts it."""
    return os.path.join(os.path.dirname(os.path.realpath(__file__)), "libsinter.so")


def _source_tree_library():
    """lib/libsinter.so of the source tree this package sits in (bindings/python/sinter)."""
    package_dir = os.path.dirname(os.path.realpath(__file__))
    return os.path.normpath(os.path.join(package_dir, "..", "..", "..", "lib", "libsinter.so"))


def library_candidates(environ=None):
    """The paths or names tried, in order.

    SINTER_LIBRARY, when set, is the only candidate; otherwise the library
    bundled in the package (an installed wheel), when there is one, then the
    source tree's lib/libsinter.so, then an installed library.
    """
    environ = os.environ if environ is None else environ
    explicit = environ.get("SINTER_LIBRARY")
    if explicit:
        return [explicit]
    candidates = []
    bundled = _bundled_library()
    if os.path.isfile(bundled):
        candidates.append(bundled)
    candidates.append(_source_tree_library())
    installed = ctypes.util.find_library("sinter")
    if installed:
        candidates.append(installed)
    candidates.append("libsinter.so.0")
    return list(dict.fromkeys(candidates))


def declare(cdll):
    """Set restype and argtypes of every function of SIGNATURES that `cdll` defines.

    Return the names it lacks (an older library, or a header ahead of the
    build); calling one of those raises AttributeError.
    """
    missing = []
    for name, (restype, argtypes) in SIGNATURES.items():
        try:
            function = getattr(cdll, name)
        except AttributeError:
            missing.append(name)
            continue
        function.restype = restype
        function.argtypes = argtypes
        setattr(cdll, name, checked_function(name, function))  # OverflowError, not wrapping
    return missing


def load_library(environ=None):
    """Load and declare libsinter; return (cdll, path, missing function names).

    Raises LibraryNotFound, listing every candidate and why it failed.
    """
    tried = []
    for candidate in library_candidates(environ):
        try:
            cdll = ctypes.CDLL(candidate)
        except OSError as error:
            tried.append("%s (%s)" % (candidate, error))
            continue
        if not hasattr(cdll, "sinter_version_number"):
            tried.append("%s (not libsinter: no sinter_version_number)" % candidate)
            continue
        return cdll, candidate, declare(cdll)
    raise LibraryNotFound(
        "cannot load libsinter; tried:\n  " + "\n  ".join(tried)
        + "\nBuild the library or set SINTER_LIBRARY to the path of libsinter.so."
    )


#: The loaded library, its path, and the declared functions it does not define.
lib, library_path, missing_functions = load_library()


def text(value):
    """Decode a const char * result (None stays None)."""
    return None if value is None else value.decode("utf-8", "replace")
