/* Private view of a material: the parameter table and the struct. */
#ifndef SINTER_MATERIAL_H
#define SINTER_MATERIAL_H

#include "core/core.h"

#define SINTER_MATERIAL_NAME_SIZE 64

struct sinter_material {
    sinter_ctx *ctx;
    char name[SINTER_MATERIAL_NAME_SIZE];
    double value[SINTER_MAT_PARAM_COUNT_];
};

/* Fill `values` with every parameter's default. */
void sinter_material_defaults(double values[SINTER_MAT_PARAM_COUNT_]);

/* Check one value against a parameter's range; 0 if valid. */
int sinter_material_value_valid(sinter_material_param param, double value);

#endif
