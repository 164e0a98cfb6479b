"""Pull-off of a sticky sphere from a standard solid against the retract speed
=============================================================================

A rigid sphere (radius R = 50 um, as a paraboloid) with work of adhesion w = 50 mJ/m^2 is
pressed 0.8 um into a standard linear solid (G(t) = G_inf + G1 exp(-t / tau), G_inf = 2 MPa,
G1 = 6 MPa, tau = 10 ms: an elastomer whose glassy modulus is four times its relaxed one)
and pulled off again, both at one speed v under depth control, as an AFM force curve does.
Two methods solve it:

- MDR with the JKR law on 2001 elements, 2000 steps of retract, its edge letting go by one of
  two criteria (see the adhesion page): with the process zone of the BEM law's stress sigma0
  (``mv.JKR(work_of_adhesion=w, stress=sigma0)``: the edge is a crack whose Dugdale zone,
  pi K^2 / (8 sigma0^2) long, is crossed at the crack's speed, and it lets go when
  K^2 C_eff / 2 = w, C_eff the creep compliance averaged over the zone), and without it
  (Heß's rule with the relaxed modulus, exact only for slow cycles);
- BEM with a Maugis–Dugdale cohesive zone of the same w and a stress sigma0 = 1.07 MPa
  (range h0 = w / sigma0 = 47 nm), so that Maugis's transition parameter is lambda = 3 at the
  relaxed modulus (1.19 at the glassy one): close to the JKR limit (Maugis's pull-off
  1.011 and 1.053 times JKR's). 80 x 80 elements over 20 um, 20 steps of approach and 80 of
  retract, at five speeds (the BEM forces move by 2-3 % with the steps and the grid), the
  sweeps' tolerance 1e-6 of sigma0.

Slow against tau all give the relaxed body's JKR (BEM: Maugis's) largest tension,
3/2 pi w R, and the depth-controlled pull-off near JKR's 5/6 pi w R. Fast, the body is
glassy throughout: BEM and MDR with the zone give the glassy elastic body's pull-off — for a
paraboloid again about 3/2 pi w R, as JKR's does not depend on the modulus — while MDR's
relaxed critical opening on the glassy springs gives G_0 / G_inf times it. In between, the
crack runs through its zone faster than the body relaxes and the pull-off rises to about
three times JKR's near a cycle of 30 tau: MDR with the zone follows BEM there within 10 %
(below it), while the relaxed critical opening rises too late and peaks too high.

Run: python examples/viscoelastic_pull_off.py [OUT.png] [--bem-n N] [--bem-steps IN OUT]
[--no-bem] (default OUT: viscoelastic_pull_off.png; N = 80, IN OUT = 20 80; --no-bem: MDR
only, a second)
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
LAMBDA = 3.0  # Maugis's transition parameter at the relaxed modulus
K_RELAXED = 4.0 * (4.0 * MEDIUM.G_inf) / 3.0  # K = 4 E* / 3, E* = 4 G (incompressible)
LAW = mv.MaugisDugdale(work_of_adhesion=W, stress=LAMBDA / 2 * (math.pi * W * K_RELAXED**2 / R) ** (1 / 3))
BEM_SIDE = 20e-6


def sphere_map(n, side):
    """The paraboloid x^2 / (2 R) as a height map (m) on an n x n grid spanning ``side``."""
    dx = side / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    return mv.HeightMap(-(x[:, None] ** 2 + x[None, :] ** 2) / (2 * R), dx)


def cycle(speed, method, bem_n=80, bem_steps=(20, 80)):
    """Largest tension (N) and pull-off force (N) of an approach to D_MAX and a retract to
    D_MIN, both at ``speed`` (m/s), by ``method`` ("mdr": JKR with the BEM law's zone stress,
    "mdr-relaxed": JKR without it, or "bem"; BEM on ``bem_n`` x ``bem_n`` elements over
    BEM_SIDE, ``bem_steps`` steps of approach and of retract)."""
    t_in = D_MAX / speed
    t_end = t_in + (D_MAX - D_MIN) / speed
    if method.startswith("mdr"):
        stress = LAW.stress if method == "mdr" else None
        indenter = mv.Paraboloid(c=1 / (2 * R))
        contact = mv.JKR(work_of_adhesion=W, stress=stress)
        n, steps = 2001, (100, 2000)
        options = {}
    else:
        indenter, contact, n, steps = sphere_map(bem_n, BEM_SIDE), LAW, bem_n, bem_steps
        options = {"tol": 1e-6}
    times = np.concatenate([np.linspace(t_in / steps[0], t_in, steps[0]),
                            np.linspace(t_in, t_end, steps[1] + 1)[1:]])
    scene = mv.Scene(indenter=indenter, medium=MEDIUM, contact=contact,
                     depth=([0.0, t_in, t_end], [0.0, D_MAX, D_MIN]), duration=t_end, times=times)
    r = mv.solve(scene, "bem" if method == "bem" else "mdr", n, **options)
    return -r.force.min(), -r.pull_off_force


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out", nargs="?", default="viscoelastic_pull_off.png")
    parser.add_argument("--bem-n", type=int, default=80, help="BEM elements per side (default 80)")
    parser.add_argument("--bem-steps", type=int, nargs=2, default=(20, 80), metavar=("IN", "OUT"),
                        help="BEM steps of approach and of retract (default 20 80)")
    parser.add_argument("--no-bem", action="store_true", help="MDR only")
    args = parser.parse_args()
    jkr = 1.5 * math.pi * W * R
    ratio = (MEDIUM.G_inf + MEDIUM.G1) / MEDIUM.G_inf
    lam_glassy = LAMBDA / ratio ** (2 / 3)
    speeds = np.logspace(-8, 0, 9)
    bem_speeds = [] if args.no_bem else speeds[[0, 2, 3, 4, 6]]
    mdr = [cycle(v, "mdr") for v in speeds]
    relaxed = [cycle(v, "mdr-relaxed") for v in speeds]
    bem = [cycle(v, "bem", args.bem_n, tuple(args.bem_steps)) for v in bem_speeds]
    print(f"JKR 3/2 pi w R = {jkr:.4e} N; G_0 / G_inf = {ratio:g}; Maugis's pull-off / JKR: "
          f"{mv.analytic.maugis_pull_off(LAMBDA) / 1.5:.4f} relaxed (lambda {LAMBDA:g}), "
          f"{mv.analytic.maugis_pull_off(lam_glassy) / 1.5:.4f} glassy (lambda {lam_glassy:.3f})")
    print(f"zone stress sigma0 = {LAW.stress:.4g} Pa (MDR's mv.JKR(stress=...) and BEM's law)")
    print("   v (m/s)   largest tension / JKR (MDR zone, MDR relaxed, BEM)"
          "   pull-off / (5/6 pi w R) (MDR zone, BEM)")
    bem_at = dict(zip(bem_speeds, bem))
    for v, (tension, pull), (old, _) in zip(speeds, mdr, relaxed):
        bt, bp = bem_at.get(v, (math.nan, math.nan))
        print(f"  {v:8.1e}   {tension / jkr:10.4f} {old / jkr:10.4f} {bt / jkr:10.4f}"
              f"          {pull / (jkr * 5 / 9):10.4f} {bp / (jkr * 5 / 9):10.4f}")

    fig, ax = plt.subplots(figsize=(6.0, 4.0))
    ax.semilogx(speeds, [t / jkr for t, _ in mdr], "o-", color="C0", label="largest tension (MDR with zone)")
    ax.semilogx(speeds, [p / jkr for _, p in mdr], "s--", color="C0", label="force at pull-off (MDR, zone)")
    ax.semilogx(speeds, [t / jkr for t, _ in relaxed], "^:", color="C2",
                label="largest tension (MDR, relaxed critical opening)")
    if bem:
        ax.semilogx(bem_speeds, [t / jkr for t, _ in bem], "o-", color="C1",
                    label=f"largest tension (BEM, Maugis lambda = {LAMBDA:g})")
        ax.semilogx(bem_speeds, [p / jkr for _, p in bem], "s--", color="C1", label="force at pull-off (BEM)")
    ax.axhline(1.0, color="0.5", lw=0.9, ls=":")
    ax.axhline(ratio, color="0.5", lw=0.9, ls=":")
    ax.annotate("relaxed JKR, 3/2 pi w R", (speeds[0], 1.0), va="bottom", fontsize=8, color="0.3")
    ax.annotate("G_0 / G_inf times it", (speeds[0], ratio), va="bottom", fontsize=8, color="0.3")
    ax.set_xlabel("approach and retract speed v (m/s)")
    ax.set_ylabel("force / (3/2 pi w R)")
    ax.set_title(f"sphere R = {R * 1e6:g} um, w = {W * 1e3:g} mJ/m^2, tau = {MEDIUM.tau1 * 1e3:g} ms")
    ax.legend(loc="upper left", fontsize=7)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    plt.close(fig)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
