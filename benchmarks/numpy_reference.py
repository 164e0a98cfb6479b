"""Plain numpy/scipy reference implementation of the mdrvisc viscous BEM.

This module is a self-contained competitor for the Rust core (``rust/src``) used in
wall-time benchmarks. It implements the same algorithm as the crate's viscous BEM:

* Love's (1929) influence coefficients for square elements of uniform pressure on an
  incompressible half-space with shear modulus G = 1 (E* = 4G = 4), see :func:`love_kernel`;
* the non-periodic half-space operator by zero-padded FFT convolution (DC-FFT, Liu, Wang &
  Liu 2000), see :class:`FftOperator`;
* the Polonsky & Keer (1999) constrained conjugate gradient, force controlled, see
  :func:`polonsky_keer`;
* implicit viscous time stepping in impulse form, see :func:`viscous_bem`.

Sign convention: depths and surface deflections are positive into the
body, the gap is g = u + h - d.

Only numpy and ``scipy.fft`` are used. The FFTs are scipy's pocketfft real transforms
(``rfft2`` / ``irfft2``) with ``workers=-1`` (all cores; pocketfft parallelises the batches of
1D transforms of a 2D transform) and padded sizes from ``scipy.fft.next_fast_len`` (factors
2, 3, 5, 7 only). pocketfft keeps its plans (twiddle factors) in an internal LRU cache, so a
repeated transform of the same size reuses its plan; the kernel's transform is computed
once per operator. All element-wise work is vectorised numpy on whole arrays.

Run ``python benchmarks/numpy_reference.py [n ...] [--workers K]`` for the paper's paraboloid case
(c = 1, 2.56 m x 2.56 m footprint, eta = 1 Pa s, F = 1 N, t = 1..5 s); the default grid is
257 x 257.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import scipy.fft as sfft

__all__ = ["love_kernel", "FftOperator", "polonsky_keer", "viscous_bem", "paraboloid_closed_form"]

#: workers argument of every scipy.fft call (-1: all cores)
FFT_WORKERS = -1


# ---------------------------------------------------------------------------------------------
# Influence coefficients
# ---------------------------------------------------------------------------------------------

def _phi(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Antiderivative of 1/sqrt(x^2 + y^2) in x and y, odd in each argument.

    Phi(x, y) = x asinh(y/|x|) + y asinh(x/|y|) (a term is 0 where its prefactor is 0),
    so that Phi(x, y) = integral_0^x integral_0^y 1/r with signed limits. In the first
    quadrant it equals the textbook x asinh(y/x) + y asinh(x/y); that literal form is even
    in x in its first term and must NOT be used for negative coordinates (it gives a wrong,
    non-even kernel with a zero diagonal).
    """
    ax, ay = np.abs(x), np.abs(y)
    with np.errstate(divide="ignore", invalid="ignore"):
        tx = np.where(ax > 0.0, x * np.arcsinh(y / np.where(ax > 0.0, ax, 1.0)), 0.0)
        ty = np.where(ay > 0.0, y * np.arcsinh(x / np.where(ay > 0.0, ay, 1.0)), 0.0)
    return tx + ty


def love_kernel(nx: int, ny: int, dx: float) -> np.ndarray:
    """Influence coefficients of square elements on an incompressible half-space, G = 1.

    The surface deflection at the centre of an element offset (kx*dx, ky*dx) from a square
    element of side ``dx`` loaded by a unit uniform pressure is

        K[ky, kx] = (1 / (4 pi)) * I,   I = integral over the square of 1/sqrt(xi^2 + eta^2)
                  = Phi(x2, y2) - Phi(x1, y2) - Phi(x2, y1) + Phi(x1, y1),

    x1 = kx*dx - dx/2, x2 = kx*dx + dx/2 (y likewise), Phi the signed antiderivative of
    :func:`_phi`, x asinh(y/|x|) + y asinh(x/|y|) (Love 1929,
    Boussinesq u = F / (4 pi G r) for nu = 1/2). The integral is evaluated in units of dx
    and scaled by dx (it is homogeneous of degree 1).

    Parameters
    ----------
    nx, ny : number of elements along x and y (>= 1).
    dx : element side (> 0).

    Returns
    -------
    K : array of shape (2*ny - 1, 2*nx - 1); ``K[ky + ny - 1, kx + nx - 1]`` is the
        coefficient for offset (kx, ky), kx in -(nx-1)..(nx-1), ky in -(ny-1)..(ny-1).
        It is even in kx and in ky.
    """
    if nx < 1 or ny < 1:
        raise ValueError(f"grid must have at least one element, got nx={nx}, ny={ny}")
    if not dx > 0.0:
        raise ValueError(f"element size dx must be positive, got dx={dx}")
    kx = np.arange(-(nx - 1), nx, dtype=np.float64)[None, :]
    ky = np.arange(-(ny - 1), ny, dtype=np.float64)[:, None]
    x1, x2 = kx - 0.5, kx + 0.5
    y1, y2 = ky - 0.5, ky + 0.5
    integral = _phi(x2, y2) - _phi(x1, y2) - _phi(x2, y1) + _phi(x1, y1)
    return integral * (dx / (4.0 * np.pi))


# ---------------------------------------------------------------------------------------------
# Surface operator
# ---------------------------------------------------------------------------------------------

class FftOperator:
    """Half-space surface operator u = K[p] on an ny x nx grid by DC-FFT.

    The non-periodic convolution is a circular one on a zero-padded grid of size
    (My, Mx) with Mx = next_fast_len(2*nx - 2) (1 when nx == 1), My likewise. Offsets
    +(n-1) and -(n-1) share the slot n-1 when M = 2n - 2; this is exact because the kernel
    is even in each coordinate. The kernel's rfft2 is computed once.

    Parameters
    ----------
    nx, ny : grid size (elements along x and y).
    dx : element side.
    """

    def __init__(self, nx: int, ny: int, dx: float):
        self.nx, self.ny, self.dx = int(nx), int(ny), float(dx)
        self.kernel = love_kernel(self.nx, self.ny, self.dx)
        self.mx = 1 if self.nx == 1 else sfft.next_fast_len(2 * self.nx - 2, real=True)
        self.my = 1 if self.ny == 1 else sfft.next_fast_len(2 * self.ny - 2, real=True)
        padded = np.zeros((self.my, self.mx))
        kx = np.arange(-(self.nx - 1), self.nx)
        ky = np.arange(-(self.ny - 1), self.ny)
        # offset k goes to slot k mod M; +(n-1) and -(n-1) may coincide (equal values).
        padded[np.ix_(ky % self.my, kx % self.mx)] = self.kernel
        self.kernel_hat = sfft.rfft2(padded, workers=FFT_WORKERS)
        self.shape = (self.ny, self.nx)

    def apply(self, p: np.ndarray) -> np.ndarray:
        """Deflections (ny, nx) of the pressures ``p`` (ny, nx): irfft2(rfft2(p padded) K_hat)."""
        s = (self.my, self.mx)
        p_hat = sfft.rfft2(p, s=s, workers=FFT_WORKERS)  # zero-pads to s
        p_hat *= self.kernel_hat
        return sfft.irfft2(p_hat, s=s, workers=FFT_WORKERS, overwrite_x=True)[: self.ny, : self.nx]

    __call__ = apply

    def dense_matrix(self) -> np.ndarray:
        """The dense (ny*nx, ny*nx) influence matrix in C (row-major) order, for small grids."""
        n = self.nx * self.ny
        if n > 20000:
            raise ValueError(f"dense_matrix is for small grids, got {self.ny} x {self.nx}")
        j, i = np.divmod(np.arange(n), self.nx)  # row index j (y), column index i (x)
        dj = j[:, None] - j[None, :] + self.ny - 1
        di = i[:, None] - i[None, :] + self.nx - 1
        return self.kernel[dj, di]


# ---------------------------------------------------------------------------------------------
# Preconditioner: truncated inverse-kernel stencil (as rust/src/precondition.rs)
# ---------------------------------------------------------------------------------------------

#: stencil radius of the preconditioner (elements), as ``precondition::RADIUS``
STENCIL_RADIUS = 3


def inverse_stencil(radius: int = STENCIL_RADIUS) -> np.ndarray:
    """Coefficients of K^-1 at dx = 1 for offsets 0..radius in y and x, shape
    (radius + 1, radius + 1): the circulant inverse of the operator of a 65 x 65 grid,
    irfft2(1 / K_hat). Truncated to (2 radius + 1)^2 it is the preconditioner."""
    op = FftOperator(65, 65, 1.0)
    inv = sfft.irfft2(1.0 / op.kernel_hat, s=(op.my, op.mx), workers=FFT_WORKERS)
    return np.ascontiguousarray(inv[: radius + 1, : radius + 1])


def apply_stencil(g: np.ndarray, c: np.ndarray) -> np.ndarray:
    """z = S * g with the even stencil of quarter coefficients ``c`` and g zero beyond the
    grid: rows at +-k are summed first, then columns at +-j (vectorised slices)."""
    rad = c.shape[0] - 1
    ny, nx = g.shape
    gp = np.zeros((ny + 2 * rad, nx + 2 * rad))
    gp[rad:rad + ny, rad:rad + nx] = g
    z = np.zeros_like(g)
    for k in range(rad + 1):
        pair = gp[rad - k:rad - k + ny] + gp[rad + k:rad + k + ny] if k else gp[rad:rad + ny].copy()
        z += c[k, 0] * pair[:, rad:rad + nx]
        for j in range(1, rad + 1):
            z += c[k, j] * (pair[:, rad - j:rad - j + nx] + pair[:, rad + j:rad + j + nx])
    return z


# ---------------------------------------------------------------------------------------------
# Polonsky & Keer constrained conjugate gradient
# ---------------------------------------------------------------------------------------------

def _dot(a: np.ndarray, b: np.ndarray) -> float:
    """Sum of a*b over all elements, by einsum (single-threaded, no temporary).

    Not np.dot: OpenBLAS threads its ddot for arrays this size, which is slightly faster on an
    idle machine but up to 100x slower when the cores are shared (spinning thread pool).
    """
    return float(np.einsum("ij,ij->", a, b))


def polonsky_keer(op: FftOperator, h: np.ndarray, mask: np.ndarray, force: float,
                  compliance: float, tol: float = 1e-10, max_iter: int = 1000,
                  p0: np.ndarray | None = None, return_deflection: bool = False,
                  precondition: bool = False):
    """Force-controlled frictionless contact by Polonsky & Keer's (1999) constrained CG.

    Finds p >= 0 on the elements where ``mask`` is True (p = 0 elsewhere) with
    sum(p) * dx^2 = force and gap g = compliance * K[p] + h - d >= 0 on the mask, p g = 0.

    Iteration (Ic = {p > 0}):
        g = compliance*K[p] + h; gbar = mean_Ic g; g -= gbar; G = sum_Ic g^2;
        t = g + delta (G/G_old) t on Ic, 0 elsewhere; r = compliance*K[t]; r -= mean_Ic r;
        tau = sum_Ic(g t) / sum_Ic(r t); p -= tau t; p = max(p, 0);
        Iol = {p == 0, g < 0, mask}: if nonempty p[Iol] -= tau g[Iol], delta = 0, else
        delta = 1; p *= force / (sum(p) dx^2); error = sum|p - p_old| / sum(p).
    With ``precondition``, t follows z = S g_Ic - mean_Ic(S g_Ic) on Ic instead of g (S the
    truncated inverse-kernel stencil, :func:`apply_stencil`) and G = sum_Ic(g z), as in
    mdrvisc's Rust solver. The loop stops when error < tol. The convergence test is made at
    the top of the next pass, after its K[p]: that apply is the final p's, so the returned depth
    d = gbar = mean_Ic(compliance*K[p] + h) (the rigid-body approach, positive into the
    body) and the deflection belong to the returned p, at no extra cost.

    Parameters
    ----------
    op : the surface operator (G = 1); its ``dx`` sets the element area.
    h : (ny, nx) initial separation (height of the indenter above its tip, plus any
        prior deflection).
    mask : (ny, nx) bool, the elements that may carry pressure.
    force : total force (> 0).
    compliance : multiplier of K (1/G_actual for elastic, dt/eta or 1/eta for viscous).
    tol : relative L1 change of p that ends the iteration.
    max_iter : iteration limit; RuntimeError beyond it.
    p0 : optional warm start (rescaled to the force, clipped to the mask, >= 0).
    return_deflection : also return K[p] (G = 1, without the compliance factor).
    precondition : precondition the search directions with the inverse-kernel stencil.

    Returns
    -------
    (p, d, iterations, residual) or (p, d, iterations, residual, K[p]).
    """
    dx2 = op.dx * op.dx
    h = np.asarray(h, dtype=np.float64)
    mask = np.asarray(mask, dtype=bool)
    if h.shape != op.shape or mask.shape != op.shape:
        raise ValueError(f"h {h.shape} and mask {mask.shape} must have the grid shape {op.shape}")
    if not force > 0.0:
        raise ValueError(f"force must be positive, got {force}")
    n_mask = int(np.count_nonzero(mask))
    if n_mask == 0:
        raise ValueError("mask selects no element")

    if p0 is None:
        p = np.where(mask, force / (n_mask * dx2), 0.0)
    else:
        p = np.where(mask, np.maximum(np.asarray(p0, dtype=np.float64), 0.0), 0.0)
        total = p.sum() * dx2
        if not total > 0.0:
            p = np.where(mask, force / (n_mask * dx2), 0.0)
        else:
            p *= force / total
    # work arrays, reused in every pass (in-place numpy ufuncs)
    shape = p.shape
    t = np.zeros(shape)
    g = np.empty(shape)
    g_ic = np.empty(shape)
    r = np.empty(shape)
    p_old = np.empty(shape)
    buf = np.empty(shape)
    ic = np.empty(shape, dtype=bool)
    ic_f = np.empty(shape)
    overlap = np.empty(shape, dtype=bool)
    stencil = inverse_stencil() if precondition else None
    g_old = 1.0
    delta = 0.0
    error = np.inf
    iterations = 0
    while True:
        kp = op.apply(p)
        np.multiply(kp, compliance, out=g)
        g += h
        np.greater(p, 0.0, out=ic)
        n_ic = np.count_nonzero(ic)
        np.copyto(ic_f, ic)
        gbar = _dot(g, ic_f) / n_ic
        if error < tol:
            break
        if iterations >= max_iter:
            raise RuntimeError(
                f"Polonsky-Keer CG did not converge: residual {error:.3e} > tol {tol:.1e} "
                f"after {iterations} iterations")
        g -= gbar
        np.multiply(g, ic_f, out=g_ic)
        if stencil is None:
            z = g_ic
        else:
            z = apply_stencil(g_ic, stencil)
            z *= ic_f
            z -= _dot(z, ic_f) / n_ic * ic_f
        g_new = _dot(g_ic, z)
        # t = z + delta (G/G_old) t on Ic, 0 elsewhere (z = g without preconditioning)
        if delta != 0.0:
            t *= delta * g_new / g_old
            t *= ic_f
            t += z
        else:
            np.copyto(t, z)
        g_old = g_new
        np.copyto(r, op.apply(t))
        # r.t with r -> compliance (r - mean_Ic r), t = 0 outside Ic
        r_mean = _dot(r, ic_f) / n_ic
        rt = compliance * (_dot(r, t) - r_mean * t.sum())
        if rt == 0.0:
            raise RuntimeError(f"Polonsky-Keer CG broke down (r.t = 0) after {iterations} "
                               f"iterations, residual {error:.3e}")
        tau = _dot(g_ic, t) / rt
        np.copyto(p_old, p)
        np.multiply(t, tau, out=buf)
        p -= buf
        np.maximum(p, 0.0, out=p)
        # overlap set {p == 0, g < 0, mask}
        np.equal(p, 0.0, out=overlap)
        overlap &= mask
        np.less(g, 0.0, out=ic)  # ic reused as scratch
        overlap &= ic
        if overlap.any():
            np.multiply(g, tau, out=buf)
            np.subtract(p, buf, out=p, where=overlap)
            delta = 0.0
        else:
            delta = 1.0
        p_sum = p.sum()
        p *= force / (p_sum * dx2)
        np.subtract(p, p_old, out=buf)
        np.abs(buf, out=buf)
        error = buf.sum() * dx2 / force  # = sum|p - p_old| / sum(p) after the rescaling
        iterations += 1
    if return_deflection:
        return p, gbar, iterations, error, kp
    return p, gbar, iterations, error


# ---------------------------------------------------------------------------------------------
# Viscous stepping
# ---------------------------------------------------------------------------------------------

def viscous_bem(h: np.ndarray, mask: np.ndarray, dx: float, eta: float, force: float,
                t_out, tol: float = 1e-10, max_iter: int = 1000,
                precondition: bool = False) -> dict:
    """Viscous half-space under a constant force F from t = 0, implicit stepping in impulse form.

    At each output time t_k the impulse increment is dI = F (t_k - t_{k-1}); one
    force-controlled contact problem (:func:`polonsky_keer`) gives the impulse-density
    increment dP >= 0 (Pa s) with sum(dP) dx^2 = dI, compliance 1/eta and separation
    h + u_prev, where u_prev = K[P_total]/eta is the accumulated surface deflection (kept
    as an array and advanced by K[dP]/eta from the solver's last operator apply). Each
    solve is warm-started from the previous dP scaled by the ratio of impulses. The depth
    at t_k is that solve's rigid-body approach; contact area A_k = dx^2 count(dP > 0),
    contact length l = 2 sqrt(A / pi).

    Parameters
    ----------
    h : (ny, nx) indenter height above its tip; mask : (ny, nx) bool footprint;
    dx : element side; eta : shear viscosity; force : constant force F;
    t_out : increasing output times (> 0); tol, max_iter, precondition : passed to the CG.

    Returns
    -------
    dict(t, depth, contact_length, iterations (total CG iterations), solves).
    """
    h = np.asarray(h, dtype=np.float64)
    ny, nx = h.shape
    t_out = np.asarray(t_out, dtype=np.float64)
    if t_out.ndim != 1 or t_out.size == 0 or t_out[0] <= 0.0 or np.any(np.diff(t_out) <= 0.0):
        raise ValueError(f"t_out must be increasing positive times, got {t_out}")
    if not eta > 0.0:
        raise ValueError(f"eta must be positive, got {eta}")
    op = FftOperator(nx, ny, dx)
    u_prev = np.zeros_like(h)
    depth = np.empty_like(t_out)
    length = np.empty_like(t_out)
    total_iter = 0
    d_p = None
    di_prev = None
    t_prev = 0.0
    for k, tk in enumerate(t_out):
        di = force * (tk - t_prev)
        p0 = None if d_p is None else d_p * (di / di_prev)
        d_p, d, it, _, kdp = polonsky_keer(op, h + u_prev, mask, di, 1.0 / eta, tol=tol,
                                           max_iter=max_iter, p0=p0, return_deflection=True,
                                           precondition=precondition)
        u_prev += kdp / eta
        depth[k] = d
        area = dx * dx * np.count_nonzero(d_p > 0.0)
        length[k] = 2.0 * np.sqrt(area / np.pi)
        total_iter += it
        di_prev, t_prev = di, tk
    return dict(t=t_out, depth=depth, contact_length=length, iterations=total_iter,
                solves=len(t_out))


def paraboloid_closed_form(c: float, force: float, eta: float, t):
    """Lee-Radok: d = (3 F t sqrt(2c) / (16 eta))^(2/3), l = 2 sqrt(d / (2c))."""
    t = np.asarray(t, dtype=np.float64)
    d = (3.0 * force * t * np.sqrt(2.0 * c) / (16.0 * eta)) ** (2.0 / 3.0)
    return d, 2.0 * np.sqrt(d / (2.0 * c))


# ---------------------------------------------------------------------------------------------
# Paper case
# ---------------------------------------------------------------------------------------------

def _check_operator() -> float:
    rng = np.random.default_rng(0)
    nx, ny, dx = 13, 9, 0.37
    op = FftOperator(nx, ny, dx)
    p = rng.random((ny, nx))
    u_fft = op.apply(p)
    u_dense = (op.dense_matrix() @ p.ravel()).reshape(ny, nx)
    return float(np.max(np.abs(u_fft - u_dense)) / np.max(np.abs(u_dense)))


def _paper_case(n: int = 257, edge: float = 2.56, c: float = 1.0, eta: float = 1.0,
                force: float = 1.0, t_out=(1.0, 2.0, 3.0, 4.0, 5.0), tol: float = 1e-10):
    dx = edge / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    h = c * (x[None, :] ** 2 + x[:, None] ** 2)
    mask = np.ones((n, n), dtype=bool)
    start = time.perf_counter()
    res = viscous_bem(h, mask, dx, eta, force, t_out, tol)
    wall = time.perf_counter() - start
    return res, wall


def main(argv=None) -> None:
    global FFT_WORKERS
    parser = argparse.ArgumentParser(description="numpy reference of the mdrvisc viscous BEM: "
                                     "the paper's paraboloid case (c = 1) on n x n grids")
    parser.add_argument("n", type=int, nargs="*", default=[257], help="grid sizes (257)")
    parser.add_argument("--workers", type=int, default=FFT_WORKERS,
                        help="scipy.fft workers (-1: all cores, the default)")
    args = parser.parse_args(argv)
    FFT_WORKERS = args.workers
    grids = args.n
    print(f"FFT operator vs dense matrix, random 13 x 9 field: max relative difference "
          f"{_check_operator():.2e}")
    c, eta, force = 1.0, 1.0, 1.0
    for n in grids:
        res, wall = _paper_case(n, c=c, eta=eta, force=force)
        d_ex, l_ex = paraboloid_closed_form(c, force, eta, res["t"])
        print(f"\nparaboloid c = {c}, {n} x {n} elements over 2.56 m, eta = {eta}, F = {force}")
        print(f"wall time {wall:.3f} s, solves {res['solves']}, total CG iterations "
              f"{res['iterations']}")
        print(f"{'t':>5} {'d BEM':>12} {'d exact':>12} {'rel err':>10} "
              f"{'l BEM':>12} {'l exact':>12} {'rel err':>10}")
        for tk, d, de, length, le in zip(res["t"], res["depth"], d_ex, res["contact_length"], l_ex):
            print(f"{tk:5.2f} {d:12.8f} {de:12.8f} {(d - de) / de:10.2e} "
                  f"{length:12.8f} {le:12.8f} {(length - le) / le:10.2e}")


if __name__ == "__main__":
    main()
