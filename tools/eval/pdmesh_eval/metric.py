"""Anisotropic mesh measures of the Unstructured Grid Adaptation Working Group (UGAWG) in 2-D, with
the standard library and numpy only: the analytic metric fields of issue 37's cases, metric edge
lengths and the unit-mesh window, the mean-ratio quality in the metric, the complexity C = ∫√det M
with the ideal element count 4C/√3, and the tanh layer's P1 interpolation error.

Metrics are arrays of shape (N, 3) holding (m11, m12, m22); meshes are points (N, 2) and triangles
(T, 3) of 0-based indices, as numpy arrays."""

import math

import numpy as np

SQRT2 = math.sqrt(2.0)
WINDOW = (1.0 / SQRT2, SQRT2)


# ---- metric fields -------------------------------------------------------------------------------

def metric_from_sizes(h1, h2, angle):
    """M = R diag(1/h1², 1/h2²) Rᵀ with R the rotation by `angle` (radians): size h1 along the
    direction (cos angle, sin angle), h2 across it. Returns (N, 3) = (m11, m12, m22)."""
    h1, h2, angle = np.broadcast_arrays(*(np.asarray(v, float) for v in (h1, h2, angle)))
    c, s = np.cos(angle), np.sin(angle)
    a, b = 1.0 / h1 ** 2, 1.0 / h2 ** 2
    return np.stack([a * c * c + b * s * s, (a - b) * c * s, a * s * s + b * c * c], axis=-1).reshape(-1, 3)


def linear_metric(p):
    """linear: h_x = 0.1, h_y = 0.001 + 0.198·|y − 0.5| on the unit square."""
    p = np.asarray(p, float).reshape(-1, 2)
    return metric_from_sizes(0.1, 0.001 + 0.198 * np.abs(p[:, 1] - 0.5), 0.0)


def _polar(p, h_t):
    p = np.asarray(p, float).reshape(-1, 2)
    r = np.hypot(p[:, 0], p[:, 1])
    return metric_from_sizes(0.001 + 0.198 * np.abs(r - 0.5), h_t(r), np.arctan2(p[:, 1], p[:, 0]))


def polar1_metric(p):
    """polar-1: h_r = 0.001 + 0.198·|r − 0.5| along the radius, h_t = 0.1 (r = |(x, y)|)."""
    return _polar(p, lambda r: np.full_like(r, 0.1))


def polar2_h_t(r):
    """polar-2's tangential size: d = 10·(0.6 − r), h_t = d/40 + (1 − d)/10 for d ≥ 0, else 0.1."""
    d = 10.0 * (0.6 - r)
    return np.where(d >= 0.0, d / 40.0 + (1.0 - d) / 10.0, 0.1)


def polar2_metric(p):
    """polar-2: as polar-1 with h_t graded to 0.025 at the wall r = 0.5."""
    return _polar(p, polar2_h_t)


# ---- tanh layer and its Hessian metric -----------------------------------------------------------

TANH_A = 100.0


def tanh_u(p):
    """u = tanh(100·(y − 0.5 − 0.25·sin 2πx))."""
    p = np.asarray(p, float).reshape(-1, 2)
    return np.tanh(TANH_A * (p[:, 1] - 0.5 - 0.25 * np.sin(2 * np.pi * p[:, 0])))


def tanh_hessian(p):
    """The exact Hessian of tanh_u, (N, 3) = (u_xx, u_xy, u_yy)."""
    p = np.asarray(p, float).reshape(-1, 2)
    x, y = p[:, 0], p[:, 1]
    g = y - 0.5 - 0.25 * np.sin(2 * np.pi * x)
    gx = -0.5 * np.pi * np.cos(2 * np.pi * x)
    gxx = np.pi ** 2 * np.sin(2 * np.pi * x)
    t = np.tanh(TANH_A * g)
    f1 = TANH_A * (1 - t * t)                      # d/dg tanh(a g)
    f2 = -2 * TANH_A * TANH_A * t * (1 - t * t)    # d²/dg²
    return np.stack([f2 * gx * gx + f1 * gxx, f2 * gx, f2], axis=-1)


def _sym_eig(m):
    """Eigen-decomposition of symmetric 2x2 matrices given as (N, 3)."""
    mat = np.stack([np.stack([m[:, 0], m[:, 1]], -1), np.stack([m[:, 1], m[:, 2]], -1)], -2)
    return np.linalg.eigh(mat)


def abs_clipped(h, lam_min, lam_max=np.inf):
    """|H| = R |Λ| Rᵀ with each |λ| clipped to [lam_min, lam_max]: an SPD matrix, (N, 3)."""
    lam, vec = _sym_eig(np.asarray(h, float))
    lam = np.clip(np.abs(lam), lam_min, lam_max)
    m = np.einsum("nik,nk,njk->nij", vec, lam, vec)
    return np.stack([m[:, 0, 0], m[:, 0, 1], m[:, 1, 1]], -1)


# |H|'s eigenvalues are floored here before det|H|^(-1/6) is taken (where u is flat, H = 0); the
# tanh layer's Hessian is ~1e4 inside the layer, so the floor only touches where u is constant.
HESSIAN_FLOOR = 1e-8


def l2_optimal_scale(hessian, complexity, grid=1024):
    """D of the L2-optimal metric (Loseille-Alauzet, 2-D, L^p with p = 2): M = D·det|H|^(−1/6)·|H|
    has complexity ∫√det M = D·∫det|H|^(1/3) = C, so D = C / ∫det|H|^(1/3), the integral over the
    unit square by the midpoint rule on a grid x grid grid (|H| floored by HESSIAN_FLOOR). The size
    clipping of l2_optimal_metric comes after and changes C slightly (aniso_anchors.py reports it)."""
    s = (np.arange(grid) + 0.5) / grid
    total = 0.0
    for row in np.array_split(np.arange(grid), 16):
        x, y = np.meshgrid(s, s[row])
        h = abs_clipped(hessian(np.column_stack([x.ravel(), y.ravel()])), HESSIAN_FLOOR)
        total += np.sum(np.abs(h[:, 0] * h[:, 2] - h[:, 1] ** 2) ** (1.0 / 3.0))
    return complexity / (total / grid ** 2)


def l2_optimal_metric(hessian, scale, hmin=1e-5, hmax=0.3):
    """M(p) = D·det|H|^(−1/6)·|H| at the points p, then its eigenvalues clipped to
    [1/hmax², 1/hmin²] (sizes between hmin and hmax)."""
    def metric(p):
        h = abs_clipped(hessian(p), HESSIAN_FLOOR)
        det = np.abs(h[:, 0] * h[:, 2] - h[:, 1] ** 2)
        return abs_clipped(h * (scale * det ** (-1.0 / 6.0))[:, None], 1.0 / hmax ** 2, 1.0 / hmin ** 2)
    return metric


# ---- measures -------------------------------------------------------------------------------------

def edges(triangles):
    """The unique edges (E, 2) of the triangles, smaller index first."""
    t = np.asarray(triangles, int)
    e = np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]])
    return np.unique(np.sort(e, axis=1), axis=0)


def _quad(m, v):
    return m[:, 0] * v[:, 0] ** 2 + 2 * m[:, 1] * v[:, 0] * v[:, 1] + m[:, 2] * v[:, 1] ** 2


def edge_lengths(points, edge_list, metric_at_points):
    """UGAWG metric edge length: La = √(vᵀM_a v), Lb likewise at the other end, and
    L = (La − Lb)/ln(La/Lb) (exact when the size varies geometrically along the edge), or
    (La + Lb)/2 when |La − Lb| ≤ 1e-3."""
    p = np.asarray(points, float)
    m = np.asarray(metric_at_points, float)
    e = np.asarray(edge_list, int)
    v = p[e[:, 1]] - p[e[:, 0]]
    la, lb = np.sqrt(_quad(m[e[:, 0]], v)), np.sqrt(_quad(m[e[:, 1]], v))
    close = np.abs(la - lb) <= 1e-3
    with np.errstate(divide="ignore", invalid="ignore"):
        log = (la - lb) / np.log(la / lb)
    return np.where(close, 0.5 * (la + lb), log)


def qualities(points, triangles, metric_at_points):
    """UGAWG mean-ratio quality in the metric: Q = 4√3·|K|·√det M / Σ l²_M over the three edges,
    with M the corner metric of largest det and |K| the (signed) physical area: 1 for a triangle
    equilateral in M, ≤ 0 for an inverted one."""
    p = np.asarray(points, float)
    t = np.asarray(triangles, int)
    m = np.asarray(metric_at_points, float)
    det = m[:, 0] * m[:, 2] - m[:, 1] ** 2
    pick = t[np.arange(len(t)), np.argmax(det[t], axis=1)]
    mk = m[pick]
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    area = 0.5 * ((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    sum_l2 = _quad(mk, b - a) + _quad(mk, c - b) + _quad(mk, a - c)
    return 4.0 * math.sqrt(3.0) * area * np.sqrt(det[pick]) / sum_l2


# Gauss-Legendre on [0, 1] and a collapsed (Duffy) rule on the reference triangle (0,0),(1,0),(0,1).
def gauss01(n):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1.0), 0.5 * w


def triangle_rule(n):
    """Collapsed Gauss rule with n² points: barycentric-free reference coordinates (ξ, η) and weights
    summing to 1/2; exact for polynomials of degree ≤ 2n − 2."""
    s, ws = gauss01(n)
    xi = np.repeat(s, n)
    eta = np.tile(s, n) * (1.0 - xi)
    w = np.repeat(ws, n) * np.tile(ws, n) * (1.0 - xi)
    return xi, eta, w


def interpolation_error(points, triangles, u, order=8):
    """(e_L2, e_max): the L2 norm of u − Π_h u (Π_h the P1 interpolant at the vertices) by the
    collapsed Gauss rule of `order`² points per triangle (exact for the integrand (u − Π_h u)² when u
    is a polynomial of degree ≤ order − 1), and the largest |u − Π_h u| at those points."""
    p = np.asarray(points, float)
    t = np.asarray(triangles, int)
    xi, eta, w = triangle_rule(order)
    uv = u(p)
    a, b, c = p[t[:, 0]], p[t[:, 1]], p[t[:, 2]]
    jac = np.abs((b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0]))
    total, worst = 0.0, 0.0
    for chunk in np.array_split(np.arange(len(t)), max(1, len(t) // 20000)):
        q = (a[chunk, None, :] + xi[None, :, None] * (b - a)[chunk, None, :]
             + eta[None, :, None] * (c - a)[chunk, None, :])
        exact = u(q.reshape(-1, 2)).reshape(len(chunk), -1)
        ua, ub, uc = uv[t[chunk, 0]], uv[t[chunk, 1]], uv[t[chunk, 2]]
        interp = ua[:, None] + xi[None, :] * (ub - ua)[:, None] + eta[None, :] * (uc - ua)[:, None]
        err = exact - interp
        total += float(np.sum(jac[chunk] * (err ** 2 @ w)))
        worst = max(worst, float(np.max(np.abs(err))) if err.size else 0.0)
    return math.sqrt(total), worst


# ---- complexity ------------------------------------------------------------------------------------

def sqrt_det(metric, p):
    m = metric(p)
    return np.sqrt(np.maximum(m[:, 0] * m[:, 2] - m[:, 1] ** 2, 0.0))


def complexity_square(metric, panels=400, order=4):
    """C = ∫√det M over the unit square by tensor Gauss-Legendre (`panels`² cells of `order`² points;
    cell faces at x, y = 0.5 where the cases' sizes have a kink)."""
    s, w = gauss01(order)
    cells = (np.arange(panels)[:, None] + s[None, :]).ravel() / panels
    weights = np.tile(w, panels) / panels
    total = 0.0
    for row in np.array_split(np.arange(len(cells)), 32):
        x, y = np.meshgrid(cells, cells[row])
        f = sqrt_det(metric, np.column_stack([x.ravel(), y.ravel()])).reshape(x.shape)
        total += float(weights[row] @ f @ weights)
    return total


def complexity_square_minus_disc(metric, radius=0.5, panels=(400, 200), order=4):
    """C = ∫√det M over [0,1]² minus the disc r < radius, in polar coordinates (r, θ), θ ∈ [0, π/2],
    r from the radius to the square's edge 1/max(cos θ, sin θ); tensor Gauss-Legendre with `panels`
    (radial, angular) panels of `order` points, the radial panels graded quadratically towards the
    wall where the cases' radial size is smallest. The Jacobian r is included."""
    s, w = gauss01(order)
    nr, nt = panels
    t_nodes = (np.arange(nt)[:, None] + s[None, :]).ravel() / nt * (np.pi / 2)
    t_weights = np.tile(w, nt) / nt * (np.pi / 2)
    edges_r = (np.arange(nr + 1) / nr) ** 2
    lo, width = edges_r[:-1], np.diff(edges_r)
    u = (lo[:, None] + width[:, None] * s[None, :]).ravel()         # in [0, 1]
    uw = (width[:, None] * w[None, :]).ravel()
    total = 0.0
    for theta, wt in zip(t_nodes, t_weights):
        rmax = 1.0 / max(math.cos(theta), math.sin(theta))
        r = radius + (rmax - radius) * u
        f = sqrt_det(metric, np.column_stack([r * math.cos(theta), r * math.sin(theta)]))
        total += wt * (rmax - radius) * float(np.sum(uw * f * r))
    return total


def ideal_triangles(complexity):
    """The unit mesh's triangle count 4C/√3 (a metric-equilateral triangle of unit edges has metric
    area √3/4)."""
    return 4.0 * complexity / math.sqrt(3.0)


# ---- the report of one mesh ----------------------------------------------------------------------

def histogram(values, bins):
    counts, _ = np.histogram(values, bins=bins)
    return [int(c) for c in counts]


Q_BINS = [-np.inf, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, np.inf]


def metric_report(points, triangles, metric, complexity=None):
    """The UGAWG figures of one mesh in the metric field `metric` (a function of (N, 2) points)."""
    p = np.asarray(points, float)
    t = np.asarray(triangles, int)
    m = metric(p)
    lengths = edge_lengths(p, edges(t), m)
    q = qualities(p, t, m)
    inside = (lengths >= WINDOW[0]) & (lengths <= WINDOW[1])
    out = {
        "vertices": int(len(p)), "triangles": int(len(t)), "edges": int(len(lengths)),
        "window_percent": 100.0 * float(np.mean(inside)),
        "L_min": float(lengths.min()), "L_max": float(lengths.max()),
        "Q_min": float(q.min()), "Q_mean": float(q.mean()),
        "Q_below_0.3_percent": 100.0 * float(np.mean(q < 0.3)),
        "Q_histogram": {"bins": [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0],
                        "counts": histogram(q, Q_BINS)},
    }
    if complexity is not None:
        out["complexity"] = complexity
        out["ideal_triangles"] = ideal_triangles(complexity)
        out["N_over_ideal"] = len(t) / ideal_triangles(complexity)
    return out
