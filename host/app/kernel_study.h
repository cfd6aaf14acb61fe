/* kernel_study.h — the kernel study of 004 §2.2-2.3 (Tables 1-4, Fig. 2):
 * `sphsolid kernel-study`.
 *
 * A disc of diameter D = 2 is relaxed with each kernel (host/setup/relax.c, the
 * project's own relaxation, in double on the host) at each kappa = h/dp,
 * with h held at 1.3 dp_ref (dp = h / kappa, so the smoothing error is the
 * same for every kappa, 004 §2.2), and on the relaxed particles away from
 * the surface it measures
 *
 *   the truncation error of df/dx, 004 eq. 6:
 *     e_i = | grad f_i - sum_j (f_i + f_j) G_ij V_j |,
 *     G_ij = grad_i W_ij (Table 1, 3) or B_i grad_i W_ij (Table 2, 4),
 *     B_i = -( sum_j r_ij (x) grad_i W_ij V_j )^-1 (004 eq. 5),
 *   for f = 1 and f = sin(2 pi x); L1 = mean_i e_i, Linf = max_i e_i;
 *   the relaxation residue |2 sum_j V_j grad_i W_ij| (004 eq. 4, Fig. 2):
 *     its mean and max - min.
 *
 * Output (DIR, default "runs/kernel-study"): kernel_study.json and one
 * residues_<kernel>_<kappa>.csv per case (x, y, residue, interior) for the
 * figure; every file is written as FILE.partial and renamed once all are
 * complete.  docs/kernel-study.md describes the definitions and choices.
 */
#ifndef SPH_KERNEL_STUDY_H
#define SPH_KERNEL_STUDY_H

/* `sphsolid kernel-study [--out DIR] [--dp X] [--kappas list] [--kernels
 * list] [--steps N] [--seed S]`: returns the exit status (0; 1 runtime or
 * I/O failure; 2 bad flags). */
int sph_kernel_study_main(int argc, char **argv);

#endif
