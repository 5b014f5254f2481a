#!/usr/bin/env python3
"""Mesh adaptation to a solution: -Δu = f on the unit square, solved by P1 finite elements with
scikit-fem, re-meshed by pdmesh in the L2-optimal metric of the solution's Hessian, repeated.

The exact solution is issue 37's layer, u = tanh(k (y - 0.5 - 0.25 sin 2πx)) (k = 100 in the issue;
default here k = 50), with f = -Δu and u on the boundary. Each loop
1. solves for the P1 solution u_h on the current mesh (scikit-fem),
2. re-meshes with pdmesh's Hessian metric of u_h (pdmesh.adapt_mesher, the command pdmesh adapt from
   Python: u_h on the mesh as values={"u": u_h}, complexity = C: the Hessian by a least-squares
   quadratic fit at every vertex, the
   L2-optimal metric M = D det|H|^(-1/6) |H| whose unit mesh has about 2C/√3 vertices, clipped
   to sizes in [1e-5, 0.3] by hmin and hmax; the other keys at their defaults),
3. prints the vertex count N_v, e_L2 = ||u_h - u||_L2 against the exact solution and e_L2·N_v.
The first adapted mesh starts from scratch (the uniform start mesh is no guess at the metric's nodes);
from the second on, each re-mesh starts warm from the previous mesh's points
(initial=points, the case key init.file): its interior points are the initial
interior nodes, and the relaxation's population control fixes their density. --cold re-meshes every
loop from scratch, for comparison. Each loop's line also gives the re-mesh's time, its iterations and
whether its stopping rule ended it ("settled") or the iteration maximum did ("maximum").

    .venv/bin/python examples/adapt_poisson.py [--k 50] [--complexity 1000] [--loops 5] [--cold]

needs scikit-fem (pip install "pdmesh[adapt]", or .venv/bin/pip install scikit-fem). It stops when
N_v and e_L2·N_v change by less than --tolerance (default 10 %) from one loop to the next.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import dataclass

import numpy as np

import pdmesh

SQUARE = [np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])]


@dataclass
class Layer:
    """u = tanh(k φ), φ = y - 0.5 - 0.25 sin 2πx, and f = -Δu."""

    k: float = 50.0

    def u(self, x, y):
        return np.tanh(self.k * (y - 0.5 - 0.25 * np.sin(2 * np.pi * x)))

    def f(self, x, y):
        phi = y - 0.5 - 0.25 * np.sin(2 * np.pi * x)
        t = np.tanh(self.k * phi)
        s2 = 1.0 - t * t  # sech²
        grad2 = (0.5 * np.pi * np.cos(2 * np.pi * x)) ** 2 + 1.0  # |∇φ|²
        lap_phi = np.pi ** 2 * np.sin(2 * np.pi * x)  # Δφ
        # Δ tanh(kφ) = k sech²(kφ) Δφ - 2 k² tanh(kφ) sech²(kφ) |∇φ|²
        return -(self.k * s2 * lap_phi - 2 * self.k ** 2 * t * s2 * grad2)


def solve(points: np.ndarray, triangles: np.ndarray, layer: Layer) -> tuple[np.ndarray, float]:
    """The P1 solution at the points and its L2 error against the exact solution."""
    import skfem
    from skfem.models.poisson import laplace

    mesh = skfem.MeshTri(np.ascontiguousarray(points.T), np.ascontiguousarray(triangles.T, dtype=np.int64))
    basis = skfem.Basis(mesh, skfem.ElementTriP1(), intorder=4)

    @skfem.LinearForm
    def load(v, w):
        return layer.f(w.x[0], w.x[1]) * v

    a = laplace.assemble(basis)
    b = load.assemble(basis)
    boundary = mesh.boundary_nodes()
    u = np.zeros(basis.N)
    u[boundary] = layer.u(*mesh.p[:, boundary])
    u = skfem.solve(*skfem.condense(a, b, x=u, D=boundary))

    fine = skfem.Basis(mesh, skfem.ElementTriP1(), intorder=8)

    @skfem.Functional
    def squared_error(w):
        return (w["uh"] - layer.u(w.x[0], w.x[1])) ** 2

    error = float(np.sqrt(squared_error.assemble(fine, uh=fine.interpolate(u))))
    return u, error


def remesh(points, triangles, u, complexity, seed, warm=False):
    """pdmesh's mesh of the square in the Hessian metric of the data u on (points, triangles); with
    warm, started from the points. Also returns the re-mesh's iterations and whether its stopping rule
    ended it (its nodes had settled) rather than the iteration maximum."""
    mesher = pdmesh.adapt_mesher(SQUARE, (points, triangles), "u", values=u, complexity=complexity, hmin=1e-5,
                                 hmax=0.3, device="host", seed=seed, initial=points if warm else None)
    mesher.run()
    mesh = mesher.triangulate()
    return np.array(mesh.points), np.array(mesh.triangles), mesher.iteration, mesher.converged


def adapt(layer: Layer, complexity: float, loops: int, tolerance: float = 0.1, start: float = 0.05, seed: int = 1,
          report=print, warm: bool = True) -> list[dict]:
    """The adaptation loop; returns one row per loop (vertices, e_L2, e_L2·N_v, and the seconds, the
    iterations and whether the stopping rule ended the re-mesh that made its mesh), the first on the
    uniform start mesh of size `start`. With warm, the re-meshes from the second on start from the
    previous mesh's points."""
    mesh = pdmesh.generate(SQUARE, size=start, device="host", seed=seed)
    points, triangles = np.array(mesh.points), np.array(mesh.triangles)
    rows = []
    seconds, iterations, settled = 0.0, 0, False
    for loop in range(loops + 1):
        u, error = solve(points, triangles, layer)
        rows.append({"loop": loop, "vertices": len(points), "e_L2": error, "e_L2_Nv": error * len(points),
                     "remesh_s": seconds, "remesh_iterations": iterations, "remesh_settled": settled})
        report(f"loop {loop}: N_v = {len(points):6d}   e_L2 = {error:.3e}   e_L2*N_v = {error * len(points):.3f}"
               + (f"   re-mesh {seconds:.2f} s, {iterations} iterations ({'settled' if settled else 'maximum'})"
                  if loop else ""))
        if loop >= 2 and all(abs(rows[-1][key] / rows[-2][key] - 1.0) < tolerance
                             for key in ("vertices", "e_L2_Nv")):
            report(f"converged after {loop} adaptations (N_v and e_L2*N_v within {tolerance:.0%})")
            break
        if loop < loops:
            began = time.perf_counter()
            points, triangles, iterations, settled = remesh(points, triangles, u, complexity, seed,
                                                            warm=warm and loop >= 1)
            seconds = time.perf_counter() - began
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--k", type=float, default=50.0, help="the layer's steepness (issue 37: 100)")
    parser.add_argument("--complexity", type=float, default=1000.0, help="C: about 2C/sqrt(3) vertices")
    parser.add_argument("--loops", type=int, default=5, help="the most adaptations")
    parser.add_argument("--tolerance", type=float, default=0.1)
    parser.add_argument("--cold", action="store_true", help="re-mesh every loop from scratch")
    args = parser.parse_args()
    adapt(Layer(args.k), args.complexity, args.loops, args.tolerance, warm=not args.cold)


if __name__ == "__main__":
    main()
