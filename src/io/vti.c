/* The coarse-grained fields as VTK XML ImageData (io/vti.h). */
#include <sinter_domain.h>

#include "io/series.h"
#include "io/vti.h"
#include "io/vtk_arrays.h"

sinter_status sinter_vti_write_fields(sinter_ctx *ctx, const char *path,
                                      const sinter_coarse_options *grid,
                                      const sinter_coarse_fields *fields, int binary)
{
    sinter_out_file out;
    sinter_status st = sinter_out_open(&out, ctx, "sinter_vti_write_fields", path);
    if (st != SINTER_OK)
        return st;
    FILE *fp = out.fp;
    const size_t *n = grid->points;
    char extent[128];
    snprintf(extent, sizeof(extent), "0 %zu 0 %zu 0 %zu", n[0] - 1, n[1] - 1, n[2] - 1);
    fprintf(fp,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"ImageData\" version=\"%s\" byte_order=\"LittleEndian\"%s>\n"
            "  <ImageData WholeExtent=\"%s\" Origin=\"",
            (binary & SINTER_VTK_BINARY) ? "1.0" : "0.1",
            (binary & SINTER_VTK_BINARY) ? " header_type=\"UInt64\"" : "", extent);
    for (int d = 0; d < 3; ++d) {
        sinter_out_double(fp, grid->origin[d]);
        fputs(d < 2 ? " " : "\" Spacing=\"", fp);
    }
    for (int d = 0; d < 3; ++d) {
        sinter_out_double(fp, grid->spacing[d]);
        fputs(d < 2 ? " " : "\">\n", fp);
    }
    fprintf(fp,
            "    <Piece Extent=\"%s\">\n"
            "      <PointData Scalars=\"solid_fraction\" Vectors=\"velocity\" "
            "Tensors=\"stress\">\n",
            extent);
    const double *arrays[SINTER_COARSE_COUNT_] = {
        fields->solid, fields->density, fields->temperature, fields->velocity, fields->stress};
    for (int q = 0; q < SINTER_COARSE_COUNT_; ++q) {
        const char *name = NULL;
        size_t components = 0;
        (void)sinter_coarse_quantity_info((sinter_coarse_quantity)q, &name, NULL, &components);
        sinter_vtk_doubles(fp, name, arrays[q], fields->points, components, binary);
    }
    fputs("      </PointData>\n"
          "      <CellData>\n"
          "      </CellData>\n"
          "    </Piece>\n"
          "  </ImageData>\n"
          "</VTKFile>\n",
          fp);
    return sinter_out_close(&out, SINTER_OK);
}

sinter_status sinter_write_vti_sums(sinter_ctx *ctx, const char *path,
                                    const sinter_coarse_options *options, const double *sums,
                                    size_t sums_count, int flags)
{
    static const char *const fn = "sinter_write_vti_sums";
    if (ctx == NULL)
        return SINTER_ERR_NULL;
    SINTER_CHECK_NULL(ctx, path);
    SINTER_CHECK_NULL(ctx, options);
    SINTER_CHECK_NULL(ctx, sums);
    sinter_status st = sinter_coarse_check(ctx, fn, options);
    if (st != SINTER_OK)
        return st;
    const size_t points = options->points[0] * options->points[1] * options->points[2];
    if (sums_count != points * SINTER_COARSE_SUMS)
        return sinter_fail(ctx, SINTER_ERR_INVALID,
                           "%s: sums_count is %zu, the grid's %zu points need %zu", fn, sums_count,
                           points, points * SINTER_COARSE_SUMS);
    if (flags < 0 || flags > (SINTER_VTK_BINARY | SINTER_VTK_FLOAT32))
        return sinter_fail(ctx, SINTER_ERR_INVALID, "%s: flags is %d, expected 0 to 3", fn, flags);
    sinter_coarse_fields fields;
    st = sinter_coarse_fields_from_sums(ctx, points, sums, &fields);
    if (st != SINTER_OK)
        return st;
    st = sinter_vti_write_fields(ctx, path, options, &fields, flags);
    sinter_coarse_fields_free(ctx, &fields);
    return st;
}
