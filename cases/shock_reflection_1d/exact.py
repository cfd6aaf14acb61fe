#!/usr/bin/python3
"""exact.py — the exact solution of cases/shock_reflection_1d: Sod's tube closed by a wall at x = 1.

    /usr/bin/python3 cases/shock_reflection_1d/exact.py [--t T] [--csv FILE]

The Riemann problem of (rho, u, p) = (1, 0, 1 | 0.125, 0, 0.1) at x = 0.5, gamma = 1.4, solved
exactly (Toro, Riemann Solvers and Numerical Methods for Fluid Dynamics, ch. 4): a rarefaction
to the left, the contact and a shock to the right behind which the gas moves at u*.  The shock
meets the wall at x = 1 and is reflected as a shock that stops the gas: behind it the state 5 at
rest of the Rankine-Hugoniot relations.  profile(x, t) is exact for t below the first
interaction after that (the reflected shock meets the contact at t = 0.4068; the rarefaction's
head reaches the left wall at 0.4226).  Prints the waves and states; --csv writes the profile
at time T (default 0.38) as x,density,velocity,pressure on 2001 points.
"""
import argparse
import math
import sys

GAMMA = 1.4
LEFT = (1.0, 0.0, 1.0)  # rho, u, p
RIGHT = (0.125, 0.0, 0.1)
X0, WALL = 0.5, 1.0


def wave_jump(p, rho, p_k):
    """The velocity change across the wave from a side at rest (rho, p_k) to pressure p: a shock
    (p > p_k) or a rarefaction (Toro, eqs. 4.6-4.7)."""
    if p > p_k:
        a, b = 2.0 / ((GAMMA + 1.0) * rho), (GAMMA - 1.0) / (GAMMA + 1.0) * p_k
        return (p - p_k) * math.sqrt(a / (p + b))
    c = math.sqrt(GAMMA * p_k / rho)
    return 2.0 * c / (GAMMA - 1.0) * ((p / p_k) ** ((GAMMA - 1.0) / (2.0 * GAMMA)) - 1.0)


def solve(f, lo, hi):
    """The root of the increasing f on [lo, hi], by bisection to round-off."""
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if f(mid) > 0.0 else (mid, hi)
    return 0.5 * (lo + hi)


def shock_density(rho, p_k, p):
    """The density behind a shock from (rho, p_k) to p (Rankine-Hugoniot, Toro eq. 4.50)."""
    m = (GAMMA - 1.0) / (GAMMA + 1.0)
    return rho * (p / p_k + m) / (m * p / p_k + 1.0)


class Solution:
    """The waves and states of the exact solution."""

    def __init__(self):
        rl, _, pl = LEFT
        rr, _, pr = RIGHT
        self.c_left = math.sqrt(GAMMA * pl / rl)
        self.p_star = solve(lambda p: wave_jump(p, rl, pl) + wave_jump(p, rr, pr), 1e-6, 10.0)
        self.u_star = 0.5 * (wave_jump(self.p_star, rr, pr) - wave_jump(self.p_star, rl, pl))
        self.rho3 = rl * (self.p_star / pl) ** (1.0 / GAMMA)  # left of the contact
        self.rho2 = shock_density(rr, pr, self.p_star)  # right of it, behind the shock
        c_right = math.sqrt(GAMMA * pr / rr)
        self.shock = c_right * math.sqrt((GAMMA + 1.0) / (2.0 * GAMMA) * self.p_star / pr
                                         + (GAMMA - 1.0) / (2.0 * GAMMA))
        self.tail = self.u_star - self.c_left * (self.p_star / pl) ** ((GAMMA - 1.0) / (2 * GAMMA))
        # the reflection: a shock into state 2 that brings u* to rest, seen from the gas of
        # state 2 the same jump as any shock (Toro's function of the shock side)
        self.p5 = solve(lambda p: wave_jump(p, self.rho2, self.p_star) - self.u_star,
                        self.p_star, 50.0)
        self.rho5 = shock_density(self.rho2, self.p_star, self.p5)
        # mass across it: rho2 (u* - W) = rho5 (0 - W)
        self.reflected = self.rho2 * self.u_star / (self.rho2 - self.rho5)
        self.t_wall = (WALL - X0) / self.shock
        # the reflected shock meets the contact: WALL + W (t - t_wall) = X0 + u* t
        self.t_valid = min((WALL - self.reflected * self.t_wall - X0) / (self.u_star
                                                                         - self.reflected),
                           X0 / self.c_left)

    def shock_position(self, t):
        """The right-going shock before the wall, the reflected one after it."""
        if t <= self.t_wall:
            return X0 + self.shock * t
        return WALL + self.reflected * (t - self.t_wall)

    def profile(self, x, t):
        """(rho, u, p) at x in [0, 1], time 0 < t < t_valid."""
        if not 0.0 < t < self.t_valid:
            raise ValueError("the exact profile holds for 0 < t < %.5f, got %g" % (self.t_valid, t))
        rl, ul, pl = LEFT
        xi = (x - X0) / t
        if xi <= -self.c_left:
            return LEFT
        if xi <= self.tail:  # inside the rarefaction fan (Toro eq. 4.56)
            g = GAMMA
            c = 2.0 / (g + 1.0) * (self.c_left + (g - 1.0) / 2.0 * (ul - xi))
            u = 2.0 / (g + 1.0) * (self.c_left + (g - 1.0) / 2.0 * ul + xi)
            rho = rl * (c / self.c_left) ** (2.0 / (g - 1.0))
            return rho, u, pl * (c / self.c_left) ** (2.0 * g / (g - 1.0))
        if x <= X0 + self.u_star * t:
            return self.rho3, self.u_star, self.p_star
        s = self.shock_position(t)
        if t <= self.t_wall:
            return (self.rho2, self.u_star, self.p_star) if x <= s else RIGHT
        return (self.rho2, self.u_star, self.p_star) if x <= s else (self.rho5, 0.0, self.p5)


def main(argv):
    ap = argparse.ArgumentParser(prog="exact.py", description=__doc__.split("\n")[0])
    ap.add_argument("--t", type=float, default=0.38)
    ap.add_argument("--csv", help="write the profile at time T to this file")
    args = ap.parse_args(argv)
    s = Solution()
    print(f"star state p* {s.p_star:.6f}, u* {s.u_star:.6f}; rho3 {s.rho3:.6f}, rho2 {s.rho2:.6f}")
    print(f"shock speed {s.shock:.6f}, at the wall at t = {s.t_wall:.6f}; reflected at "
          f"{s.reflected:.6f} leaving p5 {s.p5:.6f}, rho5 {s.rho5:.6f} at rest")
    print(f"the profile holds to t = {s.t_valid:.5f}; at t = {args.t:g} the shock is at "
          f"x = {s.shock_position(args.t):.5f}, the contact at {X0 + s.u_star * args.t:.5f}")
    if args.csv:
        with open(args.csv, "w") as f:
            f.write("x,density,velocity,pressure\n")
            for k in range(2001):
                x = k / 2000.0
                rho, u, p = s.profile(x, args.t)
                f.write(f"{x:.6f},{rho:.10g},{u:.10g},{p:.10g}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
