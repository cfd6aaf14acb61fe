#!/usr/bin/python3
"""public_force_estimator.py CHECKPOINT — the force on the cylinder in one state of a run, by
sphsolid's estimator and by the public code's, side by side.

sphsolid's drag and lift are the momentum the fluid loses to the wall body: minus the wall
pairs' share of the fluid's momentum rate, with the corrected gradients the step uses
(`wall_force`, docs/fluids.md, "Boundaries").  The public code, whose numbers Table 5 of
seed 004 reports, sums separate expressions over the wall particles at output times, with the
uncorrected kernel gradient (eulerian-sph-reference.md §4, "Forces"):

  viscous   F_i = w_i sum_j 4 mu (v_wall - v_j) / (r_ij + 0.01 h) dW_ij w_j
  pressure  F_i = -w_i sum_j [(p_j + p_j^w) e_ij + D n_f] dW_ij w_j,
            D = Z u_J min(3 max(u_J, 0) / c0, 1), u_J = 2 (v_j - v_wall) . n_f, Z = rho_j c0,

with p_j^w = p_j + rho_j r_ij max(0, a_j . e_ij), a_j the fluid particle's viscous
acceleration, which a checkpoint does not hold: formed here from the state as the public code
forms it (uncorrected gradients, its 1/(r + 0.01 h): 2 mu (v_j - v_k) for a fluid neighbour k,
4 mu v_j for a wall neighbour, divided by rho_j), and also left out (p_j^w = p_j, a lower bound:
the term only adds) to show its share.  Both estimators read the same state: the
checkpoint's positions, velocities, densities, pressures, volumes, kinds and wall normals (any
`sphsolid run ... --checkpoint-every T` of the cylinder writes one).  Prints the pressure and
viscous parts of C_D = 2 F_x / (rho U^2 D) and C_L for both (the scene's forces.reference_*).
"""
import argparse
import re

import h5py
import numpy as np


def scene_number(text, key, default=None):
    m = re.search(r"\b%s\s*=\s*([-0-9.eE+]+)" % key, text)
    return float(m.group(1)) if m else default


def laguerre_gauss_gradient(r, h):
    """dW/dr of the truncated Laguerre-Gauss kernel in 2D (device/sph_smoothing_kernel.h)."""
    q = r / h
    alpha = 3.0 / (np.pi * h * h)
    df = q * (-q ** 4 / 3.0 + 8.0 * q ** 2 / 3.0 - 4.0) * np.exp(-q * q)
    return np.where(q <= 2.0, alpha * df / h, 0.0)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("checkpoint", help="RUN/checkpoint/checkpoint.h5 of a cylinder run")
    args = ap.parse_args()
    with h5py.File(args.checkpoint, "r") as f:
        text = bytes(f["scene_text"][...].astype(np.uint8)).decode(errors="replace")
        if "laguerre-gauss" not in text or "dimension = 2" not in text:
            raise SystemExit("%s: a 2D Laguerre-Gauss scene is expected" % args.checkpoint)
        t, n = float(f.attrs["time"]), int(f.attrs["particles"])
        fields = f["fields"]
        pos = fields["pos"][...].reshape(2, n).T
        vel = fields["vel"][...].reshape(2, n).T
        rho, vol, kind = fields["rho"][...], fields["vol"][...], fields["kind"][...]
        pressure = fields["pressure"][...]
        normal = fields["normal"][...].reshape(2, n).T
        wall_force = fields["wall_force"][...].reshape(4, n).T
    dp, mu = scene_number(text, "dp"), scene_number(text, "viscosity")
    c0 = scene_number(text, "sound_speed")
    h = scene_number(text, "smoothing_ratio", 1.3) * dp
    scale = 2.0 / (scene_number(text, "reference_density", 1.0) *
                   scene_number(text, "reference_speed", 1.0) ** 2 *
                   scene_number(text, "reference_length", 1.0))

    # sphsolid: minus the fluid's share of the wall pairs' momentum rate
    ours = -wall_force.sum(axis=0) * scale  # pressure x, y, viscous x, y

    # the public code's sums over the wall particles
    wall, fluid = np.where(kind == 1)[0], np.where(kind != 1)[0]
    # the fluid within 2h of the wall body's box: the only candidates of its pairs
    lo, hi = pos[wall].min(axis=0) - 2.0 * h, pos[wall].max(axis=0) + 2.0 * h
    fluid = fluid[np.all((pos[fluid] >= lo) & (pos[fluid] <= hi), axis=1)]
    # the viscous acceleration of the fluid particles within 2h of a wall particle, from every
    # neighbour within 2h of them
    lo2, hi2 = lo - 2.0 * h, hi + 2.0 * h
    around = np.where(np.all((pos >= lo2) & (pos <= hi2), axis=1))[0]
    near_wall = set()
    for i in wall:
        r = np.hypot(*(pos[i] - pos[fluid]).T)
        near_wall.update(fluid[(r > 0.0) & (r <= 2.0 * h)].tolist())
    accel = np.zeros((n, 2))
    for j in near_wall:
        d = pos[j] - pos[around]
        r = np.hypot(d[:, 0], d[:, 1])
        near = (r > 0.0) & (r <= 2.0 * h)
        ks, r = around[near], r[near]
        coef = laguerre_gauss_gradient(r, h) * vol[ks] / (r + 0.01 * h)
        dv = np.where((kind[ks] == 1)[:, None], 2.0 * vel[j], vel[j] - vel[ks])
        accel[j] = (2.0 * mu * dv * coef[:, None]).sum(axis=0) / rho[j]

    press, press_no_d, press_no_w, visc = np.zeros(2), np.zeros(2), np.zeros(2), np.zeros(2)
    for i in wall:
        d = pos[i] - pos[fluid]
        r = np.hypot(d[:, 0], d[:, 1])
        near = (r > 0.0) & (r <= 2.0 * h)
        js, d, r = fluid[near], d[near], r[near]
        e = d / r[:, None]
        g = laguerre_gauss_gradient(r, h) * vol[js]
        visc += vol[i] * (4.0 * mu * -vel[js] / (r + 0.01 * h)[:, None] * g[:, None]).sum(axis=0)
        u_j = 2.0 * (vel[js] @ normal[i])
        dissipation = rho[js] * c0 * u_j * np.minimum(3.0 * np.maximum(u_j, 0.0) / c0, 1.0)
        p_wall = pressure[js] + rho[js] * r * np.maximum(0.0, (accel[js] * e).sum(axis=1))
        p_term = -vol[i] * ((pressure[js] + p_wall)[:, None] * e * g[:, None]).sum(axis=0)
        d_term = -vol[i] * (dissipation * g).sum() * normal[i]
        press_no_d += p_term
        press += p_term + d_term
        p_plain = -vol[i] * ((2.0 * pressure[js])[:, None] * e * g[:, None]).sum(axis=0)
        press_no_w += p_plain + d_term
    press, press_no_d, press_no_w = press * scale, press_no_d * scale, press_no_w * scale
    visc = visc * scale

    print("t = %.4g, dp = %g, h = %g, %d wall particles" % (t, dp, h, len(wall)))
    print("%-36s %9s %9s %9s %9s" % ("estimator", "C_D", "pressure", "viscous", "C_L"))
    print("%-36s %9.4f %9.4f %9.4f %9.4f" % ("sphsolid (momentum exchange)", ours[0] + ours[2],
                                            ours[0], ours[2], ours[1] + ours[3]))
    print("%-36s %9.4f %9.4f %9.4f %9.4f" % ("public code", press[0] + visc[0], press[0],
                                            visc[0], press[1] + visc[1]))
    print("%-36s %9.4f %9.4f" % ("  with p_j^w = p_j", press_no_w[0] + visc[0], press_no_w[0]))
    print("%-36s %9.4f %9.4f" % ("  without D", press_no_d[0] + visc[0], press_no_d[0]))


if __name__ == "__main__":
    main()
