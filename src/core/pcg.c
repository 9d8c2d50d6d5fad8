/* SUNDIALS PCG behind a small matrix-free interface (see pcg.h). */
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_pcg.h>

#include "pcg.h"

#include "core/clones.h"
#include "core/two_parts.h"

struct sinter_pcg {
    sinter_ctx *ctx;
    SUNContext sunctx;
    SUNLinearSolver solver;
    N_Vector x, b;
    size_t n;
    int max_iterations;
    /* the operator of the solve under way */
    sinter_pcg_operator apply, precondition;
    void *data;
    /* the unknowns in three parts [0, part_a), [part_a, part_b), [part_b, n) (both 0: one);
     * part_threads 2: the second part on a second thread */
    size_t part_a, part_b;
    int part_threads;
    /* spread over subdomains (sinter_pcg_set_sum): dot products over [0, counted) summed by
     * sum (NULL: local) */
    sinter_pcg_sum sum;
    void *sum_data;
    size_t counted;
    /* the reproducible mode (sinter_pcg_set_dot): every dot product through dot (NULL: off) */
    sinter_pcg_dot_fn dot;
    void *dot_data;
};

/* The solve under way on this thread: SUNDIALS calls the vector operations below without a
 * way to reach it. */
static _Thread_local const sinter_pcg *active_solve;

void sinter_pcg_free(sinter_pcg *pcg)
{
    if (pcg == NULL)
        return;
    if (pcg->solver)
        SUNLinSolFree(pcg->solver);
    if (pcg->x)
        N_VDestroy(pcg->x);
    if (pcg->b)
        N_VDestroy(pcg->b);
    if (pcg->sunctx)
        SUNContext_Free(&pcg->sunctx);
    sinter_free(pcg->ctx, pcg);
}

/*
 * SUNDIALS' serial dot product adds one product at a time to one sum: on the copper packing
 * (seed 001, 4830 unknowns, about 180 iterations a solve) its three dot products an iteration
 * took a quarter of the whole run, more than the link operator (issue 9). Eight lanes, each
 * summed in order and joined in a fixed tree, let the compiler use vector registers: the sum's
 * rounding differs from the one-chain sum's, not its value beyond it, and it is the same on
 * every run and thread count.
 */
SINTER_CLONES
double sinter_pcg_dot(const double *restrict x, const double *restrict y, size_t n)
{
    enum { LANES = 8 };
    double lane[LANES] = {0.0};
    size_t i = 0;
    for (; i + LANES <= n; i += LANES)
        for (int k = 0; k < LANES; ++k)
            lane[k] += x[i + (size_t)k] * y[i + (size_t)k];
    double sum =
        ((lane[0] + lane[4]) + (lane[1] + lane[5])) + ((lane[2] + lane[6]) + (lane[3] + lane[7]));
    for (; i < n; ++i)
        sum += x[i] * y[i];
    return sum;
}

/* z = a x + b y, elementwise (z may be x or y). */
SINTER_CLONES
void sinter_pcg_linear_sum(double a, const double *x, double b, const double *y, double *z,
                           size_t n)
{
    for (size_t i = 0; i < n; ++i)
        z[i] = a * x[i] + b * y[i];
}

static void scale(double c, const double *x, double *z, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        z[i] = c * x[i];
}

/* The three parts of a solve with parts (sinter_pcg_set_parts): the operation `op` on each,
 * the second on the second thread when there are two. Each part's result is the same on one
 * thread or two. */
enum part_op { PART_DOT, PART_LINEAR_SUM, PART_SCALE };

static void part_run(enum part_op op, double a, const double *x, double b, const double *y,
                     double *z, size_t lo, size_t hi, double *dot)
{
    if (op == PART_DOT)
        *dot = sinter_pcg_dot(x + lo, y + lo, hi - lo);
    else if (op == PART_LINEAR_SUM)
        sinter_pcg_linear_sum(a, x + lo, b, y + lo, z + lo, hi - lo);
    else
        scale(a, x + lo, z + lo, hi - lo);
}

/* The arguments of parts_run for sinter_two_parts. */
typedef struct part_work {
    const sinter_pcg *p;
    enum part_op op;
    double a, b;
    const double *x, *y;
    double *z;
    double dot[3];
} part_work;

static void first_two_parts(void *data, int which)
{
    part_work *w = data;
    const size_t lo = which ? w->p->part_a : 0, hi = which ? w->p->part_b : w->p->part_a;
    part_run(w->op, w->a, w->x, w->b, w->y, w->z, lo, hi, &w->dot[which]);
}

static double parts_run(const sinter_pcg *p, enum part_op op, double a, const double *x, double b,
                        const double *y, double *z)
{
    part_work w = {p, op, a, b, x, y, z, {0.0, 0.0, 0.0}};
    sinter_two_parts(p->part_threads, first_two_parts, &w);
    part_run(op, a, x, b, y, z, p->part_b, p->n, &w.dot[2]);
    return (w.dot[0] + w.dot[1]) + w.dot[2];
}

/* The solve under way if it has parts (sinter_pcg_set_parts), else NULL. */
static const sinter_pcg *parted_solve(void)
{
    const sinter_pcg *p = active_solve;
    return p != NULL && p->part_b > 0 ? p : NULL;
}

static realtype dot_op(N_Vector x, N_Vector y)
{
    const sinter_pcg *g = active_solve;
    if (g != NULL && g->dot != NULL)
        return g->dot(NV_DATA_S(x), NV_DATA_S(y), g->counted, g->dot_data);
    if (g != NULL && g->sum != NULL)
        return g->sum(sinter_pcg_dot(NV_DATA_S(x), NV_DATA_S(y), g->counted), g->sum_data);
    const sinter_pcg *p = parted_solve();
    if (p != NULL)
        return parts_run(p, PART_DOT, 0.0, NV_DATA_S(x), 0.0, NV_DATA_S(y), NULL);
    return sinter_pcg_dot(NV_DATA_S(x), NV_DATA_S(y), (size_t)NV_LENGTH_S(x));
}

static void linear_sum_op(realtype a, N_Vector x, realtype b, N_Vector y, N_Vector z)
{
    const sinter_pcg *p = parted_solve();
    if (p != NULL)
        parts_run(p, PART_LINEAR_SUM, a, NV_DATA_S(x), b, NV_DATA_S(y), NV_DATA_S(z));
    else
        sinter_pcg_linear_sum(a, NV_DATA_S(x), b, NV_DATA_S(y), NV_DATA_S(z),
                              (size_t)NV_LENGTH_S(z));
}

static void scale_op(realtype c, N_Vector x, N_Vector z)
{
    const sinter_pcg *p = parted_solve();
    if (p != NULL)
        parts_run(p, PART_SCALE, c, NV_DATA_S(x), 0.0, NULL, NV_DATA_S(z));
    else
        scale(c, NV_DATA_S(x), NV_DATA_S(z), (size_t)NV_LENGTH_S(z));
}

static int apply_trampoline(void *data, N_Vector v, N_Vector z)
{
    const sinter_pcg *pcg = data;
    pcg->apply(N_VGetArrayPointer(v), N_VGetArrayPointer(z), pcg->data);
    return 0;
}

static int precondition_trampoline(void *data, N_Vector r, N_Vector z, realtype tol, int lr)
{
    (void)tol;
    (void)lr;
    const sinter_pcg *pcg = data;
    pcg->precondition(N_VGetArrayPointer(r), N_VGetArrayPointer(z), pcg->data);
    return 0;
}

sinter_status sinter_pcg_reserve(sinter_ctx *ctx, sinter_pcg **pcg, size_t n, int max_iterations)
{
    if (*pcg != NULL && (*pcg)->n == n && (*pcg)->max_iterations == max_iterations)
        return SINTER_OK;
    sinter_pcg_free(*pcg);
    *pcg = NULL;
    sinter_pcg *p = sinter_calloc(ctx, 1, sizeof(*p));
    if (p == NULL)
        return sinter_last_status(ctx);
    p->ctx = ctx;
    p->n = n;
    p->max_iterations = max_iterations;
    int ok = SUNContext_Create(NULL, &p->sunctx) == 0;
    if (ok) {
        p->x = N_VNew_Serial((sunindextype)n, p->sunctx);
        p->b = N_VNew_Serial((sunindextype)n, p->sunctx);
        ok = p->x != NULL && p->b != NULL;
    }
    if (ok) { /* the solver's work vectors are clones of x: they take these operations */
        p->x->ops->nvdotprod = dot_op;
        p->x->ops->nvlinearsum = linear_sum_op;
        p->x->ops->nvscale = scale_op;
    }
    if (ok) {
        p->solver = SUNLinSol_PCG(p->x, SUN_PREC_LEFT, max_iterations, p->sunctx);
        ok = p->solver != NULL && SUNLinSolSetATimes(p->solver, p, apply_trampoline) == 0 &&
             SUNLinSolSetPreconditioner(p->solver, p, NULL, precondition_trampoline) == 0 &&
             SUNLinSolInitialize(p->solver) == 0;
    }
    if (!ok) {
        sinter_pcg_free(p);
        return sinter_fail(ctx, SINTER_ERR_NOMEM,
                           "could not create a SUNDIALS PCG solver for %zu unknowns", n);
    }
    *pcg = p;
    return SINTER_OK;
}

double *sinter_pcg_rhs(sinter_pcg *pcg)
{
    return N_VGetArrayPointer(pcg->b);
}

double *sinter_pcg_solution(sinter_pcg *pcg)
{
    return N_VGetArrayPointer(pcg->x);
}

void sinter_pcg_set_parts(sinter_pcg *pcg, size_t a, size_t b, int threads)
{
    const int valid = a <= b && b <= pcg->n;
    pcg->part_a = valid ? a : 0;
    pcg->part_b = valid ? b : 0;
    pcg->part_threads = valid && threads >= 2 && a > 0 && b > a ? 2 : 1;
}

void sinter_pcg_set_sum(sinter_pcg *pcg, sinter_pcg_sum sum, void *data, size_t counted)
{
    pcg->sum = sum;
    pcg->sum_data = data;
    pcg->counted = counted <= pcg->n ? counted : pcg->n;
}

void sinter_pcg_set_dot(sinter_pcg *pcg, sinter_pcg_dot_fn dot, void *data, size_t counted)
{
    pcg->dot = dot;
    pcg->dot_data = data;
    pcg->counted = counted <= pcg->n ? counted : pcg->n;
}

int sinter_pcg_solve(sinter_pcg *pcg, sinter_pcg_operator apply, sinter_pcg_operator precondition,
                     void *data, double tol, int *iterations, double *residual)
{
    pcg->apply = apply;
    pcg->precondition = precondition;
    pcg->data = data;
    const sinter_pcg *outer = active_solve;
    active_solve = pcg;
    const int rc = SUNLinSolSolve(pcg->solver, NULL, pcg->x, pcg->b, tol);
    active_solve = outer;
    if (iterations)
        *iterations = SUNLinSolNumIters(pcg->solver);
    if (residual)
        *residual = SUNLinSolResNorm(pcg->solver);
    return rc;
}
