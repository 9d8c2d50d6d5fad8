// include/sinter.hpp, the C++17 layer: failing calls throw sinter::error with the status and the
// context's message; every handle frees what it owns (a counting allocator sees every block
// given back, and the sanitizer build runs this test too); moves transfer ownership; views are
// released; an observer's exception comes out of advance(); a small run gives the C API's
// result bit for bit.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <sinter.hpp>

namespace {

int failures = 0;

#define CHECK(cond)                                                                            \
    do {                                                                                       \
        if (!(cond)) {                                                                         \
            std::fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond);      \
            ++failures;                                                                        \
        }                                                                                      \
    } while (0)

// Run `f`, which must throw sinter::error with status `expected`; return the error's message.
template <typename F> std::string expect_error(sinter::status expected, F &&f, int line)
{
    try {
        f();
    } catch (const sinter::error &e) {
        if (e.code() != expected) {
            std::fprintf(stderr, "%s:%d: expected %s, got %s (%s)\n", __FILE__, line,
                         sinter::status_name(expected), sinter::status_name(e.code()), e.what());
            ++failures;
        }
        return e.message();
    } catch (const std::exception &e) {
        std::fprintf(stderr, "%s:%d: expected sinter::error, got %s\n", __FILE__, line, e.what());
        ++failures;
        return "";
    }
    std::fprintf(stderr, "%s:%d: expected sinter::error %s, nothing thrown\n", __FILE__, line,
                 sinter::status_name(expected));
    ++failures;
    return "";
}
#define EXPECT_ERROR(status, ...) expect_error(status, [&] { __VA_ARGS__; }, __LINE__)

bool contains(const std::string &s, const char *part) { return s.find(part) != std::string::npos; }

// --- a counting allocator: live blocks of the context ---------------------------------------

struct counts {
    long live = 0, total = 0;
};
void *count_alloc(std::size_t size, void *user)
{
    void *p = std::malloc(size);
    if (p != nullptr) {
        ++static_cast<counts *>(user)->live;
        ++static_cast<counts *>(user)->total;
    }
    return p;
}
void *count_realloc(void *ptr, std::size_t size, void *user)
{
    void *p = std::realloc(ptr, size);
    if (p != nullptr && ptr == nullptr) {
        ++static_cast<counts *>(user)->live;
        ++static_cast<counts *>(user)->total;
    }
    return p;
}
void count_free(void *ptr, void *user)
{
    if (ptr != nullptr)
        --static_cast<counts *>(user)->live;
    std::free(ptr);
}

// --- the enums carry the C values ------------------------------------------------------------

static_assert(static_cast<int>(sinter::status::invalid) == SINTER_ERR_INVALID);
static_assert(static_cast<int>(sinter::status::interrupted) == SINTER_ERR_INTERRUPTED);
static_assert(static_cast<int>(sinter::field::temperature) == SINTER_FIELD_TEMPERATURE);
static_assert(static_cast<int>(sinter::material_param::grain_boundary_mobile_fraction_hot) ==
              SINTER_MAT_GRAIN_BOUNDARY_MOBILE_FRACTION_HOT);
static_assert(static_cast<int>(sinter::stepper_kind::quasistatic) == SINTER_STEPPER_QUASISTATIC);
static_assert((sinter::particle_flag::fixed | sinter::particle_flag::no_rotation) ==
              static_cast<sinter::particle_flag>(SINTER_PARTICLE_FIXED |
                                                 SINTER_PARTICLE_NO_ROTATION));
// unique ownership: movable, not copyable
static_assert(!std::is_copy_constructible_v<sinter::particles>);
static_assert(std::is_nothrow_move_constructible_v<sinter::particles>);
static_assert(std::is_nothrow_move_assignable_v<sinter::stepper>);
static_assert(!std::is_copy_assignable_v<sinter::field_view<double>>);

constexpr double radius = 1e-3, density = 3000, dt = 2e-5;

void test_errors()
{
    sinter::context ctx;
    sinter::material grain(ctx, "grain");
    std::string message =
        EXPECT_ERROR(sinter::status::invalid, grain.set(sinter::material_param::density, -1));
    CHECK(contains(message, "density = -1 kg/m^3 is invalid"));
    CHECK(message == ctx.last_error());
    CHECK(ctx.last_status() == sinter::status::invalid);
    try {
        grain.set(sinter::material_param::density, -2);
    } catch (const sinter::error &e) {
        CHECK(e.function() == "sinter_material_set");
        CHECK(contains(e.what(), "sinter_material_set: material 'grain': density = -2"));
        CHECK(contains(e.what(), "[SINTER_ERR_INVALID]"));
    }
    CHECK(grain.get(sinter::material_param::density) > 0); // unchanged

    message = EXPECT_ERROR(sinter::status::not_found, sinter::force_model(ctx, "no_such_model"));
    CHECK(contains(message, "no force model is called 'no_such_model'"));
    CHECK(contains(message, "hertz_mindlin"));
    message = EXPECT_ERROR(sinter::status::io, sinter::scene(ctx, "/nonexistent/dir/x.scene"));
    CHECK(contains(message, "/nonexistent/dir/x.scene"));

    sinter::particles ps(ctx);
    ps.set_material(0, grain);
    message = EXPECT_ERROR(sinter::status::invalid, ps.add({0.0, 0.0, 0.0}, {-1.0}, 0, 300));
    CHECK(contains(message, "radius of new particle 0 is -1 m"));
    // sizes checked before the library is called
    message = EXPECT_ERROR(sinter::status::invalid, ps.add({0.0, 0.0}, {radius}, 0, 300));
    CHECK(contains(message, "3 per particle"));
    CHECK(ps.size() == 0);
    ps.add({0.0, 0.0, radius}, {radius}, 0, 300);
    CHECK(ps.size() == 1);
    // property tables: read back linearly, the enthalpy C theta for a constant C
    ps.set_property_table(0, sinter::property::thermal_conductivity, {300.0, 1300.0},
                          {400.0, 300.0});
    CHECK(ps.property_at(0, sinter::property::thermal_conductivity, 800.0) == 350.0);
    message = EXPECT_ERROR(sinter::status::invalid,
                           ps.set_property_table(0, sinter::property::heat_capacity, {300.0},
                                                 {1.0, 2.0}));
    CHECK(contains(message, "differ in size"));
    CHECK(ps.specific_enthalpy(0, 500.0) ==
          500.0 * grain.get(sinter::material_param::heat_capacity));

    {
        auto x = ps.view(sinter::field::position);
        message = EXPECT_ERROR(sinter::status::busy, ps.reserve(100));
        CHECK(contains(message, "still out"));
        // the element type must be the field's
        EXPECT_ERROR(sinter::status::invalid, ps.view<std::int32_t>(sinter::field::position));
    }
    ps.reserve(100); // the view was released by its destructor
    CHECK(ps.capacity() >= 100);

    // a moved-from handle refuses calls instead of passing NULL on
    sinter::particles moved = std::move(ps);
    CHECK(!ps && moved);
    EXPECT_ERROR(sinter::status::null, (void)ps.size());
    CHECK(moved.size() == 1);

    sinter::series s(ctx, {"t", "T"}, {"s", "K"});
    s.append({0.0, 300.0});
    EXPECT_ERROR(sinter::status::invalid, s.append({1.0}));
    CHECK(s.rows() == 1 && s.at(0, 1) == 300.0);
    EXPECT_ERROR(sinter::status::range, (void)s.at(5, 0));
}

void test_views_and_span()
{
    sinter::context ctx;
    sinter::material grain(ctx, "grain");
    grain.set(sinter::material_param::density, density);
    sinter::particles ps(ctx);
    ps.set_material(0, grain);
    const std::vector<double> x = {0, 0, 0, 3e-3, 0, 0};
    const double r[2] = {radius, 2 * radius};
    CHECK(ps.add(x, r, 0, 300) == 0);
    {
        sinter::field_view<double> t = ps.view(sinter::field::temperature);
        CHECK(t.count() == 2 && t.components() == 1 && t.values().size() == 2);
        for (double &v : t.values())
            v = 500;
        sinter::field_view<const double> pos = ps.view_read(sinter::field::position);
        CHECK(pos[1].size() == 3 && pos(1, 0) == 3e-3);
        sinter::field_view<const std::uint64_t> ids = ps.view_read<std::uint64_t>(sinter::field::id);
        CHECK(ids.count() == 2);
        sinter::field_view<const double> moved = std::move(pos);
        CHECK(moved(1, 0) == 3e-3 && pos.values().empty());
    }
    CHECK(ps.copy(sinter::field::temperature) == std::vector<double>({500, 500}));
    const std::vector<double> mass = ps.copy(sinter::field::mass);
    CHECK(std::fabs(mass[1] / mass[0] - 8) < 1e-12);
    ps.remove({std::size_t{0}});
    CHECK(ps.size() == 1);
}

// Every object freed by its destructor, moves included: the context's allocator has nothing out
// when only the context is left.
void test_raii_frees()
{
    counts c;
    sinter_allocator allocator{sizeof(sinter_allocator), count_alloc, count_realloc, count_free, &c};
    sinter::context ctx(&allocator);
    const long after_context = c.live;
    {
        sinter::material grain(ctx, "grain");
        sinter::material copy = grain.clone();
        sinter::particles ps(ctx);
        ps.set_material(0, copy);
        ps.add({0.0, 0.0, radius}, {radius}, 0, 300);
        sinter::walls ws(ctx);
        ws.add_plane({0, 0, 0}, {0, 0, 1}, grain);
        sinter::force_model hertz(ctx, "hertz_mindlin"), gravity(ctx, "gravity");
        sinter::heat_model conduction(ctx, "conduction");
        sinter::neck_model neck(ctx);
        sinter::series s(ctx, {"t"}, {"s"});
        s.append({1.0});
        sinter::stepper st(ctx, sinter::stepper_kind::explicit_, ps, ws);
        st.add(hertz).add(gravity).add(conduction).set_dt(dt);
        st.set_domain({-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01});
        st.set_observer([](double) { return false; });
        st.step(10);
        sinter::stepper other = std::move(st); // ownership moves; st holds nothing
        other.step(10);
        CHECK(c.live > after_context);
        sinter::particles ps2(ctx);
        ps2 = sinter::particles(ctx); // move assignment destroys the first set
        sinter_particles *raw = ps2.release();
        sinter_particles_destroy(raw);
        CHECK(other.stats().steps == 20);
    }
    CHECK(c.live == after_context);
    if (c.live != after_context)
        std::fprintf(stderr, "%ld blocks out after the objects' scope\n", c.live - after_context);
    CHECK(c.total > after_context);
}

// The observer: true stops advance(); an exception stops the run and comes out of advance().
void test_observer()
{
    sinter::context ctx;
    sinter::material grain(ctx, "grain");
    sinter::particles ps(ctx);
    ps.set_material(0, grain);
    ps.add({0.0, 0.0, 0.5}, {0.05}, 0, 300);
    sinter::force_model gravity(ctx, "gravity");
    sinter::stepper st(ctx, sinter::stepper_kind::explicit_, ps);
    st.add(gravity).set_dt(1e-3).set_domain({-1, -1, -1}, {1, 1, 1});
    int calls = 0;
    st.set_observer([&calls](double) { return ++calls == 5; });
    st.advance(1.0);
    CHECK(calls == 5);
    CHECK(std::fabs(st.time() - 5e-3) < 1e-12);
    st.set_observer([](double t) -> bool {
        if (t > 8e-3)
            throw std::runtime_error("observer says stop");
        return false;
    });
    bool caught = false;
    try {
        st.advance(1.0);
    } catch (const std::runtime_error &e) {
        caught = std::strcmp(e.what(), "observer says stop") == 0;
    }
    CHECK(caught);
    CHECK(st.time() < 1e-2);
    st.set_observer(nullptr);
    st.advance(2e-2);
    CHECK(std::fabs(st.time() - 2e-2) < 1e-12);
}

// A particle settling on a hot floor, through the C API and through sinter.hpp: the same bits.
struct outcome {
    std::vector<double> position, temperature;
    double force_z = 0;
};

outcome run_c()
{
    outcome r;
    sinter_ctx *ctx = nullptr;
    sinter_material *m = nullptr;
    sinter_particles *ps = nullptr;
    sinter_walls *ws = nullptr;
    sinter_force_model *hertz = nullptr, *gravity = nullptr;
    sinter_heat_model *conduction = nullptr;
    sinter_stepper *st = nullptr;
    const double x[3] = {0, 0, radius}, r0 = radius, origin[3] = {0, 0, 0}, up[3] = {0, 0, 1};
    const double lo[3] = {-0.01, -0.01, -0.01}, hi[3] = {0.01, 0.01, 0.01};
    size_t floor_index = 0;
    int bad = sinter_ctx_create(&ctx, nullptr) != SINTER_OK;
    bad = bad || sinter_material_create(&m, ctx, "grain") != SINTER_OK;
    bad = bad || sinter_material_set(m, SINTER_MAT_DENSITY, density) != SINTER_OK;
    bad = bad || sinter_material_set(m, SINTER_MAT_YOUNGS_MODULUS, 1e6) != SINTER_OK;
    bad = bad || sinter_material_set(m, SINTER_MAT_DAMPING_RATIO, 1.0) != SINTER_OK;
    bad = bad || sinter_material_set(m, SINTER_MAT_THERMAL_CONDUCTIVITY, 60) != SINTER_OK;
    bad = bad || sinter_material_set(m, SINTER_MAT_HEAT_CAPACITY, 100) != SINTER_OK;
    bad = bad || sinter_particles_create(&ps, ctx) != SINTER_OK;
    bad = bad || sinter_particles_set_material(ps, 0, m) != SINTER_OK;
    bad = bad || sinter_particles_add(ps, 1, x, &r0, 0, 300, nullptr) != SINTER_OK;
    bad = bad || sinter_walls_create(&ws, ctx) != SINTER_OK;
    bad = bad || sinter_walls_add_plane(ws, origin, up, m, &floor_index) != SINTER_OK;
    bad = bad || sinter_walls_set_temperature(ws, floor_index, 700) != SINTER_OK;
    bad = bad || sinter_force_model_create(&hertz, ctx, "hertz_mindlin") != SINTER_OK;
    bad = bad || sinter_force_model_create(&gravity, ctx, "gravity") != SINTER_OK;
    bad = bad || sinter_heat_model_create(&conduction, ctx, "conduction") != SINTER_OK;
    bad = bad || sinter_stepper_create(&st, ctx, SINTER_STEPPER_EXPLICIT, ps, ws) != SINTER_OK;
    bad = bad || sinter_stepper_add_force(st, hertz) != SINTER_OK;
    bad = bad || sinter_stepper_add_force(st, gravity) != SINTER_OK;
    bad = bad || sinter_stepper_add_heat(st, conduction) != SINTER_OK;
    bad = bad || sinter_stepper_set_dt(st, dt) != SINTER_OK;
    bad = bad || sinter_stepper_set_domain(st, lo, hi) != SINTER_OK;
    bad = bad || sinter_stepper_advance(st, 0.05) != SINTER_OK;
    double f[3] = {0, 0, 0};
    bad = bad || sinter_walls_get_force(ws, floor_index, f) != SINTER_OK;
    const void *data = nullptr;
    size_t n = 0, k = 0;
    if (!bad && sinter_particles_view_read(ps, SINTER_FIELD_POSITION, &data, &n, &k) == SINTER_OK) {
        r.position.assign(static_cast<const double *>(data), static_cast<const double *>(data) + n * k);
        sinter_particles_release(ps, SINTER_FIELD_POSITION);
    }
    if (!bad && sinter_particles_view_read(ps, SINTER_FIELD_TEMPERATURE, &data, &n, &k) == SINTER_OK) {
        r.temperature.assign(static_cast<const double *>(data),
                             static_cast<const double *>(data) + n * k);
        sinter_particles_release(ps, SINTER_FIELD_TEMPERATURE);
    }
    CHECK(!bad);
    r.force_z = f[2];
    sinter_stepper_destroy(st);
    sinter_heat_model_destroy(conduction);
    sinter_force_model_destroy(gravity);
    sinter_force_model_destroy(hertz);
    sinter_walls_destroy(ws);
    sinter_particles_destroy(ps);
    sinter_material_destroy(m);
    sinter_ctx_destroy(ctx);
    return r;
}

outcome run_cpp()
{
    using sinter::material_param;
    sinter::context ctx;
    sinter::material grain(ctx, "grain");
    grain.set(material_param::density, density)
        .set(material_param::youngs_modulus, 1e6)
        .set(material_param::damping_ratio, 1.0)
        .set(material_param::thermal_conductivity, 60)
        .set(material_param::heat_capacity, 100);
    sinter::particles ps(ctx);
    ps.set_material(0, grain);
    ps.add({0.0, 0.0, radius}, {radius}, 0, 300);
    sinter::walls ws(ctx);
    const std::size_t floor_index = ws.add_plane({0, 0, 0}, {0, 0, 1}, grain);
    ws.set_temperature(floor_index, 700);
    sinter::force_model hertz(ctx, "hertz_mindlin"), gravity(ctx, "gravity");
    sinter::heat_model conduction(ctx, "conduction");
    sinter::stepper st(ctx, sinter::stepper_kind::explicit_, ps, ws);
    st.add(hertz).add(gravity).add(conduction).set_dt(dt);
    st.set_domain({-0.01, -0.01, -0.01}, {0.01, 0.01, 0.01});
    st.advance(0.05);
    outcome r;
    r.position = ps.copy(sinter::field::position);
    r.temperature = ps.copy(sinter::field::temperature);
    r.force_z = ws.force(floor_index)[2];
    // a portable checkpoint of the run, restored into a stepper set up alike: the same particle
    const std::vector<unsigned char> part = st.save_global(), records = st.export_particles({0});
    sinter::particles ps2(ctx);
    ps2.set_material(0, grain);
    sinter::walls ws2(ctx);
    ws2.add_plane({0, 0, 0}, {0, 0, 1}, grain);
    sinter::stepper st2(ctx, sinter::stepper_kind::explicit_, ps2, ws2);
    sinter::force_model hertz2(ctx, "hertz_mindlin"), gravity2(ctx, "gravity");
    sinter::heat_model conduction2(ctx, "conduction");
    st2.add(hertz2).add(gravity2).add(conduction2).set_dt(dt);
    st2.load_global(part);
    CHECK(st2.import_particles(records) == 1);
    CHECK(ps2.copy(sinter::field::position) == r.position);
    return r;
}

void test_same_result_as_c()
{
    const outcome c = run_c(), cpp = run_cpp();
    CHECK(c.position.size() == 3 && c.temperature.size() == 1);
    CHECK(c.position == cpp.position);
    CHECK(c.temperature == cpp.temperature);
    CHECK(c.force_z == cpp.force_z);
    CHECK(cpp.temperature[0] > 300); // the floor heated it
    std::printf("C and C++: z = %.17g m, T = %.17g K, F_z = %.17g N\n", cpp.position[2],
                cpp.temperature[0], cpp.force_z);
}

// A mixture inserted by mass fraction: insertion_mixture() gives each material's mass, adding
// up to the mass inserted, each within one sphere's mass of its share (test_mixture.c has the
// physics; this checks the C++ wrapper).
void test_insertion_mixture()
{
    using sinter::material_param;
    sinter::context ctx;
    sinter::material a(ctx, "a"), b(ctx, "b");
    a.set(material_param::density, 2500).set(material_param::youngs_modulus, 1e6);
    b.set(material_param::density, 7500).set(material_param::youngs_modulus, 1e6);
    sinter::particles ps(ctx);
    ps.set_material(0, a);
    ps.set_material(1, b);
    sinter::walls ws(ctx);
    ws.add_plane({0, 0, 0}, {0, 0, 1}, a);
    sinter::force_model hertz(ctx, "hertz_mindlin"), gravity(ctx, "gravity");
    sinter::stepper st(ctx, sinter::stepper_kind::explicit_, ps, ws);
    st.add(hertz).add(gravity).set_dt(1e-5);
    CHECK(st.insertion_mixture().empty());
    sinter_packing_options powder;
    sinter_packing_options_init(&powder, sizeof(powder));
    const std::int32_t ids[2] = {0, 1};
    const double shares[2] = {0.4, 0.6}, r = 1e-3;
    powder.radius_mean = r;
    powder.box_min[0] = powder.box_min[1] = -0.02;
    powder.box_max[0] = powder.box_max[1] = 0.02;
    powder.box_min[2] = 0.01;
    powder.box_max[2] = 0.02;
    powder.mixture_count = 2;
    powder.mixture_materials = ids;
    powder.mixture_mass_fractions = shares;
    sinter_insertion_options options;
    sinter_insertion_options_init(&options, sizeof(options));
    options.mass_rate = 0.05;
    st.set_insertion(&powder, &options);
    st.advance(0.0105);
    const std::vector<double> mass = st.insertion_mixture();
    CHECK(mass.size() == 2);
    const double pi = 3.14159265358979323846, m_max = 7500 * 4.0 / 3.0 * pi * r * r * r;
    const double total = mass.size() == 2 ? mass[0] + mass[1] : 0.0;
    CHECK(total > 10 * m_max);
    for (std::size_t k = 0; k < mass.size(); ++k)
        CHECK(std::fabs(mass[k] - shares[k] * total) <= m_max);
}

} // namespace

int main()
{
    std::printf("libsinter %s (sinter.hpp)\n", sinter::version_string());
    test_errors();
    test_views_and_span();
    test_raii_frees();
    test_observer();
    test_same_result_as_c();
    test_insertion_mixture();
    if (failures != 0) {
        std::fprintf(stderr, "%d check(s) failed\n", failures);
        return 1;
    }
    std::printf("all checks passed\n");
    return 0;
}
