#!/usr/bin/env python3
"""A solver's loop around pdmesh.MovingMesher (docs/motion.md, "Stepping from Python"): NACA 0012
pitching ±10° about the quarter chord, posed step by step as a solver would, and a field carried from
each step's nodes to the next by pdmesh.transfer: u = x + 2y, a stand-in for a solution, which a
linear transfer keeps exactly away from the body (poses: docs/motion.md, "Stepping from Python").

    .venv/bin/python examples/pitching_loop.py [STEPS]   (default 40; about 1 s a step)
"""
import math
import os
import sys

import numpy as np

import pdmesh

steps = int(sys.argv[1]) if len(sys.argv) > 1 else 40
case = os.path.join(os.path.dirname(os.path.abspath(__file__)), "naca0012_pitch", "case.toml")
m = pdmesh.MovingMesher(case)  # step 0 (cold); moving curves and pivot from the case's [motion]
previous, u = m.last, m.mesh.points @ np.array([1.0, 2.0])
for k in range(1, steps + 1):
    t = k / steps  # the case's 10*sin(2*_pi*t), with π (muParser's _pi is 3.141592653589)
    m.move(rotate=10 * math.sin(2 * math.pi * t))  # degrees about the pivot, absolute
    s = m.step(t=t)
    u = pdmesh.transfer(previous.mesh, u, s.mesh.points)  # the solver would advance u here
    far = np.hypot(*(s.mesh.points - (0.5, 0)).T) > 1.0  # away from where the body was and is
    error = np.abs(u - s.mesh.points @ np.array([1.0, 2.0]))[far].max()
    print(f"step {k}: {len(s.node_id)} nodes, {100 * s.ids_kept:.1f} % ids kept, min angle "
          f"{s.min_angle:.1f}, {s.wall_s:.2f} s, transfer error far from the body {error:.1e}")
    previous = s
