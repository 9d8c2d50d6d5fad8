/*
 * A first libsinter program: make a material, put a small cubic lattice of
 * copper-like particles in a set, and report their total mass.
 * Uses only the public header.
 */
#include <stdio.h>

#include <sinter.h>

static int check(sinter_ctx *ctx, sinter_status st, const char *what)
{
    if (st == SINTER_OK)
        return 0;
    fprintf(stderr, "%s failed: %s (%s)\n", what, sinter_status_string(st), sinter_last_error(ctx));
    return 1;
}

int main(void)
{
    sinter_ctx *ctx = NULL;
    sinter_material *copper = NULL;
    sinter_particles *ps = NULL;
    if (sinter_ctx_create(&ctx, NULL) != SINTER_OK)
        return 1;
    printf("libsinter %s\n", sinter_version_string());

    int fail = check(ctx, sinter_material_create(&copper, ctx, "copper"), "material_create");
    fail = fail || check(ctx, sinter_material_set(copper, SINTER_MAT_DENSITY, 8960.0), "density");
    fail = fail || check(ctx, sinter_material_set(copper, SINTER_MAT_YOUNGS_MODULUS, 110e9), "E");
    fail = fail || check(ctx, sinter_particles_create(&ps, ctx), "particles_create");
    fail = fail || check(ctx, sinter_particles_set_material(ps, 0, copper), "set_material");

    enum { n = 4 };
    const double radius = 25e-6; /* m */
    double positions[3 * n * n * n], radii[n * n * n];
    int k = 0;
    for (int iz = 0; iz < n; ++iz)
        for (int iy = 0; iy < n; ++iy)
            for (int ix = 0; ix < n; ++ix, ++k) {
                positions[3 * k + 0] = (2 * ix + 1) * radius;
                positions[3 * k + 1] = (2 * iy + 1) * radius;
                positions[3 * k + 2] = (2 * iz + 1) * radius;
                radii[k] = radius;
            }
    fail = fail || check(ctx, sinter_particles_add(ps, n * n * n, positions, radii, 0, 293.15, NULL),
                         "particles_add");

    if (!fail) {
        const double *mass = NULL;
        size_t count = 0;
        fail = check(ctx, sinter_particles_view_read(ps, SINTER_FIELD_MASS, (const void **)&mass,
                                                     &count, NULL),
                     "view_read");
        if (!fail) {
            double total = 0.0;
            for (size_t i = 0; i < count; ++i)
                total += mass[i];
            sinter_particles_release(ps, SINTER_FIELD_MASS);
            printf("%zu particles of r = %g m, total mass %.6e kg\n", count, radius, total);
        }
    }
    sinter_particles_destroy(ps);
    sinter_material_destroy(copper);
    sinter_ctx_destroy(ctx);
    return fail;
}
