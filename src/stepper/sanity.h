/*
 * Sanity checks of the steppers (sanity.c): a bad starting state is refused before the first
 * step, and a trial step that shows an instability is rejected, with a message that names the
 * particle or pair, the quantity and the time. The limits are justified in sanity.c.
 */
#ifndef SINTER_SANITY_H
#define SINTER_SANITY_H

#include "core/core.h"

/* Largest growth of one contact's overlap in one step, as a fraction of the smaller radius. */
#define SINTER_SANITY_APPROACH_LIMIT 0.5
/* Criterion 4: a particle's kinetic energy gain in one step beyond this many times the elastic
 * energy of its contacts at the start and at the end of the step is energy created. */
#define SINTER_SANITY_ENERGY_FACTOR 2.0
/* ... and beyond this fraction of its (and its contact partners') kinetic energy at t. */
#define SINTER_SANITY_ENERGY_GROWTH 0.5
/* ... and beyond this fraction of the least elastic energy of a contact at the stable step's
 * reference overlap (the check's resolution: stable_step.c). */
#define SINTER_SANITY_ENERGY_FLOOR 1e-3
/* Largest temperature a particle may reach [K]. */
#define SINTER_SANITY_MAX_TEMPERATURE 1e5

struct sinter_stepper;

/* What an integrator pass already measured for criterion 2: the largest squared
 * displacement of a centre in the step and the smallest radius (saves a pass). */
typedef struct sinter_sanity_scan {
    double moved2; /* max over particles of |x(t + h) - x(t)|^2 [m^2] */
    double rmin;   /* smallest radius [m] */
} sinter_sanity_scan;

/*
 * The state a stepper starts from (its contact lists just evaluated): a particle whose centre
 * is behind a wall (on the side its normal points away from) and two particles with the same
 * centre are refused with SINTER_ERR_INVALID naming them.
 */
sinter_status sinter_sanity_start(struct sinter_stepper *st);

/*
 * A trial step from t to t + h whose new state (positions, temperatures, contact lists) is in
 * the stepper; x_old holds the positions at t (3 per particle). Rejected, with the last
 * accepted state to be restored by the caller:
 *   - a particle centre behind a wall (it passed through): SINTER_ERR_LOST_PARTICLE;
 *   - a contact whose overlap grew by more than SINTER_SANITY_APPROACH_LIMIT of the smaller
 *     radius in this one step: SINTER_ERR_UNSTABLE;
 *   - a free temperature not in (0, SINTER_SANITY_MAX_TEMPERATURE]: SINTER_ERR_UNSTABLE.
 * `scan` (may be NULL: then measured here) is the integrator's measure of the step.
 */
sinter_status sinter_sanity_step(struct sinter_stepper *st, const double *x_old, double t,
                                 double h, const sinter_sanity_scan *scan);

/*
 * Criterion 4 of sanity.c (the explicit stepper, option "energy_check", on by default), after
 * an accepted-looking trial step from t to t + h whose state at t is in the stepper's spare
 * arrays (x, v, w): a particle whose kinetic energy more than doubled in the step, beyond the
 * work of gravity, body forces and the drag's medium, while it and its contact partners (in
 * their centre-of-mass frame, or the walls' when one touches a wall) gained more than
 * SINTER_SANITY_ENERGY_FACTOR times the elastic energy of their contacts at t and at t + h and
 * a bound of the work of their contacts with other particles, plus SINTER_SANITY_ENERGY_GROWTH
 * times their kinetic energy at t (a gain below st->energy_floor is not examined), is
 * SINTER_ERR_UNSTABLE naming it (and a few others), the energies and the time. Particles
 * touching a moving wall are not examined (the wall's work is not known here), nor any when a
 * host model computes contact forces.
 */
sinter_status sinter_sanity_energy(struct sinter_stepper *st, double t, double h);

/*
 * The stepper's domain (sinter_stepper_set_domain; none: nothing to check) after a trial
 * `step` ("step", "staggered step") from t to t + h: a particle whose centre is not inside it
 * (a non-finite centre is not) is SINTER_ERR_LOST_PARTICLE naming the one of lowest index and
 * its first axis outside. Tested on the contact law's particle ranges (contact/particle_pass.h).
 */
sinter_status sinter_sanity_domain(struct sinter_stepper *st, const char *step, double t,
                                   double h);

/*
 * sinter_sanity_domain after an explicit step whose largest displacement of a centre was
 * `moved` [m]: the full test runs only when the displacements summed since the last full test
 * reach the smallest distance of a centre to the domain's faces then, so that no particle can
 * have left the domain unseen; the same verdict at the same step as a test every step (a
 * non-finite `moved` tests). Particles added, removed, reordered or written: tested.
 */
sinter_status sinter_sanity_domain_moved(struct sinter_stepper *st, const char *step, double t,
                                         double h, double moved);

#endif
