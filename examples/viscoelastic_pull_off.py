"""Pull-off of a sticky sphere from a standard solid against the retract speed
=============================================================================

A rigid sphere (radius R = 50 um) with JKR adhesion (work of adhesion w = 50 mJ/m^2) is
pressed 0.8 um into a standard linear solid (G(t) = G_inf + G1 exp(-t / tau), G_inf = 2 MPa,
G1 = 6 MPa, tau = 10 ms: an elastomer whose glassy modulus is four times its relaxed one)
and pulled off again, both at one speed v under depth control, as an AFM force curve does.
MDR solves it by Heß's rule with the relaxed modulus (see the adhesion page).

The largest tension during the retract is JKR's 3/2 pi w R for the relaxed body when the
cycle is slow against tau, and tends to G_0 / G_inf times it when the cycle is too fast for
the body to relax; the force at which the contact lets go (the pull-off under depth control)
is JKR's 5/6 pi w R in the slow limit. In between, where the contact was made partly relaxed
and is pulled faster than the body follows, the pinned contact carries more than either
limit: the zero-range opening criterion has no bound there (see the adhesion page). Each
output time is a step: the retract is given 2000. BEM with adhesion is not available yet, so
the curve is MDR's alone.

Run: python examples/viscoelastic_pull_off.py [OUT.png]   (default OUT: viscoelastic_pull_off.png)
"""

import argparse
import math

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mdrvisc as mv  # noqa: E402

R, W = 50e-6, 0.05
MEDIUM = mv.StandardSolid(G_inf=2e6, G1=6e6, tau1=0.01)
D_MAX, D_MIN = 0.8e-6, -1.5e-6


def cycle(speed, n=2001):
    """Largest tension (N) and pull-off force (N) of an approach to D_MAX and a retract to
    D_MIN, both at ``speed`` (m/s), by MDR on ``n`` elements."""
    t_in = D_MAX / speed
    t_end = t_in + (D_MAX - D_MIN) / speed
    times = np.concatenate([np.linspace(t_in / 100, t_in, 100), np.linspace(t_in, t_end, 2001)[1:]])
    scene = mv.Scene(indenter=mv.Sphere(radius=R), medium=MEDIUM, contact=mv.JKR(work_of_adhesion=W),
                     depth=([0.0, t_in, t_end], [0.0, D_MAX, D_MIN]), duration=t_end, times=times)
    r = mv.solve(scene, "mdr", n)
    return -r.force.min(), -r.pull_off_force


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out", nargs="?", default="viscoelastic_pull_off.png")
    args = parser.parse_args()
    jkr = 1.5 * math.pi * W * R
    ratio = (MEDIUM.G_inf + MEDIUM.G1) / MEDIUM.G_inf
    speeds = np.logspace(-8, 0, 9)
    rows = [cycle(v) for v in speeds]
    print(f"JKR 3/2 pi w R = {jkr:.4e} N; G_0 / G_inf = {ratio:g}")
    print("   v (m/s)   largest tension / JKR   pull-off / (5/6 pi w R)")
    for v, (tension, pull) in zip(speeds, rows):
        print(f"  {v:8.1e}   {tension / jkr:21.4f}   {pull / (jkr * 5 / 9):23.4f}")

    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    ax.semilogx(speeds, [t / jkr for t, _ in rows], "o-", label="largest tension (MDR)")
    ax.semilogx(speeds, [p / jkr for _, p in rows], "s--", label="force at pull-off (MDR)")
    ax.axhline(1.0, color="0.5", lw=0.9, ls=":")
    ax.axhline(ratio, color="0.5", lw=0.9, ls=":")
    ax.annotate("relaxed JKR, 3/2 pi w R", (speeds[0], 1.0), va="bottom", fontsize=8, color="0.3")
    ax.annotate("G_0 / G_inf times it", (speeds[0], ratio), va="bottom", fontsize=8, color="0.3")
    ax.set_xlabel("approach and retract speed v (m/s)")
    ax.set_ylabel("force / (3/2 pi w R)")
    ax.set_title(f"sphere R = {R * 1e6:g} um, w = {W * 1e3:g} mJ/m^2, tau = {MEDIUM.tau1 * 1e3:g} ms")
    ax.legend(loc="center right")
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    plt.close(fig)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
