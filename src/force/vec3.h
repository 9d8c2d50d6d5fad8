/* Small 3-vector helpers for the contact laws and the bonded links. */
#ifndef SINTER_VEC3_H
#define SINTER_VEC3_H

static inline double v3_dot(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void v3_cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static inline double v3_norm(const double a[3])
{
    return __builtin_sqrt(v3_dot(a, a));
}

#endif
