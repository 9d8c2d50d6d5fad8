"""Python bindings of libsinter (DEM simulation of powder sintering), via ctypes.

Units are SI throughout: m, kg, s, K, N, Pa, W, A, V.

    import sinter
    with sinter.Context() as ctx:
        steel = sinter.Material(ctx, "steel", density=7800.0, youngs_modulus=2e11)
        ps = sinter.Particles(ctx)
        ps.set_material(0, steel)
        ps.add([(0.0, 0.0, 0.0), (2e-3, 0.0, 0.0)], [1e-3, 1e-3])
        with ps.view("velocity") as v:   # zero-copy, NumPy if available
            v[0, 0] = 0.1
        with sinter.Stepper(ctx, ps, dt=1e-5,
                            forces=[sinter.ForceModel(ctx, "hertz_mindlin")]) as st:
            st.advance(1e-3)

Library messages go to the "sinter" logger of Python's logging module (Context(logger=...)).
Ctrl-C during Stepper.advance or Scene.run raises KeyboardInterrupt with the last accepted
state kept. A missing input file raises FileNotFoundError.

The shared library is found through SINTER_LIBRARY, the source tree's
lib/libsinter.so, or the system's libsinter.so.0 (see sinter._lib).
"""

from ._errors import (BusyError, FileNotFound, Interrupted, InvalidArgument, NotFound,
                      RangeError, SinterError, Status)
from ._lib import LibraryNotFound, library_path
from ._callbacks import CallbackResult, ContactBatch, ContactKind, NeckLawBatch, StateView
from .fields import CoarseQuantity, coarse_grain, lamina_profile
from .context import LOGGER_NAME, Context, LogLevel, version_number, version_string
from .material import Material, MaterialParam, ParamInfo
from .models import ElectricModel, ForceModel, HeatModel
from .neck import NeckModel, NeckResult, NeckSensitivities, NeckStats
from .output import Series, plot_csv, plot_run, write_pvd, write_vtu
from .packing import (InsertionRegion, RadiusDistribution, compaction_options, pack_compact, pack_lattice,
                      pack_random, packing_options, pour)
from .particles import (FIELDS, DType, Field, FieldInfo, FieldView, ParticleFlag,
                        Particles, Property)
from .scene import Scene
from .stepper import (OPTIONS, SinteringStats, Stepper, StepperKind, StepperStats,
                      ThermalScheme, damping_ratio_from_restitution, stable_dt_hertz)
from .walls import WallElectric, WallKind, WallMotion, WallThermal, Walls
from . import domain  # noqa: E402 (sinter_domain.h: a subdomain of the host's decomposition)

__version__ = version_string()

__all__ = [
    "BusyError", "CallbackResult", "CoarseQuantity", "coarse_grain", "lamina_profile", "ContactBatch", "ContactKind", "Context", "NeckLawBatch", "DType", "Field",
    "MaterialParam", "ParticleFlag", "ElectricModel", "FIELDS", "FieldInfo", "FieldView",
    "FileNotFound", "ForceModel", "HeatModel", "Interrupted", "InvalidArgument", "LOGGER_NAME",
    "LibraryNotFound", "LogLevel", "Material", "NeckModel", "NeckResult",
    "NeckSensitivities", "NeckStats",
    "NotFound", "OPTIONS", "ParamInfo", "Particles", "Property", "RadiusDistribution",
    "InsertionRegion", "RangeError",
    "Scene", "Series", "SinterError", "SinteringStats", "StateView", "Status", "Stepper",
    "StepperKind", "StepperStats", "ThermalScheme", "WallElectric", "WallKind", "WallMotion", "WallThermal", "Walls",
    "compaction_options", "damping_ratio_from_restitution", "library_path", "pack_compact",
    "pack_lattice", "pack_random", "packing_options", "plot_csv", "plot_run", "pour", "stable_dt_hertz",
    "version_number", "version_string", "write_pvd", "write_vtu",
]
