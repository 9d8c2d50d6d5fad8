// Seed 003 sec. 5.1 from C++: a particle (r = 1 mm, 300 K) settling on a floor held at
// 700 K, with and without thermal softening, through the C API with small RAII wrappers.
//
// Every handle lives in a std::unique_ptr whose deleter is the library's destroy
// function, and every failing call throws sinter_error carrying the status and the
// context's message. Objects are declared in the order the library needs them
// destroyed in reverse: context first, stepper last, so scope exit tears them
// down safely even when an exception unwinds.
//
// Prints the static contact force (the seed: 1.23e-4 N), the time to thermal
// equilibrium and the ratio of the contact areas (the seed: about 63 % larger
// with softening). Exit status 0 when the static force equals the weight and
// softening enlarges the contact. Units: SI.
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <sinter.h>

namespace sinter {

// --- RAII ------------------------------------------------------------------

template <typename T, void (*Destroy)(T *)> struct deleter {
    void operator()(T *p) const noexcept { Destroy(p); }
};
template <typename T, void (*Destroy)(T *)>
using handle = std::unique_ptr<T, deleter<T, Destroy>>;

using context = handle<sinter_ctx, sinter_ctx_destroy>;
using material = handle<sinter_material, sinter_material_destroy>;
using particles = handle<sinter_particles, sinter_particles_destroy>;
using walls = handle<sinter_walls, sinter_walls_destroy>;
using force_model = handle<sinter_force_model, sinter_force_model_destroy>;
using heat_model = handle<sinter_heat_model, sinter_heat_model_destroy>;
using stepper = handle<sinter_stepper, sinter_stepper_destroy>;

class error : public std::runtime_error {
  public:
    error(sinter_status status, const std::string &message)
        : std::runtime_error(message + " [" + sinter_status_name(status) + "]"), status_(status)
    {
    }
    sinter_status status() const noexcept { return status_; }

  private:
    sinter_status status_;
};

// Throw for a failing status, with the context's detail when it has one.
inline void check(sinter_status status, const sinter_ctx *ctx, const char *what)
{
    if (status == SINTER_OK)
        return;
    std::string message = what;
    if (ctx != nullptr && *sinter_last_error(ctx) != '\0')
        message = sinter_last_error(ctx);
    throw error(status, message);
}

// Create through a C create function of the form f(T **out, args...).
template <typename Handle, typename Create, typename... Args>
Handle make(const sinter_ctx *ctx, Create create, const char *what, Args... args)
{
    typename Handle::pointer raw = nullptr;
    check(create(&raw, args...), ctx, what);
    return Handle(raw);
}

inline context make_context()
{
    sinter_ctx *raw = nullptr;
    check(sinter_ctx_create(&raw, nullptr), nullptr, "sinter_ctx_create");
    return context(raw);
}

// A field borrowed read-only for the lifetime of the object (released by the destructor).
class field_view {
  public:
    field_view(const sinter_particles *ps, sinter_field field, const sinter_ctx *ctx)
        : ps_(ps), field_(field)
    {
        const void *data = nullptr;
        check(sinter_particles_view_read(ps, field, &data, &count_, &components_), ctx,
              "sinter_particles_view_read");
        data_ = static_cast<const double *>(data);
    }
    field_view(const field_view &) = delete;
    field_view &operator=(const field_view &) = delete;
    ~field_view() { sinter_particles_release(ps_, field_); }
    double operator()(size_t i, size_t c = 0) const { return data_[i * components_ + c]; }

  private:
    const sinter_particles *ps_;
    sinter_field field_;
    const double *data_ = nullptr;
    size_t count_ = 0, components_ = 0;
};

} // namespace sinter

namespace {

constexpr double radius = 1e-3;        // m
constexpr double theta_particle = 300; // K
constexpr double theta_floor = 700;    // K
constexpr double dt = 2e-5;            // s, the seed's step
constexpr double end_time = 40;        // s
constexpr double sample = 0.1;         // s

struct result {
    std::vector<double> time, temperature;
    double force_z = 0, height = 0;
};

result simulate(bool softening)
{
    using namespace sinter;
    // Declaration order = reverse destruction order: the context outlives everything.
    context ctx = make_context();
    sinter_ctx *c = ctx.get();
    auto set = [c](sinter_material *m, sinter_material_param p, double v) {
        check(sinter_material_set(m, p, v), c, "sinter_material_set");
    };
    material grain = make<material>(c, sinter_material_create, "sinter_material_create", c,
                                    "particle");
    set(grain.get(), SINTER_MAT_DENSITY, 3000);
    set(grain.get(), SINTER_MAT_YOUNGS_MODULUS, 1e6);
    set(grain.get(), SINTER_MAT_POISSON_RATIO, 0.3);
    set(grain.get(), SINTER_MAT_DAMPING_RATIO, 1.0); // critically damped
    set(grain.get(), SINTER_MAT_THERMAL_CONDUCTIVITY, 60);
    set(grain.get(), SINTER_MAT_HEAT_CAPACITY, 100);
    if (softening) {
        set(grain.get(), SINTER_MAT_SOFTENING_LAW, 2); // exponential, seed 003 eq. 42
        set(grain.get(), SINTER_MAT_SOFTENING_TEMPERATURE, 400);
    }
    material floor = make<material>(c, sinter_material_create, "sinter_material_create", c,
                                    "floor");
    set(floor.get(), SINTER_MAT_YOUNGS_MODULUS, 1e13); // rigid
    set(floor.get(), SINTER_MAT_POISSON_RATIO, 0.3);
    set(floor.get(), SINTER_MAT_THERMAL_CONDUCTIVITY, 60);

    particles ps = make<particles>(c, sinter_particles_create, "sinter_particles_create", c);
    check(sinter_particles_set_material(ps.get(), 0, grain.get()), c, "set_material");
    const double x[3] = {0, 0, radius};
    check(sinter_particles_add(ps.get(), 1, x, &radius, 0, theta_particle, nullptr), c,
          "sinter_particles_add");

    walls ws = make<walls>(c, sinter_walls_create, "sinter_walls_create", c);
    const double origin[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    size_t floor_index = 0;
    check(sinter_walls_add_plane(ws.get(), origin, up, floor.get(), &floor_index), c,
          "sinter_walls_add_plane");
    check(sinter_walls_set_temperature(ws.get(), floor_index, theta_floor), c,
          "sinter_walls_set_temperature");

    force_model hertz = make<force_model>(c, sinter_force_model_create, "hertz_mindlin", c,
                                          "hertz_mindlin");
    force_model gravity = make<force_model>(c, sinter_force_model_create, "gravity", c,
                                            "gravity");
    heat_model conduction = make<heat_model>(c, sinter_heat_model_create, "conduction", c,
                                             "conduction");
    // The stepper borrows everything above, so it is declared (and destroyed) last.
    stepper st = make<stepper>(c, sinter_stepper_create, "sinter_stepper_create", c,
                               SINTER_STEPPER_EXPLICIT, ps.get(), ws.get());
    check(sinter_stepper_add_force(st.get(), hertz.get()), c, "add_force");
    check(sinter_stepper_add_force(st.get(), gravity.get()), c, "add_force");
    check(sinter_stepper_add_heat(st.get(), conduction.get()), c, "add_heat");
    check(sinter_stepper_set_dt(st.get(), dt), c, "set_dt");
    const double lo[3] = {-0.01, -0.01, -0.01}, hi[3] = {0.01, 0.01, 0.01};
    check(sinter_stepper_set_domain(st.get(), lo, hi), c, "set_domain");

    result r;
    r.time.push_back(0);
    r.temperature.push_back(theta_particle);
    const int samples = static_cast<int>(std::lround(end_time / sample));
    for (int k = 1; k <= samples; ++k) {
        check(sinter_stepper_advance(st.get(), k * sample), c, "sinter_stepper_advance");
        double t = 0;
        check(sinter_stepper_time(st.get(), &t), c, "sinter_stepper_time");
        field_view theta(ps.get(), SINTER_FIELD_TEMPERATURE, c);
        r.time.push_back(t);
        r.temperature.push_back(theta(0));
    }
    double f[3];
    check(sinter_walls_get_force(ws.get(), floor_index, f), c, "sinter_walls_get_force");
    r.force_z = f[2];
    field_view pos(ps.get(), SINTER_FIELD_POSITION, c);
    r.height = pos(0, 2);
    return r;
}

// First sample after which the temperature stays within 0.1 % of the initial difference.
double equilibrium_time(const result &r)
{
    const double band = 1e-3 * (theta_floor - theta_particle);
    double reached = -1;
    for (size_t k = 0; k < r.time.size(); ++k) {
        if (std::fabs(theta_floor - r.temperature[k]) <= band) {
            if (reached < 0)
                reached = r.time[k];
        } else {
            reached = -1;
        }
    }
    return reached;
}

// pi a^2 with a^2 = r^2 - L^2, L the centre-plane distance (sinter_contact_batch).
double contact_area(double height)
{
    return 3.14159265358979323846 * std::fmax(radius * radius - height * height, 0.0);
}

} // namespace

int main()
{
    try {
        const result soft = simulate(true), hard = simulate(false);
        const double weight = 3000 * 4.0 / 3.0 * 3.14159265358979323846 * std::pow(radius, 3) *
                              9.81;
        std::printf("seed 003 sec. 5.1 (C++, libsinter %s): weight m g = %.4e N "
                    "(seed: contact force 1.23e-4 N)\n",
                    sinter_version_string(), weight);
        const struct {
            const char *label;
            const result &r;
        } cases[] = {{"with softening", soft}, {"without softening", hard}};
        for (const auto &c : cases)
            std::printf("%-18s static force %.4e N, equilibrium (within 0.4 K) at %.1f s, "
                        "contact area %.4e m^2\n",
                        c.label, std::fabs(c.r.force_z), equilibrium_time(c.r),
                        contact_area(c.r.height));
        const double ratio = contact_area(soft.height) / contact_area(hard.height);
        std::printf("contact area ratio (softening / none): %.3f (seed: about 1.63)\n", ratio);
        for (const auto &c : cases)
            if (std::fabs(std::fabs(c.r.force_z) - weight) > 1e-3 * weight) {
                std::fprintf(stderr, "error: the static force (%s) is not the weight\n",
                             c.label);
                return 1;
            }
        if (!(ratio > 1.0)) {
            std::fprintf(stderr, "error: softening did not enlarge the contact area\n");
            return 1;
        }
    } catch (const sinter::error &e) {
        std::fprintf(stderr, "libsinter error: %s\n", e.what());
        return 1;
    }
    return 0;
}
