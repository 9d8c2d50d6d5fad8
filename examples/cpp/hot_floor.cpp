// Seed 003 sec. 5.1 from C++: a particle (r = 1 mm, 300 K) settling on a floor held at
// 700 K, with and without thermal softening, through include/sinter.hpp (C++17).
//
// Every object of the library is a sinter:: handle that destroys it at scope exit, and
// every failing call throws sinter::error carrying the status and the context's message.
// Objects are declared in the order the library needs them destroyed in reverse: context
// first, stepper last, so scope exit tears them down safely even when an exception unwinds.
//
// Prints the static contact force (the seed: 1.23e-4 N), the time to thermal
// equilibrium and the ratio of the contact areas (the seed: about 63 % larger
// with softening). Exit status 0 when the static force equals the weight and
// softening enlarges the contact. Units: SI.
#include <cmath>
#include <cstdio>
#include <vector>

#include <sinter.hpp>

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
    using sinter::material_param;
    // Declaration order = reverse destruction order: the context outlives everything.
    sinter::context ctx;
    sinter::material grain(ctx, "particle");
    grain.set(material_param::density, 3000)
        .set(material_param::youngs_modulus, 1e6)
        .set(material_param::poisson_ratio, 0.3)
        .set(material_param::damping_ratio, 1.0) // critically damped
        .set(material_param::thermal_conductivity, 60)
        .set(material_param::heat_capacity, 100);
    if (softening)
        grain.set(material_param::softening_law, 2) // exponential, seed 003 eq. 42
            .set(material_param::softening_temperature, 400);
    sinter::material floor(ctx, "floor");
    floor.set(material_param::youngs_modulus, 1e13) // rigid
        .set(material_param::poisson_ratio, 0.3)
        .set(material_param::thermal_conductivity, 60);

    sinter::particles ps(ctx);
    ps.set_material(0, grain);
    ps.add({0.0, 0.0, radius}, {radius}, 0, theta_particle);

    sinter::walls ws(ctx);
    const std::size_t floor_index = ws.add_plane({0, 0, 0}, {0, 0, 1}, floor);
    ws.set_temperature(floor_index, theta_floor);

    sinter::force_model hertz(ctx, "hertz_mindlin"), gravity(ctx, "gravity");
    sinter::heat_model conduction(ctx, "conduction");
    // The stepper borrows everything above, so it is declared (and destroyed) last.
    sinter::stepper st(ctx, sinter::stepper_kind::explicit_, ps, ws);
    st.add(hertz).add(gravity).add(conduction).set_dt(dt);
    st.set_domain({-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01});

    result r;
    r.time.push_back(0);
    r.temperature.push_back(theta_particle);
    const int samples = static_cast<int>(std::lround(end_time / sample));
    for (int k = 1; k <= samples; ++k) {
        st.advance(k * sample);
        r.time.push_back(st.time());
        // a view borrowed for this block: released at its end, before the next advance()
        const auto theta = ps.view_read(sinter::field::temperature);
        r.temperature.push_back(theta(0));
    }
    r.force_z = ws.force(floor_index)[2];
    r.height = ps.view_read(sinter::field::position)(0, 2);
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
                    sinter::version_string(), weight);
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
