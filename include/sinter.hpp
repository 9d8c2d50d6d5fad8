/*
 * libsinter for C++17: a header-only layer over the C API of sinter.h.
 *
 *  - RAII handles with unique ownership and move semantics: sinter::context, material,
 *    particles, walls, force_model, heat_model, electric_model, neck_model, stepper, scene,
 *    series. Each destroys its C object when it goes out of scope; get() gives the C handle
 *    for any function this header does not wrap. The C API's lifetime rules still hold: a
 *    context outlives everything made from it, and particles, walls and models outlive the
 *    steppers that borrow them, so declare the context first and the stepper last.
 *  - Every failing call throws sinter::error, which carries the status (sinter::status) and
 *    the context's detail text (sinter_last_error) at the time of the failure.
 *  - Scoped enums (enum class) mirror the C enums, with the C values.
 *  - Field arrays are borrowed as sinter::field_view (the view is released by its
 *    destructor), whose values() is a sinter::span: a pointer and a length, as std::span of
 *    C++20.
 *
 * The header needs C++17 and the C library (link with -lsinter, or libsinter::sinter in CMake).
 * It adds no symbol to the library and no declaration to sinter.h.
 */
#ifndef SINTER_HPP
#define SINTER_HPP

#if defined(_MSVC_LANG) ? _MSVC_LANG < 201703L : __cplusplus < 201703L
#error "sinter.hpp needs C++17 (-std=c++17); the C API is in sinter.h"
#endif

#include <array>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <functional>
#include <initializer_list>
#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "sinter.h"
#include "sinter_domain.h"

/** @brief C++17 layer of libsinter (include/sinter.hpp). */
namespace sinter {

// ---------------------------------------------------------------------------------------------
// Enums: the C values under scoped names (a trailing _ where the name is a C++ keyword)
// ---------------------------------------------------------------------------------------------

/// Mirrors sinter_status (SINTER_STATUS_LIST): 0 success, negative errors.
enum class status : int {
    ok = SINTER_OK,
    null = SINTER_ERR_NULL,
    invalid = SINTER_ERR_INVALID,
    nomem = SINTER_ERR_NOMEM,
    struct_size = SINTER_ERR_STRUCT_SIZE,
    busy = SINTER_ERR_BUSY,
    range = SINTER_ERR_RANGE,
    not_found = SINTER_ERR_NOT_FOUND,
    overflow = SINTER_ERR_OVERFLOW,
    state = SINTER_ERR_STATE,
    io = SINTER_ERR_IO,
    parse = SINTER_ERR_PARSE,
    corrupt = SINTER_ERR_CORRUPT,
    unstable = SINTER_ERR_UNSTABLE,
    not_converged = SINTER_ERR_NOT_CONVERGED,
    callback = SINTER_ERR_CALLBACK,
    unsupported = SINTER_ERR_UNSUPPORTED,
    lost_particle = SINTER_ERR_LOST_PARTICLE,
    domain = SINTER_ERR_DOMAIN,
    interrupted = SINTER_ERR_INTERRUPTED,
};

/// Mirrors sinter_log_level.
enum class log_level : int {
    error = SINTER_LOG_ERROR,
    warning = SINTER_LOG_WARNING,
    info = SINTER_LOG_INFO,
    debug = SINTER_LOG_DEBUG,
};
/// Mirrors sinter_material_param.
enum class material_param : int {
    density = SINTER_MAT_DENSITY,
    youngs_modulus = SINTER_MAT_YOUNGS_MODULUS,
    poisson_ratio = SINTER_MAT_POISSON_RATIO,
    damping_ratio = SINTER_MAT_DAMPING_RATIO,
    friction_static = SINTER_MAT_FRICTION_STATIC,
    friction_dynamic = SINTER_MAT_FRICTION_DYNAMIC,
    friction_damping_ratio = SINTER_MAT_FRICTION_DAMPING_RATIO,
    rolling_friction = SINTER_MAT_ROLLING_FRICTION,
    rolling_damping_ratio = SINTER_MAT_ROLLING_DAMPING_RATIO,
    contact_stiffness = SINTER_MAT_CONTACT_STIFFNESS,
    contact_exponent = SINTER_MAT_CONTACT_EXPONENT,
    wall_stiffness = SINTER_MAT_WALL_STIFFNESS,
    wall_exponent = SINTER_MAT_WALL_EXPONENT,
    bond_stiffness = SINTER_MAT_BOND_STIFFNESS,
    bond_exponent = SINTER_MAT_BOND_EXPONENT,
    bond_critical_strain = SINTER_MAT_BOND_CRITICAL_STRAIN,
    drag_coefficient = SINTER_MAT_DRAG_COEFFICIENT,
    thermal_conductivity = SINTER_MAT_THERMAL_CONDUCTIVITY,
    heat_capacity = SINTER_MAT_HEAT_CAPACITY,
    emissivity = SINTER_MAT_EMISSIVITY,
    absorptance = SINTER_MAT_ABSORPTANCE,
    softening_law = SINTER_MAT_SOFTENING_LAW,
    softening_temperature = SINTER_MAT_SOFTENING_TEMPERATURE,
    softening_rate = SINTER_MAT_SOFTENING_RATE,
    softening_floor = SINTER_MAT_SOFTENING_FLOOR,
    electric_conductivity = SINTER_MAT_ELECTRIC_CONDUCTIVITY,
    atomic_volume = SINTER_MAT_ATOMIC_VOLUME,
    surface_energy = SINTER_MAT_SURFACE_ENERGY,
    grain_boundary_energy = SINTER_MAT_GRAIN_BOUNDARY_ENERGY,
    surface_thickness = SINTER_MAT_SURFACE_THICKNESS,
    grain_boundary_thickness = SINTER_MAT_GRAIN_BOUNDARY_THICKNESS,
    lattice_diffusion_prefactor = SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR,
    lattice_activation_energy = SINTER_MAT_LATTICE_ACTIVATION_ENERGY,
    surface_diffusion_prefactor = SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR,
    surface_activation_energy = SINTER_MAT_SURFACE_ACTIVATION_ENERGY,
    grain_boundary_diffusion_prefactor = SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR,
    grain_boundary_activation_energy = SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY,
    surface_mobile_fraction = SINTER_MAT_SURFACE_MOBILE_FRACTION,
    grain_boundary_mobile_fraction = SINTER_MAT_GRAIN_BOUNDARY_MOBILE_FRACTION,
    atomic_volume_hot = SINTER_MAT_ATOMIC_VOLUME_HOT,
    surface_energy_hot = SINTER_MAT_SURFACE_ENERGY_HOT,
    grain_boundary_energy_hot = SINTER_MAT_GRAIN_BOUNDARY_ENERGY_HOT,
    surface_thickness_hot = SINTER_MAT_SURFACE_THICKNESS_HOT,
    grain_boundary_thickness_hot = SINTER_MAT_GRAIN_BOUNDARY_THICKNESS_HOT,
    lattice_diffusion_prefactor_hot = SINTER_MAT_LATTICE_DIFFUSION_PREFACTOR_HOT,
    lattice_activation_energy_hot = SINTER_MAT_LATTICE_ACTIVATION_ENERGY_HOT,
    surface_diffusion_prefactor_hot = SINTER_MAT_SURFACE_DIFFUSION_PREFACTOR_HOT,
    surface_activation_energy_hot = SINTER_MAT_SURFACE_ACTIVATION_ENERGY_HOT,
    grain_boundary_diffusion_prefactor_hot = SINTER_MAT_GRAIN_BOUNDARY_DIFFUSION_PREFACTOR_HOT,
    grain_boundary_activation_energy_hot = SINTER_MAT_GRAIN_BOUNDARY_ACTIVATION_ENERGY_HOT,
    surface_mobile_fraction_hot = SINTER_MAT_SURFACE_MOBILE_FRACTION_HOT,
    grain_boundary_mobile_fraction_hot = SINTER_MAT_GRAIN_BOUNDARY_MOBILE_FRACTION_HOT,
    melting_temperature = SINTER_MAT_MELTING_TEMPERATURE,
    latent_heat = SINTER_MAT_LATENT_HEAT,
    melting_range = SINTER_MAT_MELTING_RANGE,
    melting_stop = SINTER_MAT_MELTING_STOP,
    neck_boundary_path = SINTER_MAT_NECK_BOUNDARY_PATH,
    neck_cone_path = SINTER_MAT_NECK_CONE_PATH,
    neck_cap_path = SINTER_MAT_NECK_CAP_PATH,
    lattice_mobile_fraction = SINTER_MAT_LATTICE_MOBILE_FRACTION,
    phase_transition_temperature = SINTER_MAT_PHASE_TRANSITION_TEMPERATURE,
};
/// Mirrors sinter_property.
enum class property : int {
    thermal_conductivity = SINTER_PROPERTY_THERMAL_CONDUCTIVITY,
    heat_capacity = SINTER_PROPERTY_HEAT_CAPACITY,
    electric_conductivity = SINTER_PROPERTY_ELECTRIC_CONDUCTIVITY,
};
/// Mirrors sinter_field.
enum class field : int {
    position = SINTER_FIELD_POSITION,
    velocity = SINTER_FIELD_VELOCITY,
    spin = SINTER_FIELD_SPIN,
    rotation = SINTER_FIELD_ROTATION,
    radius = SINTER_FIELD_RADIUS,
    mass = SINTER_FIELD_MASS,
    inertia = SINTER_FIELD_INERTIA,
    temperature = SINTER_FIELD_TEMPERATURE,
    current = SINTER_FIELD_CURRENT,
    force = SINTER_FIELD_FORCE,
    torque = SINTER_FIELD_TORQUE,
    heat = SINTER_FIELD_HEAT,
    material = SINTER_FIELD_MATERIAL,
    flags = SINTER_FIELD_FLAGS,
    id = SINTER_FIELD_ID,
};
/// Mirrors sinter_dtype.
enum class dtype : int {
    double_ = SINTER_DTYPE_DOUBLE, ///< (trailing _: double is a keyword)
    int32 = SINTER_DTYPE_INT32,
    uint32 = SINTER_DTYPE_UINT32,
    uint64 = SINTER_DTYPE_UINT64,
};
/// Mirrors sinter_particle_flag.
enum class particle_flag : std::uint32_t {
    fixed = SINTER_PARTICLE_FIXED,
    no_rotation = SINTER_PARTICLE_NO_ROTATION,
    fixed_temperature = SINTER_PARTICLE_FIXED_TEMPERATURE,
    electrified = SINTER_PARTICLE_ELECTRIFIED,
    lit = SINTER_PARTICLE_LIT,
};
/// Mirrors sinter_wall_motion.
enum class wall_motion : int {
    fixed = SINTER_WALL_FIXED,
    velocity = SINTER_WALL_VELOCITY,
    schedule = SINTER_WALL_SCHEDULE,
    sine = SINTER_WALL_SINE,
    callback = SINTER_WALL_CALLBACK,
};
/// Mirrors sinter_wall_kind.
enum class wall_kind : int {
    plane = SINTER_WALL_PLANE,
    rectangle = SINTER_WALL_RECTANGLE,
    disc = SINTER_WALL_DISC,
    cylinder = SINTER_WALL_CYLINDER,
    mesh = SINTER_WALL_MESH,
};
/// Mirrors sinter_stepper_kind.
enum class stepper_kind : int {
    explicit_ = SINTER_STEPPER_EXPLICIT, ///< (trailing _: explicit is a keyword)
    staggered = SINTER_STEPPER_STAGGERED,
    quasistatic = SINTER_STEPPER_QUASISTATIC,
};
/// Mirrors sinter_thermal_scheme.
enum class thermal_scheme : int {
    explicit_ = SINTER_THERMAL_EXPLICIT, ///< (trailing _: explicit is a keyword)
    implicit = SINTER_THERMAL_IMPLICIT,
};
/// Mirrors sinter_wall_electric_mode.
enum class wall_electric_mode : int {
    neutral = SINTER_WALL_NEUTRAL,
    current = SINTER_WALL_CURRENT,
    potential = SINTER_WALL_POTENTIAL,
};
/// Mirrors sinter_wall_thermal_mode.
enum class wall_thermal_mode : int {
    reservoir = SINTER_WALL_RESERVOIR,
    adiabatic = SINTER_WALL_ADIABATIC,
    resistance = SINTER_WALL_RESISTANCE,
    transfer = SINTER_WALL_TRANSFER,
    imposed = SINTER_WALL_IMPOSED,
};
/// Mirrors sinter_radius_distribution.
enum class radius_distribution : int {
    monodisperse = SINTER_RADII_MONODISPERSE,
    uniform = SINTER_RADII_UNIFORM,
    normal = SINTER_RADII_NORMAL,
    lognormal = SINTER_RADII_LOGNORMAL,
    table = SINTER_RADII_TABLE,
};
/// Mirrors sinter_size_basis.
enum class size_basis : int {
    number = SINTER_SIZE_BY_NUMBER,
    volume = SINTER_SIZE_BY_VOLUME,
};
/// Mirrors sinter_insertion_region.
enum class insertion_region : int {
    box = SINTER_INSERT_BOX,
    cylinder = SINTER_INSERT_CYLINDER,
};
/// Mirrors sinter_contact_data (the per-contact arrays of a snapshot).
enum class contact_data : int {
    id_a = SINTER_CONTACT_DATA_ID_A,
    id_b = SINTER_CONTACT_DATA_ID_B,
    wall = SINTER_CONTACT_DATA_WALL,
    normal = SINTER_CONTACT_DATA_NORMAL,
    overlap = SINTER_CONTACT_DATA_OVERLAP,
    radius = SINTER_CONTACT_DATA_RADIUS,
    area = SINTER_CONTACT_DATA_AREA,
    normal_force = SINTER_CONTACT_DATA_NORMAL_FORCE,
    tangential_force = SINTER_CONTACT_DATA_TANGENTIAL_FORCE,
    heat_flow = SINTER_CONTACT_DATA_HEAT_FLOW,
    current = SINTER_CONTACT_DATA_CURRENT,
};
/// Mirrors sinter_link_data (the per-link arrays of a snapshot, quasi-static stepper).
enum class link_data : int {
    id_a = SINTER_LINK_DATA_ID_A,
    id_b = SINTER_LINK_DATA_ID_B,
    neck_radius = SINTER_LINK_DATA_NECK_RADIUS,
    neck_ratio = SINTER_LINK_DATA_NECK_RATIO,
    approach = SINTER_LINK_DATA_APPROACH,
    age = SINTER_LINK_DATA_AGE,
    phase = SINTER_LINK_DATA_PHASE,
    sintering_force = SINTER_LINK_DATA_SINTERING_FORCE,
    beam_force = SINTER_LINK_DATA_BEAM_FORCE,
    beam_moment = SINTER_LINK_DATA_BEAM_MOMENT,
    correction = SINTER_LINK_DATA_CORRECTION,
};
/// Mirrors sinter_coarse_quantity (the coarse-grained fields of sinter_coarse_grain).
enum class coarse_quantity : int {
    solid_fraction = SINTER_COARSE_SOLID_FRACTION,
    density = SINTER_COARSE_DENSITY,
    temperature = SINTER_COARSE_TEMPERATURE,
    velocity = SINTER_COARSE_VELOCITY,
    stress = SINTER_COARSE_STRESS,
};
/// Mirrors sinter_reduce_op (sinter_domain.h: the host's reductions).
enum class reduce_op : int {
    sum = SINTER_REDUCE_SUM,
    min = SINTER_REDUCE_MIN,
    max = SINTER_REDUCE_MAX,
};
/// Mirrors sinter_reduce_type (double, int64_t, uint64_t).
enum class reduce_type : int {
    f64 = SINTER_REDUCE_F64,
    i64 = SINTER_REDUCE_I64,
    u64 = SINTER_REDUCE_U64,
};
/// Mirrors sinter_halo_dir (sinter_domain.h: the host's exchanges of rows).
enum class halo_dir : int {
    forward = SINTER_HALO_FORWARD,
    reverse = SINTER_HALO_REVERSE,
};

/// Combine particle flags (sinter_particle_flag bits).
constexpr particle_flag operator|(particle_flag a, particle_flag b) noexcept
{
    return static_cast<particle_flag>(static_cast<std::uint32_t>(a) | static_cast<std::uint32_t>(b));
}
/// Intersect particle flags.
constexpr particle_flag operator&(particle_flag a, particle_flag b) noexcept
{
    return static_cast<particle_flag>(static_cast<std::uint32_t>(a) & static_cast<std::uint32_t>(b));
}

/// The name of a status constant ("SINTER_ERR_INVALID").
inline const char *status_name(status s) noexcept { return sinter_status_name(static_cast<int>(s)); }
/// The English text of a status ("an argument has an invalid value").
inline const char *status_string(status s) noexcept
{
    return sinter_status_string(static_cast<int>(s));
}
/// The library's version, "major.minor.patch" (of the library loaded, not of the header).
inline const char *version_string() noexcept { return sinter_version_string(); }
/// The library's version as major*10000 + minor*100 + patch.
inline unsigned version_number() noexcept { return sinter_version_number(); }

// ---------------------------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------------------------

/// A failing call: its status, the context's detail text and the C function's name.
class error : public std::runtime_error {
  public:
    error(status code, std::string message, std::string function)
        : std::runtime_error(function + ": " + message + " [" + status_name(code) + "]"),
          code_(code), message_(std::move(message)), function_(std::move(function))
    {
    }
    /// The status the C function returned.
    status code() const noexcept { return code_; }
    /// sinter_last_error of the context at the failure (the status's text without a context).
    const std::string &message() const noexcept { return message_; }
    /// The C function that failed ("sinter_particles_add").
    const std::string &function() const noexcept { return function_; }

  private:
    status code_;
    std::string message_;
    std::string function_;
};

namespace detail {

/// Throw sinter::error for a failing status, with the context's detail when it has one.
inline void check(sinter_status st, const sinter_ctx *ctx, const char *function)
{
    if (st == SINTER_OK)
        return;
    std::string message;
    if (ctx != nullptr && sinter_last_status(ctx) == st)
        message = sinter_last_error(ctx);
    if (message.empty())
        message = sinter_status_string(st);
    throw error(static_cast<status>(st), std::move(message), function);
}

template <typename T, void (*Destroy)(T *)> struct deleter {
    void operator()(T *p) const noexcept { Destroy(p); }
};

/// Unique ownership of a C object and the context its errors are reported on.
template <typename T, void (*Destroy)(T *)> class handle {
  public:
    using c_type = T;
    handle() noexcept = default;
    handle(T *owned, sinter_ctx *ctx) noexcept : ptr_(owned), ctx_(ctx) {}
    handle(handle &&other) noexcept : ptr_(std::move(other.ptr_)), ctx_(other.ctx_)
    {
        other.ctx_ = nullptr;
    }
    handle &operator=(handle &&other) noexcept
    {
        ptr_ = std::move(other.ptr_);
        ctx_ = other.ctx_;
        other.ctx_ = nullptr;
        return *this;
    }
    handle(const handle &) = delete;
    handle &operator=(const handle &) = delete;
    ~handle() = default;

    /// The C handle (still owned here), for the functions this header does not wrap.
    T *get() const noexcept { return ptr_.get(); }
    /// Give up ownership: the caller destroys the C object.
    T *release() noexcept
    {
        ctx_ = nullptr;
        return ptr_.release();
    }
    /// Destroy the C object now (as the destructor does).
    void reset() noexcept
    {
        ptr_.reset();
        ctx_ = nullptr;
    }
    explicit operator bool() const noexcept { return static_cast<bool>(ptr_); }
    /// The context errors are reported on.
    sinter_ctx *context_handle() const noexcept { return ctx_; }

  protected:
    void check(sinter_status st, const char *function) const { detail::check(st, ctx_, function); }
    /// A handle that does not hold an object refuses calls (instead of passing NULL on).
    T *live(const char *function) const
    {
        if (!ptr_)
            throw error(status::null, "the object was moved from or released", function);
        return ptr_.get();
    }

  private:
    std::unique_ptr<T, deleter<T, Destroy>> ptr_;
    sinter_ctx *ctx_ = nullptr;
};

template <typename T> struct field_type;
template <> struct field_type<double> { static constexpr dtype value = dtype::double_; };
template <> struct field_type<std::int32_t> { static constexpr dtype value = dtype::int32; };
template <> struct field_type<std::uint32_t> { static constexpr dtype value = dtype::uint32; };
template <> struct field_type<std::uint64_t> { static constexpr dtype value = dtype::uint64; };

} // namespace detail

// ---------------------------------------------------------------------------------------------
// span: a pointer and a length (std::span is C++20)
// ---------------------------------------------------------------------------------------------

/// A non-owning view of `size()` contiguous elements, as std::span<T> of C++20.
template <typename T> class span {
  public:
    using element_type = T;
    using value_type = std::remove_cv_t<T>;
    using size_type = std::size_t;
    using pointer = T *;
    using reference = T &;
    using iterator = T *;

    constexpr span() noexcept = default;
    constexpr span(T *data, std::size_t size) noexcept : data_(data), size_(size) {}
    template <typename U, std::size_t N,
              typename = std::enable_if_t<std::is_convertible_v<U (*)[], T (*)[]>>>
    constexpr span(U (&array)[N]) noexcept : data_(array), size_(N)
    {
    }
    /// From a braced list, for read-only spans (the list lives to the end of the full
    /// expression: pass it to a function, do not keep the span).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Winit-list-lifetime" // the lifetime is the documented contract
#endif
    template <typename U = T, typename = std::enable_if_t<std::is_const_v<U>>>
    constexpr span(std::initializer_list<value_type> list) noexcept
        : data_(list.begin()), size_(list.size())
    {
    }
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
    /// From a container with data() and size() (std::vector, std::array, std::string, span).
    template <typename Container,
              typename = std::enable_if_t<
                  !std::is_array_v<std::remove_reference_t<Container>> &&
                  std::is_convertible_v<decltype(std::declval<Container &>().data()), T *>>>
    constexpr span(Container &&c) noexcept : data_(c.data()), size_(c.size())
    {
    }

    constexpr T *data() const noexcept { return data_; }
    constexpr std::size_t size() const noexcept { return size_; }
    constexpr bool empty() const noexcept { return size_ == 0; }
    constexpr T &operator[](std::size_t i) const noexcept { return data_[i]; }
    constexpr T *begin() const noexcept { return data_; }
    constexpr T *end() const noexcept { return data_ + size_; }
    constexpr T &front() const noexcept { return data_[0]; }
    constexpr T &back() const noexcept { return data_[size_ - 1]; }
    /// Elements [offset, offset + count).
    constexpr span subspan(std::size_t offset, std::size_t count) const noexcept
    {
        return span(data_ + offset, count);
    }

  private:
    T *data_ = nullptr;
    std::size_t size_ = 0;
};

/// Three components (a point, a vector) [SI units].
using vec3 = std::array<double, 3>;

// ---------------------------------------------------------------------------------------------
// Context
// ---------------------------------------------------------------------------------------------

/// Owns a sinter_ctx: the allocator, the last error and the log callback.
class context : public detail::handle<sinter_ctx, sinter_ctx_destroy> {
  public:
    /// A context with the C library's allocator.
    context() : context(nullptr) {}
    /// A context with a custom allocator (copied; NULL for the C library's).
    explicit context(const sinter_allocator *allocator)
    {
        sinter_ctx *raw = nullptr;
        detail::check(sinter_ctx_create(&raw, allocator), nullptr, "sinter_ctx_create");
        static_cast<handle &>(*this) = handle(raw, raw);
    }
    /// sinter_last_error: the detail of the last error ("" if none).
    std::string last_error() const { return sinter_last_error(get()); }
    /// sinter_last_status: the status of the last error (status::ok if none).
    status last_status() const noexcept { return static_cast<status>(sinter_last_status(get())); }
    /// Forget the last error.
    void clear_error() { check(sinter_clear_error(live("sinter_clear_error")), "sinter_clear_error"); }
    /// Threads the library may use (0: all OpenMP offers).
    void set_threads(int n)
    {
        check(sinter_ctx_set_threads(live("sinter_ctx_set_threads"), n),
              "sinter_ctx_set_threads");
    }
    int threads() const
    {
        int n = 0;
        check(sinter_ctx_get_threads(live("sinter_ctx_get_threads"), &n), "sinter_ctx_get_threads");
        return n;
    }
    /// Install a log callback (sinter_ctx_set_log; nullptr removes it).
    void set_log(sinter_log_fn fn, log_level max_level, void *user = nullptr)
    {
        check(sinter_ctx_set_log(live("sinter_ctx_set_log"), fn, static_cast<int>(max_level), user),
              "sinter_ctx_set_log");
    }
    /// Ask the runs of this context to stop between two steps (async-signal-safe in C).
    void request_stop() noexcept { (void)sinter_ctx_request_stop(get()); }
};

// ---------------------------------------------------------------------------------------------
// Materials
// ---------------------------------------------------------------------------------------------

/// A named set of material parameters (sinter_material).
class material : public detail::handle<sinter_material, sinter_material_destroy> {
  public:
    using handle::get; // get(): the C handle; get(param): a parameter
    material() noexcept = default;
    /// Every parameter at its default; `name` is copied.
    explicit material(const context &ctx, const char *name = nullptr)
    {
        sinter_material *raw = nullptr;
        detail::check(sinter_material_create(&raw, ctx.get(), name), ctx.get(),
                      "sinter_material_create");
        static_cast<handle &>(*this) = handle(raw, ctx.get());
    }
    /// Set one parameter (refused outside its documented range).
    material &set(material_param p, double value)
    {
        check(sinter_material_set(live("sinter_material_set"),
                                  static_cast<sinter_material_param>(p), value),
              "sinter_material_set");
        return *this;
    }
    double get(material_param p) const
    {
        double v = 0;
        check(sinter_material_get(live("sinter_material_get"),
                                  static_cast<sinter_material_param>(p), &v),
              "sinter_material_get");
        return v;
    }
    std::string name() const { return sinter_material_name(live("sinter_material_name")); }
    /// A copy (name and every parameter).
    material clone() const
    {
        sinter_material *raw = nullptr;
        check(sinter_material_clone(&raw, live("sinter_material_clone")), "sinter_material_clone");
        material m;
        static_cast<handle &>(m) = handle(raw, context_handle());
        return m;
    }
};

// ---------------------------------------------------------------------------------------------
// Particles
// ---------------------------------------------------------------------------------------------

/**
 * One field of a particle set, borrowed (sinter_particles_view or _view_read) until this
 * object is destroyed: the set cannot be resized and steppers refuse to step meanwhile.
 * T is the field's element type (double, std::int32_t, std::uint32_t, std::uint64_t; const
 * for a read-only view).
 */
template <typename T> class field_view {
  public:
    /// The view moves; `other` is left empty (values() is empty, nothing to release).
    field_view(field_view &&other) noexcept
        : ps_(std::exchange(other.ps_, nullptr)), field_(other.field_),
          data_(std::exchange(other.data_, nullptr)), count_(std::exchange(other.count_, 0)),
          components_(std::exchange(other.components_, 0))
    {
    }
    field_view &operator=(field_view &&other) noexcept
    {
        if (this != &other) {
            release();
            ps_ = std::exchange(other.ps_, nullptr);
            field_ = other.field_;
            data_ = std::exchange(other.data_, nullptr);
            count_ = std::exchange(other.count_, 0);
            components_ = std::exchange(other.components_, 0);
        }
        return *this;
    }
    field_view(const field_view &) = delete;
    field_view &operator=(const field_view &) = delete;
    ~field_view() { release(); }

    /// Every value, particle-major (x0, y0, z0, x1, ...): count() * components() elements.
    span<T> values() const noexcept { return span<T>(data_, count_ * components_); }
    /// The components of particle i.
    span<T> operator[](std::size_t i) const noexcept
    {
        return span<T>(data_ + i * components_, components_);
    }
    /// Component c of particle i.
    T &operator()(std::size_t i, std::size_t c = 0) const noexcept
    {
        return data_[i * components_ + c];
    }
    std::size_t count() const noexcept { return count_; }
    std::size_t components() const noexcept { return components_; }
    sinter::field field() const noexcept { return field_; }
    /// Give the view back now (as the destructor does).
    void release() noexcept
    {
        if (ps_ != nullptr)
            (void)sinter_particles_release(ps_, static_cast<sinter_field>(field_));
        ps_ = nullptr;
        data_ = nullptr;
        count_ = components_ = 0;
    }

  private:
    friend class particles;
    field_view(const sinter_particles *ps, sinter::field f, T *values, std::size_t n,
               std::size_t per_particle) noexcept
        : ps_(ps), field_(f), data_(values), count_(n), components_(per_particle)
    {
    }
    const sinter_particles *ps_;
    sinter::field field_;
    T *data_;
    std::size_t count_, components_;
};

/// A particle set (sinter_particles), structure of arrays.
class particles : public detail::handle<sinter_particles, sinter_particles_destroy> {
  public:
    particles() noexcept = default;
    explicit particles(const context &ctx)
    {
        sinter_particles *raw = nullptr;
        detail::check(sinter_particles_create(&raw, ctx.get()), ctx.get(),
                      "sinter_particles_create");
        static_cast<handle &>(*this) = handle(raw, ctx.get());
    }
    std::size_t size() const
    {
        std::size_t n = 0;
        check(sinter_particles_count(live("sinter_particles_count"), &n), "sinter_particles_count");
        return n;
    }
    /// The owned particles: the first owned(); the rest are images a periodic stepper made.
    std::size_t owned() const
    {
        std::size_t n = 0;
        check(sinter_particles_owned_count(live("sinter_particles_owned_count"), &n),
              "sinter_particles_owned_count");
        return n;
    }
    std::size_t capacity() const
    {
        std::size_t n = 0;
        check(sinter_particles_capacity(live("sinter_particles_capacity"), &n),
              "sinter_particles_capacity");
        return n;
    }
    void reserve(std::size_t n)
    {
        check(sinter_particles_reserve(live("sinter_particles_reserve"), n),
              "sinter_particles_reserve");
    }
    /// Register (or replace) material `id` (0-255) with a copy of `m`.
    void set_material(std::int32_t id, const material &m)
    {
        check(sinter_particles_set_material(live("sinter_particles_set_material"), id, m.get()),
              "sinter_particles_set_material");
    }
    /**
     * Tabulate property `p` of material `id` against temperature (sinter_particles_set_property_table):
     * values at temperatures [K], linear between points, clamped outside; empty spans remove it.
     * A size mismatch is refused (status::invalid) before the library is called.
     */
    void set_property_table(std::int32_t id, property p, span<const double> temperatures,
                            span<const double> values)
    {
        if (temperatures.size() != values.size())
            throw error(status::invalid, "temperatures and values differ in size",
                        "sinter_particles_set_property_table");
        check(sinter_particles_set_property_table(
                  live("sinter_particles_set_property_table"), id, static_cast<sinter_property>(p),
                  values.size(), temperatures.data(), values.data()),
              "sinter_particles_set_property_table");
    }
    /// Value of property `p` of material `id` at temperature theta [K].
    double property_at(std::int32_t id, property p, double theta) const
    {
        double v = 0.0;
        check(sinter_particles_property(live("sinter_particles_property"), id,
                                        static_cast<sinter_property>(p), theta, &v),
              "sinter_particles_property");
        return v;
    }
    /// Specific enthalpy [J/kg] of material `id` at theta [K] (latent heat included).
    double specific_enthalpy(std::int32_t id, double theta) const
    {
        double h = 0.0;
        check(sinter_particles_specific_enthalpy(live("sinter_particles_specific_enthalpy"), id,
                                                 theta, &h),
              "sinter_particles_specific_enthalpy");
        return h;
    }
    /**
     * Append radii.size() particles of material `material_id` at `positions` (3 per particle,
     * [m]) with `radii` [m] at `temperature` [K]; returns the index of the first. A size
     * mismatch is refused (status::invalid) before the library is called.
     */
    std::size_t add(span<const double> positions, span<const double> radii,
                    std::int32_t material_id, double temperature)
    {
        if (positions.size() != 3 * radii.size())
            throw error(status::invalid,
                        std::to_string(positions.size()) + " position values for " +
                            std::to_string(radii.size()) + " radii (3 per particle expected)",
                        "sinter_particles_add");
        std::size_t first = 0;
        check(sinter_particles_add(live("sinter_particles_add"), radii.size(), positions.data(),
                                   radii.data(), material_id, temperature, &first),
              "sinter_particles_add");
        return first;
    }
    /**
     * add() with persistent ids chosen by the caller (ids.size() == radii.size(); unique in the
     * set, not 2^64 - 1): sinter_particles_add_with_ids. Returns the index of the first.
     */
    std::size_t add_with_ids(span<const std::uint64_t> ids, span<const double> positions,
                             span<const double> radii, std::int32_t material_id,
                             double temperature)
    {
        if (positions.size() != 3 * radii.size() || ids.size() != radii.size())
            throw error(status::invalid,
                        std::to_string(ids.size()) + " ids and " +
                            std::to_string(positions.size()) + " position values for " +
                            std::to_string(radii.size()) + " radii (1 and 3 per particle expected)",
                        "sinter_particles_add_with_ids");
        std::size_t first = 0;
        check(sinter_particles_add_with_ids(live("sinter_particles_add_with_ids"), radii.size(),
                                            ids.data(), positions.data(), radii.data(),
                                            material_id, temperature, &first),
              "sinter_particles_add_with_ids");
        return first;
    }
    /// Remove the particles at these indices (each once, any order).
    void remove(span<const std::size_t> indices)
    {
        check(sinter_particles_remove(live("sinter_particles_remove"), indices.size(),
                                      indices.data()),
              "sinter_particles_remove");
    }
    /// Borrow a field for reading and writing; T must be the field's element type.
    template <typename T = double> field_view<T> view(sinter::field f)
    {
        static_assert(!std::is_const_v<T>, "view_read gives read-only views");
        check_type<T>(f, "sinter_particles_view");
        void *data = nullptr;
        std::size_t count = 0, components = 0;
        check(sinter_particles_view(live("sinter_particles_view"), static_cast<sinter_field>(f),
                                    &data, &count, &components),
              "sinter_particles_view");
        return field_view<T>(get(), f, static_cast<T *>(data), count, components);
    }
    /// Borrow a field for reading only.
    template <typename T = double> field_view<const T> view_read(sinter::field f) const
    {
        check_type<T>(f, "sinter_particles_view_read");
        const void *data = nullptr;
        std::size_t count = 0, components = 0;
        check(sinter_particles_view_read(live("sinter_particles_view_read"),
                                         static_cast<sinter_field>(f), &data, &count, &components),
              "sinter_particles_view_read");
        return field_view<const T>(get(), f, static_cast<const T *>(data), count, components);
    }
    /// A copy of a field's values, particle-major.
    template <typename T = double> std::vector<T> copy(sinter::field f) const
    {
        const field_view<const T> v = view_read<T>(f);
        return std::vector<T>(v.values().begin(), v.values().end());
    }
    /// Check every value of every particle (throws naming the first bad particle).
    void validate() const
    {
        check(sinter_particles_validate(live("sinter_particles_validate"), nullptr),
              "sinter_particles_validate");
    }
    /// The index of the particle with persistent id `id`.
    std::size_t find_id(std::uint64_t id) const
    {
        std::size_t index = 0;
        check(sinter_particles_find_id(live("sinter_particles_find_id"), id, &index),
              "sinter_particles_find_id");
        return index;
    }
    /// Reorder the particles in memory by position (sinter_particles_sort_spatial).
    void sort_spatial()
    {
        check(sinter_particles_sort_spatial(live("sinter_particles_sort_spatial")),
              "sinter_particles_sort_spatial");
    }

  private:
    template <typename T> void check_type(sinter::field f, const char *function) const
    {
        const char *name = nullptr, *unit = nullptr;
        sinter_dtype dt = SINTER_DTYPE_DOUBLE;
        std::size_t components = 0;
        detail::check(sinter_field_info(static_cast<sinter_field>(f), &name, &unit, &dt,
                                        &components),
                      nullptr, function);
        if (static_cast<dtype>(dt) != detail::field_type<std::remove_cv_t<T>>::value)
            throw error(status::invalid, "the element type does not match the field's", function);
    }
};

// ---------------------------------------------------------------------------------------------
// Walls
// ---------------------------------------------------------------------------------------------

/// A set of planar walls (sinter_walls).
class walls : public detail::handle<sinter_walls, sinter_walls_destroy> {
  public:
    walls() noexcept = default;
    explicit walls(const context &ctx)
    {
        sinter_walls *raw = nullptr;
        detail::check(sinter_walls_create(&raw, ctx.get()), ctx.get(), "sinter_walls_create");
        static_cast<handle &>(*this) = handle(raw, ctx.get());
    }
    std::size_t size() const
    {
        std::size_t n = 0;
        check(sinter_walls_count(live("sinter_walls_count"), &n), "sinter_walls_count");
        return n;
    }
    /// A fixed plane through `point` [m] with `normal` into the particles; returns its index.
    std::size_t add_plane(const vec3 &p, const vec3 &n, const material &m)
    {
        std::size_t k = 0;
        check(sinter_walls_add_plane(live("sinter_walls_add_plane"), p.data(), n.data(),
                                     m.get(), &k),
              "sinter_walls_add_plane");
        return k;
    }
    void set_material(std::size_t k, const material &m)
    {
        check(sinter_walls_set_material(live("sinter_walls_set_material"), k, m.get()),
              "sinter_walls_set_material");
    }
    /// Constant velocity [m/s].
    void set_velocity(std::size_t k, const vec3 &u)
    {
        check(sinter_walls_set_velocity(live("sinter_walls_set_velocity"), k, u.data()),
              "sinter_walls_set_velocity");
    }
    /// Piecewise-linear displacement: times [s], displacements (3 per time) [m].
    void set_schedule(std::size_t k, span<const double> times, span<const double> displacements)
    {
        if (displacements.size() != 3 * times.size())
            throw error(status::invalid, "3 displacement values per time expected",
                        "sinter_walls_set_schedule");
        check(sinter_walls_set_schedule(live("sinter_walls_set_schedule"), k, times.size(),
                                        times.data(), displacements.data()),
              "sinter_walls_set_schedule");
    }
    /// p0 + amplitude sin(omega t) ([m], [rad/s]).
    void set_sine(std::size_t k, const vec3 &amplitude, double omega)
    {
        check(sinter_walls_set_sine(live("sinter_walls_set_sine"), k, amplitude.data(), omega),
              "sinter_walls_set_sine");
    }
    /// Time [s] at which wall k's prescribed motion starts.
    void set_motion_start(std::size_t k, double start)
    {
        check(sinter_walls_set_motion_start(live("sinter_walls_set_motion_start"), k, start),
              "sinter_walls_set_motion_start");
    }
    /// Wall temperature [K].
    void set_temperature(std::size_t k, double temperature)
    {
        check(sinter_walls_set_temperature(live("sinter_walls_set_temperature"), k, temperature),
              "sinter_walls_set_temperature");
    }
    /// Wall temperature through (times [s], temperatures [K]).
    void set_temperature_schedule(std::size_t k, span<const double> times,
                                  span<const double> temperatures)
    {
        if (times.size() != temperatures.size())
            throw error(status::invalid, "as many temperatures as times expected",
                        "sinter_walls_set_temperature_schedule");
        check(sinter_walls_set_temperature_schedule(live("sinter_walls_set_temperature_schedule"),
                                                    k, times.size(), times.data(),
                                                    temperatures.data()),
              "sinter_walls_set_temperature_schedule");
    }
    /// Electric boundary condition: a current [A] or a potential [V].
    void set_electric(std::size_t k, wall_electric_mode mode, double value)
    {
        check(sinter_walls_set_electric(live("sinter_walls_set_electric"), k,
                                        static_cast<int>(mode), value),
              "sinter_walls_set_electric");
    }
    /// A fixed rectangle centred at `c` [m], normal `n` into the particles, first edge along
    /// `edge` (half length h1), second along n x edge (half length h2) [m].
    std::size_t add_rectangle(const vec3 &c, const vec3 &n, const vec3 &edge, double h1, double h2,
                              const material &m)
    {
        std::size_t k = 0;
        check(sinter_walls_add_rectangle(live("sinter_walls_add_rectangle"), c.data(), n.data(),
                                         edge.data(), h1, h2, m.get(), &k),
              "sinter_walls_add_rectangle");
        return k;
    }
    /// A fixed disc of radius r [m] centred at `c`, normal `n` into the particles.
    std::size_t add_disc(const vec3 &c, const vec3 &n, double r, const material &m)
    {
        std::size_t k = 0;
        check(sinter_walls_add_disc(live("sinter_walls_add_disc"), c.data(), n.data(), r, m.get(),
                                    &k),
              "sinter_walls_add_disc");
        return k;
    }
    /// A fixed cylinder: axis through `p` along `a`, radius r [m], contacts within half_length
    /// [m] of p along the axis (HUGE_VAL: infinite), particles inside or outside.
    std::size_t add_cylinder(const vec3 &p, const vec3 &a, double r, double half_length,
                             bool inside, const material &m)
    {
        std::size_t k = 0;
        check(sinter_walls_add_cylinder(live("sinter_walls_add_cylinder"), p.data(), a.data(), r,
                                        half_length, inside ? 1 : 0, m.get(), &k),
              "sinter_walls_add_cylinder");
        return k;
    }
    /// A fixed triangle mesh from the STL file `path`, placed at t + R (scale x) (R: rotate
    /// [rad] about x, then y, then z); flip reverses its normals; reach [m] as in the C API.
    std::size_t add_mesh(const char *path, double scale, const vec3 &rotate, const vec3 &t,
                         bool flip, double reach, const material &m)
    {
        std::size_t k = 0;
        check(sinter_walls_add_mesh(live("sinter_walls_add_mesh"), path, scale, rotate.data(),
                                    t.data(), flip ? 1 : 0, reach, m.get(), &k),
              "sinter_walls_add_mesh");
        return k;
    }
    /// Kind of wall k.
    wall_kind kind(std::size_t k) const
    {
        int kind = 0;
        check(sinter_walls_get_kind(live("sinter_walls_get_kind"), k, &kind),
              "sinter_walls_get_kind");
        return static_cast<wall_kind>(kind);
    }
    /// Spin of wall k about its axis [rad/s].
    void set_spin(std::size_t k, double omega)
    {
        check(sinter_walls_set_spin(live("sinter_walls_set_spin"), k, omega),
              "sinter_walls_set_spin");
    }
    /// Turn mesh wall k about the axis through point [m] along axis at omega [rad/s]
    /// (sinter_walls_set_rotation).
    void set_rotation(std::size_t k, const double point[3], const double axis[3], double omega)
    {
        check(sinter_walls_set_rotation(live("sinter_walls_set_rotation"), k, point, axis, omega),
              "sinter_walls_set_rotation");
    }
    /// Force servo along wall k's normal: targets (times [s], forces [N]), gains kp [m/(s N)],
    /// ki [m/(s^2 N)], velocity limit vmax [m/s] (sinter_walls_set_servo).
    void set_servo(std::size_t k, span<const double> times, span<const double> forces, double kp,
                   double ki, double vmax)
    {
        if (times.size() != forces.size())
            throw error(status::invalid, "as many forces as times expected",
                        "sinter_walls_set_servo");
        check(sinter_walls_set_servo(live("sinter_walls_set_servo"), k, times.size(), times.data(),
                                     forces.data(), kp, ki, vmax),
              "sinter_walls_set_servo");
    }
    /// Whether wall k's reaction moment is summed (sinter_walls_set_moment).
    void set_moment(std::size_t k, bool on)
    {
        check(sinter_walls_set_moment(live("sinter_walls_set_moment"), k, on ? 1 : 0),
              "sinter_walls_set_moment");
    }
    /// Reaction moment on wall k about its point in the last accepted step [N m].
    vec3 moment(std::size_t k) const
    {
        vec3 m{};
        check(sinter_walls_get_moment(live("sinter_walls_get_moment"), k, m.data()),
              "sinter_walls_get_moment");
        return m;
    }
    /// Reaction force on wall k in the last accepted step [N].
    vec3 force(std::size_t k) const
    {
        vec3 f{};
        check(sinter_walls_get_force(live("sinter_walls_get_force"), k, f.data()),
              "sinter_walls_get_force");
        return f;
    }
    /// The position of wall k's point [m] at the stepper's current time.
    vec3 point(std::size_t k) const
    {
        vec3 p{}, v{};
        check(sinter_walls_get_state(live("sinter_walls_get_state"), k, p.data(), v.data()),
              "sinter_walls_get_state");
        return p;
    }
    /// The velocity of wall k [m/s].
    vec3 velocity(std::size_t k) const
    {
        vec3 p{}, v{};
        check(sinter_walls_get_state(live("sinter_walls_get_state"), k, p.data(), v.data()),
              "sinter_walls_get_state");
        return v;
    }
    /// The unit normal of wall k.
    vec3 normal(std::size_t k) const
    {
        vec3 n{};
        check(sinter_walls_get_normal(live("sinter_walls_get_normal"), k, n.data()),
              "sinter_walls_get_normal");
        return n;
    }
};

// ---------------------------------------------------------------------------------------------
// Submodels: named, with numeric options
// ---------------------------------------------------------------------------------------------

namespace detail {
/// A submodel made by name with key/value options (force, heat, electric); Api names the C
/// functions of its kind.
template <typename Api> class named_model : public handle<typename Api::type, Api::destroy> {
    using base = handle<typename Api::type, Api::destroy>;

  public:
    using base::get; // get(): the C handle; get(key): an option
    named_model() noexcept = default;
    /// The submodel called `name` (the library's list of models of this kind).
    named_model(const context &ctx, const char *name)
    {
        typename Api::type *raw = nullptr;
        detail::check(Api::create(&raw, ctx.get(), name), ctx.get(), Api::create_name);
        static_cast<base &>(*this) = base(raw, ctx.get());
    }
    /// Set option `key` (the model's documented keys).
    named_model &set(const char *key, double value)
    {
        this->check(Api::set(this->live(Api::set_name), key, value), Api::set_name);
        return *this;
    }
    double get(const char *key) const
    {
        double v = 0;
        this->check(Api::get(this->live(Api::get_name), key, &v), Api::get_name);
        return v;
    }
    std::string name() const { return Api::name(this->live("name")); }
};

// The C functions of one kind of named submodel: kind##_api for sinter_##kind##_model_*.
#define SINTER_HPP_MODEL_API_(kind)                                                            \
    struct kind##_api {                                                                        \
        using type = sinter_##kind##_model;                                                    \
        static constexpr void (*destroy)(type *) = sinter_##kind##_model_destroy;              \
        static constexpr auto create = sinter_##kind##_model_create;                           \
        static constexpr auto set = sinter_##kind##_model_set;                                 \
        static constexpr auto get = sinter_##kind##_model_get;                                 \
        static constexpr auto name = sinter_##kind##_model_name;                               \
        static constexpr const char *create_name = "sinter_" #kind "_model_create";            \
        static constexpr const char *set_name = "sinter_" #kind "_model_set";                  \
        static constexpr const char *get_name = "sinter_" #kind "_model_get";                  \
    };
SINTER_HPP_MODEL_API_(force)
SINTER_HPP_MODEL_API_(heat)
SINTER_HPP_MODEL_API_(electric)
#undef SINTER_HPP_MODEL_API_
} // namespace detail

/// A force submodel ("hertz_mindlin", "gravity", ...: sinter_force_model_create).
using force_model = detail::named_model<detail::force_api>;
/// A heat submodel ("conduction", "radiation", ...: sinter_heat_model_create).
using heat_model = detail::named_model<detail::heat_api>;
/// An electric submodel ("averaged", "network": sinter_electric_model_create).
using electric_model = detail::named_model<detail::electric_api>;

/// The 7DOF neck model (sinter_neck_model); sinter_neck_two_particles through get().
class neck_model : public detail::handle<sinter_neck_model, sinter_neck_model_destroy> {
  public:
    using handle::get; // get(): the C handle; get(key): an option
    neck_model() noexcept = default;
    explicit neck_model(const context &ctx)
    {
        sinter_neck_model *raw = nullptr;
        detail::check(sinter_neck_model_create(&raw, ctx.get()), ctx.get(),
                      "sinter_neck_model_create");
        static_cast<handle &>(*this) = handle(raw, ctx.get());
    }
    neck_model &set(const char *key, double value)
    {
        check(sinter_neck_model_set(live("sinter_neck_model_set"), key, value),
              "sinter_neck_model_set");
        return *this;
    }
    double get(const char *key) const
    {
        double v = 0;
        check(sinter_neck_model_get(live("sinter_neck_model_get"), key, &v),
              "sinter_neck_model_get");
        return v;
    }
};

// ---------------------------------------------------------------------------------------------
// Steppers
// ---------------------------------------------------------------------------------------------

/// Time integration over a particle set and walls (sinter_stepper); both are borrowed.
class stepper : public detail::handle<sinter_stepper, sinter_stepper_destroy> {
  public:
    stepper() noexcept = default;
    stepper(const context &ctx, stepper_kind kind, particles &ps, walls *ws = nullptr)
    {
        sinter_stepper *raw = nullptr;
        detail::check(sinter_stepper_create(&raw, ctx.get(), static_cast<sinter_stepper_kind>(kind),
                                            ps.get(), ws != nullptr ? ws->get() : nullptr),
                      ctx.get(), "sinter_stepper_create");
        static_cast<handle &>(*this) = handle(raw, ctx.get());
    }
    stepper(const context &ctx, stepper_kind kind, particles &ps, walls &ws)
        : stepper(ctx, kind, ps, &ws)
    {
    }
    stepper(stepper &&) noexcept = default;
    stepper &operator=(stepper &&) noexcept = default;
    ~stepper() = default;

    /// Add a force submodel (borrowed: it must outlive the stepper).
    stepper &add(force_model &fm)
    {
        check(sinter_stepper_add_force(live("sinter_stepper_add_force"), fm.get()),
              "sinter_stepper_add_force");
        return *this;
    }
    /// Add a heat submodel (borrowed).
    stepper &add(heat_model &hm)
    {
        check(sinter_stepper_add_heat(live("sinter_stepper_add_heat"), hm.get()),
              "sinter_stepper_add_heat");
        return *this;
    }
    /// Set the electric submodel (borrowed).
    stepper &set_electric(electric_model &em)
    {
        check(sinter_stepper_set_electric(live("sinter_stepper_set_electric"), em.get()),
              "sinter_stepper_set_electric");
        return *this;
    }
    /// Time step [s].
    stepper &set_dt(double dt)
    {
        check(sinter_stepper_set_dt(live("sinter_stepper_set_dt"), dt), "sinter_stepper_set_dt");
        return *this;
    }
    stepper &set_skin(double skin)
    {
        check(sinter_stepper_set_skin(live("sinter_stepper_set_skin"), skin),
              "sinter_stepper_set_skin");
        return *this;
    }
    /// The simulation domain [m]: particles leaving it stop the run.
    stepper &set_domain(const vec3 &lo, const vec3 &hi)
    {
        check(sinter_stepper_set_domain(live("sinter_stepper_set_domain"), lo.data(), hi.data()),
              "sinter_stepper_set_domain");
        return *this;
    }
    /// A periodic boundary along axis (0 x, 1 y, 2 z) with the cell lo..hi [m]; lo = hi = 0
    /// makes the axis non-periodic again (explicit stepper only).
    stepper &set_periodic(int axis, double lo, double hi)
    {
        check(sinter_stepper_set_periodic(live("sinter_stepper_set_periodic"), axis, lo, hi),
              "sinter_stepper_set_periodic");
        return *this;
    }
    stepper &set_option(const char *key, double value)
    {
        check(sinter_stepper_set_option(live("sinter_stepper_set_option"), key, value),
              "sinter_stepper_set_option");
        return *this;
    }
    double option(const char *key) const
    {
        double v = 0;
        check(sinter_stepper_get_option(live("sinter_stepper_get_option"), key, &v),
              "sinter_stepper_get_option");
        return v;
    }
    stepper &set_thermal_scheme(thermal_scheme scheme)
    {
        check(sinter_stepper_set_thermal_scheme(live("sinter_stepper_set_thermal_scheme"),
                                                static_cast<int>(scheme)),
              "sinter_stepper_set_thermal_scheme");
        return *this;
    }
    /// Furnace: every particle's temperature through (times [s], temperatures [K]).
    stepper &set_furnace(span<const double> times, span<const double> temperatures)
    {
        if (times.size() != temperatures.size())
            throw error(status::invalid, "as many temperatures as times expected",
                        "sinter_stepper_set_furnace");
        check(sinter_stepper_set_furnace(live("sinter_stepper_set_furnace"), times.size(),
                                         times.data(), temperatures.data()),
              "sinter_stepper_set_furnace");
        return *this;
    }
    /**
     * Call `fn(time)` after every accepted step; returning true stops advance() early. An
     * exception thrown by `fn` stops the run and is rethrown by the advance() or step() that
     * ran it (it never crosses the C library). An empty function removes the observer.
     */
    stepper &set_observer(std::function<bool(double)> fn)
    {
        sinter_stepper *st = live("sinter_stepper_set_observer");
        if (!fn) {
            check(sinter_stepper_set_observer(st, nullptr, nullptr), "sinter_stepper_set_observer");
            observer_.reset();
            return *this;
        }
        auto next = std::make_unique<observer_state>();
        next->fn = std::move(fn);
        check(sinter_stepper_set_observer(st, &stepper::observe, next.get()),
              "sinter_stepper_set_observer");
        observer_ = std::move(next);
        return *this;
    }
    /// Advance to t_end [s].
    void advance(double t_end)
    {
        run(sinter_stepper_advance(live("sinter_stepper_advance"), t_end), "sinter_stepper_advance");
    }
    /// Continuous insertion of `powder` (sinter_stepper_set_insertion); nullptr removes it.
    void set_insertion(const sinter_packing_options *powder,
                       const sinter_insertion_options *options)
    {
        run(sinter_stepper_set_insertion(live("sinter_stepper_set_insertion"), powder, options),
            "sinter_stepper_set_insertion");
    }
    /// The mass inserted so far of each material of the insertion's mixture [kg], in the order
    /// of the powder's mixture_materials (sinter_stepper_get_insertion_mixture); empty without
    /// a mixture.
    std::vector<double> insertion_mixture() const
    {
        const char *fn = "sinter_stepper_get_insertion_mixture";
        std::size_t count = 0;
        check(sinter_stepper_get_insertion_mixture(live(fn), nullptr, 0, &count), fn);
        std::vector<double> mass(count);
        if (count > 0)
            check(sinter_stepper_get_insertion_mixture(live(fn), mass.data(), count, nullptr), fn);
        return mass;
    }
    /// Take n steps.
    void step(std::uint64_t n)
    {
        run(sinter_stepper_step(live("sinter_stepper_step"), n), "sinter_stepper_step");
    }
    /// Evaluate forces and heat at the current state without stepping.
    void evaluate()
    {
        run(sinter_stepper_evaluate(live("sinter_stepper_evaluate")), "sinter_stepper_evaluate");
    }
    /// The stepper's time [s].
    double time() const
    {
        double t = 0;
        check(sinter_stepper_time(live("sinter_stepper_time"), &t), "sinter_stepper_time");
        return t;
    }
    sinter_stepper_stats stats() const
    {
        sinter_stepper_stats s{};
        s.struct_size = sizeof s;
        check(sinter_stepper_get_stats(live("sinter_stepper_get_stats"), &s),
              "sinter_stepper_get_stats");
        return s;
    }
    /// Neck and shrinkage statistics of a quasi-static stepper that has taken a step.
    sinter_sintering_stats sintering_stats() const
    {
        sinter_sintering_stats s{};
        s.struct_size = sizeof s;
        check(sinter_stepper_sintering_stats(live("sinter_stepper_sintering_stats"), &s),
              "sinter_stepper_sintering_stats");
        return s;
    }
    /// The explicit stepper's thermally stable step [s].
    double stable_dt_thermal()
    {
        double dt = 0;
        check(sinter_stepper_stable_dt_thermal(live("sinter_stepper_stable_dt_thermal"), &dt),
              "sinter_stepper_stable_dt_thermal");
        return dt;
    }
    void write_checkpoint(const std::string &path) const
    {
        check(sinter_checkpoint_write(live("sinter_checkpoint_write"), path.c_str()),
              "sinter_checkpoint_write");
    }
    void read_checkpoint(const std::string &path)
    {
        check(sinter_checkpoint_read(live("sinter_checkpoint_read"), path.c_str()),
              "sinter_checkpoint_read");
    }
    /// The particles of `indices` as a record stream with everything the stepper keeps for
    /// them (sinter_stepper_export); remove: take them out of this stepper's set.
    std::vector<unsigned char> export_particles(const std::vector<std::size_t> &indices,
                                                bool remove = false)
    {
        std::size_t bytes = 0, written = 0;
        check(sinter_stepper_export_size(live("sinter_stepper_export_size"), indices.size(),
                                         indices.data(), &bytes),
              "sinter_stepper_export_size");
        std::vector<unsigned char> records(bytes);
        check(sinter_stepper_export(live("sinter_stepper_export"), indices.size(),
                                    indices.data(), records.data(), records.size(), &written,
                                    remove ? 1 : 0),
              "sinter_stepper_export");
        records.resize(written);
        return records;
    }
    /// Take the particles of `indices` out of this stepper's set without writing their
    /// records (sinter_stepper_remove): after an export without removal.
    void remove_particles(const std::vector<std::size_t> &indices)
    {
        check(sinter_stepper_remove(live("sinter_stepper_remove"), indices.size(),
                                    indices.data()),
              "sinter_stepper_remove");
    }
    /// Append the particles of a record stream of export_particles; returns how many.
    std::size_t import_particles(const std::vector<unsigned char> &records)
    {
        std::size_t count = 0;
        check(sinter_stepper_import(live("sinter_stepper_import"), records.data(),
                                    records.size(), &count),
              "sinter_stepper_import");
        return count;
    }
    /// The stepper's global part of a portable checkpoint (sinter_stepper_save_global).
    std::vector<unsigned char> save_global() const
    {
        std::size_t bytes = 0;
        check(sinter_stepper_save_global(live("sinter_stepper_save_global"), nullptr, 0, &bytes),
              "sinter_stepper_save_global");
        std::vector<unsigned char> part(bytes);
        check(sinter_stepper_save_global(live("sinter_stepper_save_global"), part.data(),
                                         part.size(), &bytes),
              "sinter_stepper_save_global");
        return part;
    }
    /// Load a global part into this stepper, set up alike and without particles.
    void load_global(const std::vector<unsigned char> &part)
    {
        check(sinter_stepper_load_global(live("sinter_stepper_load_global"), part.data(),
                                         part.size()),
              "sinter_stepper_load_global");
    }

  private:
    struct observer_state {
        std::function<bool(double)> fn;
        std::exception_ptr thrown;
    };
    static int observe(const sinter_stepper *, double t, void *user) noexcept
    {
        auto *state = static_cast<observer_state *>(user);
        try {
            return state->fn(t) ? 1 : 0;
        } catch (...) {
            state->thrown = std::current_exception();
            return -1;
        }
    }
    void run(sinter_status st, const char *function)
    {
        if (observer_ && observer_->thrown)
            std::rethrow_exception(std::exchange(observer_->thrown, nullptr));
        check(st, function);
    }
    std::unique_ptr<observer_state> observer_; // declared after the handle: destroyed first
};

// ---------------------------------------------------------------------------------------------
// Output: time series
// ---------------------------------------------------------------------------------------------

/// A time series of named columns with units (sinter_series), written as CSV and SVG.
class series : public detail::handle<sinter_series, sinter_series_destroy> {
  public:
    series() noexcept = default;
    /// Columns named `names` with `units` (as many).
    series(const context &ctx, const std::vector<std::string> &names,
           const std::vector<std::string> &units)
    {
        if (names.size() != units.size())
            throw error(status::invalid, "as many units as names expected", "sinter_series_create");
        std::vector<const char *> n, u;
        for (const std::string &s : names)
            n.push_back(s.c_str());
        for (const std::string &s : units)
            u.push_back(s.c_str());
        sinter_series *raw = nullptr;
        detail::check(sinter_series_create(&raw, ctx.get(), names.size(), n.data(), u.data()),
                      ctx.get(), "sinter_series_create");
        static_cast<handle &>(*this) = handle(raw, ctx.get());
        columns_ = names.size();
    }
    /// Read a CSV file written by write_csv.
    static series read_csv(const context &ctx, const std::string &path)
    {
        sinter_series *raw = nullptr;
        detail::check(sinter_series_read_csv(&raw, ctx.get(), path.c_str()), ctx.get(),
                      "sinter_series_read_csv");
        series s;
        static_cast<handle &>(s) = handle(raw, ctx.get());
        s.columns_ = 0; // unknown: append() then checks nothing more than the library does
        return s;
    }
    /// Append one row (as many values as columns).
    void append(span<const double> row)
    {
        if (columns_ != 0 && row.size() != columns_)
            throw error(status::invalid,
                        std::to_string(row.size()) + " values for " + std::to_string(columns_) +
                            " columns",
                        "sinter_series_append");
        check(sinter_series_append(live("sinter_series_append"), row.data()),
              "sinter_series_append");
    }
    std::size_t rows() const
    {
        std::size_t n = 0;
        check(sinter_series_rows(live("sinter_series_rows"), &n), "sinter_series_rows");
        return n;
    }
    double at(std::size_t row, std::size_t column) const
    {
        double v = 0;
        check(sinter_series_get(live("sinter_series_get"), row, column, &v), "sinter_series_get");
        return v;
    }
    void write_csv(const std::string &path) const
    {
        check(sinter_series_write_csv(live("sinter_series_write_csv"), path.c_str()),
              "sinter_series_write_csv");
    }
    /// Every column against column `x_column` in one panel.
    void write_svg(const std::string &path, const std::string &title, std::size_t x_column = 0) const
    {
        check(sinter_series_write_svg(live("sinter_series_write_svg"), path.c_str(), title.c_str(),
                                      x_column, 0, nullptr, nullptr),
              "sinter_series_write_svg");
    }

  private:
    std::size_t columns_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Scenes
// ---------------------------------------------------------------------------------------------

/// A scene file loaded with everything it builds (sinter_scene).
class scene : public detail::handle<sinter_scene, sinter_scene_destroy> {
  public:
    scene() noexcept = default;
    scene(const context &ctx, const std::string &path)
    {
        sinter_scene *raw = nullptr;
        detail::check(sinter_scene_load(&raw, ctx.get(), path.c_str()), ctx.get(),
                      "sinter_scene_load");
        static_cast<handle &>(*this) = handle(raw, ctx.get());
    }
    /// The set-up checks of a run, without stepping.
    void check_setup() const
    {
        check(sinter_scene_check(live("sinter_scene_check")), "sinter_scene_check");
    }
    /// The scene's [compact] section run on its particles now (before stepping them yourself).
    void compact()
    {
        check(sinter_scene_compact(live("sinter_scene_compact")), "sinter_scene_compact");
    }
    /// Run to the end time, writing the outputs to `out_dir`.
    void run(const std::string &out_dir)
    {
        check(sinter_scene_run(live("sinter_scene_run"), out_dir.c_str(), nullptr, nullptr),
              "sinter_scene_run");
    }
    double end_time() const
    {
        double t = 0;
        check(sinter_scene_end_time(live("sinter_scene_end_time"), &t), "sinter_scene_end_time");
        return t;
    }
    void set_end_time(double t)
    {
        check(sinter_scene_set_end_time(live("sinter_scene_set_end_time"), t),
              "sinter_scene_set_end_time");
    }
    void write_checkpoint(const std::string &path) const
    {
        check(sinter_scene_checkpoint_write(live("sinter_scene_checkpoint_write"), path.c_str()),
              "sinter_scene_checkpoint_write");
    }
    void restart(const std::string &path)
    {
        check(sinter_scene_restart(live("sinter_scene_restart"), path.c_str()),
              "sinter_scene_restart");
    }
    /// The scene's stepper, particles and walls (borrowed C handles, valid while the scene is).
    sinter_stepper *stepper_handle() const
    {
        sinter_stepper *p = nullptr;
        check(sinter_scene_get_stepper(live("sinter_scene_get_stepper"), &p),
              "sinter_scene_get_stepper");
        return p;
    }
    sinter_particles *particles_handle() const
    {
        sinter_particles *p = nullptr;
        check(sinter_scene_get_particles(live("sinter_scene_get_particles"), &p),
              "sinter_scene_get_particles");
        return p;
    }
    sinter_walls *walls_handle() const
    {
        sinter_walls *p = nullptr;
        check(sinter_scene_get_walls(live("sinter_scene_get_walls"), &p), "sinter_scene_get_walls");
        return p;
    }
};

} // namespace sinter

#endif /* SINTER_HPP */
