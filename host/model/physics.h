/* physics.h — the physics source's point functions, evaluated on the host.
 *
 * The modules around a run that need a value of the physics itself (the
 * kernel's W and dW for the relaxation, the observers' weights, the
 * artificial stress's W(dp); the stress of a snapshot or a traction
 * observer; the monitor's measures of the particle that tripped it; the
 * unit tests' probes) call device/ through this table, not through a
 * backend: it is the same source the backends run, compiled as C
 * (host/backend/cpu/backend_cpu_kernels.c fills it for each instance;
 * sph_physics_for picks one).  Arguments and results are double whatever
 * the instance's precision.
 */
#ifndef SPH_PHYSICS_H
#define SPH_PHYSICS_H

#include "sph_params.h"

#include <stdbool.h>
#include <stdint.h>

typedef struct {
    int dim;               /* of the instance */
    bool double_precision; /* its arithmetic (single in the f32 instance) */
    /* the monitor's measures of particle i alone, from host copies of the
     * fields (double, field layout) and row-major neighbour lists: which
     * particle tripped a check (host/run/instability.c) */
    void (*monitor_particle)(const sph_params_f64 *prm, int n, int cap, const int32_t *nbr_count,
                             const int32_t *nbr_j, const double *pos, const double *vel,
                             const double *vol, const double *bmat, int i, double *out);
    double (*kernel_w)(const sph_params_f64 *prm, double r);
    double (*kernel_dw)(const sph_params_f64 *prm, double r);
    /* the kernel integrated over a plane at the distance d (sph_wall.h) */
    double (*wall_plane_kernel)(const sph_params_f64 *prm, double d);
    /* the ideal gas's sound speed sqrt(gamma p / rho) (sph_eulerian.h) */
    double (*ideal_gas_sound_speed)(double p, double rho, double gamma);
    /* Rodrigues matrix (row-major dim x dim) of spin components w over dt */
    void (*rodrigues)(const double *w, double dt, double *rot);
    /* pair terms of sph_riemann.h for states i, j (vectors of length dim) */
    void (*riemann_pair)(const double *v_i, const double *v_j, double p_i, double p_j, double z,
                         double dw, const double *e_ij, double *pressure, double *dissipation,
                         double *continuity);
    /* snapshot fields from rho and tau (host arrays, tau in field layout)
     * and the material rows (NULL: row 0); any output may be NULL:
     * pressure [n], von Mises [n], tau [n][6] */
    void (*stress_output)(const sph_params_f64 *prm, int n, const double *rho, const double *tau,
                          const uint8_t *material, double *pressure, double *von_mises,
                          double *tensor6);
    /* one substep of a material point's shear stress: Jaumann rate and, when
     * alpha is given, the J2 return with row 0 of the material table
     * (row-major) */
    void (*stress_update)(const sph_params_f64 *prm, const double *grad_v, double dt, double *tau,
                          double *alpha);
    /* artificial stress of one particle (OAS), row-major d x d */
    void (*artificial_stress)(const double *tau, double p, double rho, double epsilon, double *r);
    /* TLSPH finite-strain J2 update of a material point (tl_j2_kirchhoff):
     * f row-major d x d; state = C_p^-1 (row-major d x d), (C_p^-1)_zz,
     * alpha, updated in place; tau = Kirchhoff stress (row-major d x d),
     * then tau_zz.  Returns 1 when it yielded. */
    int (*tl_j2_update)(const sph_params_f64 *prm, const double *f, double *state, double *tau);
} sph_physics;

/* The point functions of a dimension in double or single precision (the
 * SPH-ENOG instance's; in 1D, where only the fluids exist, the weakly
 * compressible one's, double only); NULL where there is none. */
const sph_physics *sph_physics_for(int dim, bool double_precision);

#endif
