/* sph_constraints.h — kinematic constraints, applied where a substep
 * advances the particles (acoustic_step.cl, tl_step.cl).
 *
 * A constrained particle (fixed[i] = k + 1) follows entry k of the
 * constraint table of the parameter block (sph_params.h): along each axis of its mask
 * the velocity is the prescribed one (0: a clamp or a roller) and the
 * position advances with it, x <- x + dt v, exactly (a clamp keeps its
 * position bit for bit); along the other axes it moves with the solution.
 * This is how the reference code imposes its clamps and supports
 * (FixBodyPartConstraint, FixedInAxisDirection: the velocity is reset after
 * the update); a prescribed velocity (tensile pull, punch) is the same with
 * a non-zero value. */
#ifndef SPH_CONSTRAINTS_H
#define SPH_CONSTRAINTS_H

#include "sph_vec.h"

/* Along the constrained axes: the prescribed velocity, and the step dx the
 * position takes with it (dt v). */
FN void apply_constraint(CONSTANT sph_params *prm, const int fixed, const real dt, vec *dx,
                         vec *v_new) {
    if (fixed == 0) return;
    CONSTANT sph_params_constraint *row = &prm->constraints[fixed - 1];
    const int mask = row->axis_mask;
    UNROLL for (int a = 0; a < SPH_DIM; ++a) {
        if (!(mask & (1 << a))) continue;
        v_new->c[a] = row->velocity[a];
        dx->c[a] = dt * row->velocity[a];
    }
}

/* The particle update of an acoustic substep, shared by the updated- and
 * total-Lagrangian schemes: position Verlet (000 eqs. 27-29) with gravity,
 *     v <- v + dt (a + g),   x <- x + dt/2 (v_old + v_new),
 * then the particle's constraint.  `fixed` is absent (0) in scenes without
 * constraints.  The position is a history field (hreal): the step is added
 * in its precision. */
FN void verlet_advance(CONSTANT sph_params *prm, const int n, const int i, const real dt, vec acc,
                       GLOBAL hreal *pos, GLOBAL real *vel, GLOBAL const u8 *fixed) {
    acc = vec_add(acc, gravity_of(prm));
    const vec v_old = vec_load(vel, n, i);
    vec v_new = vec_axpy(v_old, dt, acc);
    vec dx = vec_scale(vec_add(v_old, v_new), R(0.5) * dt);
#if SPH_HAS_CLAMP
    if (PRESENT(fixed)) apply_constraint(prm, fixed[i], dt, &dx, &v_new);
#else
    (void)fixed;
#endif
    vec_store(vel, n, i, v_new);
    hvec_add_store(pos, n, i, dx);
}

#endif
