#!/usr/bin/python3
"""kernel_lattice_stiffness.py -- the ENOG Laplacian's stiffness on a square lattice, per kernel.

SPH-ENOG's shear acceleration is the accumulated Laplacian (000 eq. 23-24)
    sum_j (e_ij . v_ij) / r_ij dW/dr V_j e_ij,
which for a plane wave u exp(i k.x) on the 2D square lattice (spacing 1, V_j = 1) is -D(k) u,
    D(k) = sum_j w_j (1 - cos k.r_j) e_j (x) e_j,   w_j = -(dW/dr)(r_j) / r_j.
The accumulated force restores every mode only if D(k) is positive semi-definite: a kernel
with dW/dr > 0 at a lattice distance can make it negative (an unstable lattice). Prints, for
each kernel of device/sph_smoothing_kernel.h and h/dp, the smallest eigenvalue of D over the
Brillouin zone and the long-wave stiffness D(k)/|k|^2 along x (shear, longitudinal).

It also gives the acoustic time step each kernel stands.  The linearised acoustic substep on
the lattice (rho0 = 1, K = rho0 c0^2 = 1, G/K from --nu, xi_E = 3.5) is u'' = -M(k) u with
    M(k) = K s s^T + 2 xi_E G D(k),   s = sum_j grad W(r_j) sin(k.r_j)
(continuity then pressure gradient, and the ENOG Laplacian); leapfrog is stable while
dt < 2 / omega_max, omega_max^2 the largest eigenvalue of M over the zone, i.e. for an
acoustic CFL (dt = CFL h / c0) below 2 / (omega_max h).  The scheme applies the ENOG
acceleration one substep late, which lowers the real limit further.
Usage: tools/kernel_lattice_stiffness.py [--ratios 1.3 2 3] [--nk 41] [--nu 0.3975]
"""
import argparse

import numpy as np

# f(q), q = r / h, and alpha_2D h^2 (device/sph_smoothing_kernel.h, docs/scene-format.md)
KERNELS = {
    "wendland-c2": (lambda q: (1 - q / 2) ** 4 * (1 + 2 * q), 7 / (4 * np.pi)),
    "laguerre-gauss": (lambda q: (1 - q * q + q ** 4 / 6) * np.exp(-q * q), 3 / np.pi),
    "laguerre-wendland": (lambda q: (1 - q / 2) ** 6 * (1 + 3 * q + 35 * q * q / 12)
                          * (1 - 9 * q * q / 4 + 27 * q ** 4 / 32), 1287 / (188 * np.pi)),
    "cubic-bspline": (lambda q: np.where(q < 1, 1 - 1.5 * q * q * (1 - q / 2),
                                         0.25 * (2 - q) ** 3), 10 / (7 * np.pi)),
}


def dw_dr(name, r, h):
    f, alpha = KERNELS[name]
    q, dq = r / h, 1e-6
    df = (f(q + dq) - f(q - dq)) / (2 * dq)
    return np.where(q < 2, alpha / h ** 2 * df / h, 0.0)


def stiffness(name, h, nk):
    reach = int(np.ceil(2 * h))
    offsets = np.array([(a, b) for a in range(-reach, reach + 1) for b in range(-reach, reach + 1)
                        if (a, b) != (0, 0) and np.hypot(a, b) < 2 * h], float)
    r = np.hypot(offsets[:, 0], offsets[:, 1])
    e = offsets / r[:, None]
    w = -dw_dr(name, r, h) / r

    def matrix(k):
        c = 1 - np.cos(offsets @ k)
        return np.einsum("j,j,ja,jb->ab", w, c, e, e)

    ks = np.linspace(-np.pi, np.pi, nk)
    lowest = min((np.linalg.eigvalsh(matrix(np.array([kx, ky])))[0], kx, ky)
                 for kx in ks for ky in ks)
    k = 1e-2
    long_wave = np.diag(matrix(np.array([k, 0.0]))) / k ** 2  # (x, y): longitudinal, shear
    return lowest, long_wave


def acoustic_limit(name, h, nk, nu, xi_e=3.5):
    """omega_max (c0 / dp) of the linearised acoustic substep and the CFL 2 / (omega_max h)."""
    reach = int(np.ceil(2 * h))
    offsets = np.array([(a, b) for a in range(-reach, reach + 1) for b in range(-reach, reach + 1)
                        if (a, b) != (0, 0) and np.hypot(a, b) < 2 * h], float)
    r = np.hypot(offsets[:, 0], offsets[:, 1])
    e = offsets / r[:, None]
    dw = dw_dr(name, r, h)
    g_over_k = 3 * (1 - 2 * nu) / (2 * (1 + nu))
    ks = np.linspace(-np.pi, np.pi, nk)
    largest = 0.0
    for kx in ks:
        for ky in ks:
            phase = offsets @ np.array([kx, ky])
            s = ((dw * np.sin(phase))[:, None] * e).sum(axis=0)
            d = np.einsum("j,j,ja,jb->ab", -dw / r, 1 - np.cos(phase), e, e)
            largest = max(largest, np.linalg.eigvalsh(np.outer(s, s) + 2 * xi_e * g_over_k * d)[-1])
    omega = np.sqrt(largest)
    return omega, 2 / (omega * h)


def relaxation_alpha_limit(name, h, nk=41):
    """The largest stable alpha of the relaxation step x += alpha h^2 a (host/setup/relax.c,
    relaxation.step = "fixed") on the 2D lattice (spacing 1, h = h/dp): with
    a = -2 sum_j grad W V_j, a displacement wave u exp(ik.x) changes a by -K(k) u,
    K(k) = 2 sum_j H(r_j) (1 - cos k.r_j), H = W'' e e^T + (W'/r)(I - e e^T), so the step is
    stable while alpha h^2 lambda_max(K) <= 2.  W'' by a central difference of W'."""
    reach = int(np.ceil(2 * h))
    offsets = np.array([(a, b) for a in range(-reach, reach + 1) for b in range(-reach, reach + 1)
                        if (a, b) != (0, 0) and np.hypot(a, b) < 2 * h], float)
    r = np.hypot(offsets[:, 0], offsets[:, 1])
    e = offsets / r[:, None]
    d = 1e-5 * h
    w1 = dw_dr(name, r, h)
    w2 = (dw_dr(name, r + d, h) - dw_dr(name, r - d, h)) / (2 * d)
    eye = np.eye(2)[None, :, :]
    ee = np.einsum("ja,jb->jab", e, e)
    hess = w2[:, None, None] * ee + (w1 / r)[:, None, None] * (eye - ee)
    ks = np.linspace(0.0, np.pi, nk)
    largest = max(np.linalg.eigvalsh(np.einsum("j,jab->ab", 2 * (1 - np.cos(offsets @ [kx, ky])),
                                               hess))[-1] for kx in ks for ky in ks)
    return 2.0 / (h * h * largest)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("--ratios", type=float, nargs="+", default=[1.3, 2.0, 3.0], help="h / dp")
    ap.add_argument("--nk", type=int, default=41, help="wave numbers per axis")
    ap.add_argument("--nu", type=float, default=0.3975,
                    help="Poisson ratio for G/K (default: the 2D plate's)")
    args = ap.parse_args()
    print("| kernel | h/dp | smallest eigenvalue of D(k) | at k | long-wave shear "
          "| long-wave longitudinal | omega_max dp/c0 | CFL limit 2/(omega_max h) |")
    print("|---|---|---|---|---|---|---|---|")
    for name in KERNELS:
        for h in args.ratios:
            (lo, kx, ky), (lon, shear) = stiffness(name, h, args.nk)
            omega, cfl = acoustic_limit(name, h, args.nk, args.nu)
            print(f"| {name} | {h:g} | {lo:+.4f} | ({kx:+.2f}, {ky:+.2f}) | {shear:+.4f} "
                  f"| {lon:+.4f} | {omega:.3f} | {cfl:.3f} |")


if __name__ == "__main__":
    main()
