"""pdmesh: physics-based point placement and triangle meshing (Fackler's method), from Python.

    import pdmesh
    geo = pdmesh.Geometry.from_file("airfoil.crv", "farfield.crv")
    mesh = pdmesh.generate(geo, size=lambda xy: 0.01 + 0.05 * abs(xy[:, 1]), seed=1, progress=True)
    mesh.points, mesh.triangles, mesh.boundary_edges, mesh.quality()
    mesh.write("out.msh")

See docs/python.md. The C++ core is the same as the ``pdmesh`` command's: the same validation,
messages, results (bit-identical on the host device for the same case and seed) and writers.
"""

from . import _core, size
from ._progress import Progress
from .errors import Cancelled, DeviceError, Error, GeometryError, InputError, LimitError, SimulationError
from .geometry import Geometry
from .mesh import Mesh, PeriodicPairs
from .mesher import Case, Mesher, State, generate
from ._smooth import smooth
from ._adapt import adapt, adapt_mesher
from .motion import MotionStep, MovingMesher, run_motion, transfer

__version__ = _core.version


def case_keys() -> list[str]:
    """Every valid case-file key (what settings= and keywords accept)."""
    return list(_core.case_keys())


__all__ = [
    "Cancelled", "Case", "DeviceError", "Error", "Geometry", "GeometryError", "InputError", "LimitError", "Mesh",
    "Mesher", "MotionStep", "MovingMesher", "PeriodicPairs", "Progress", "SimulationError", "State", "adapt",
    "adapt_mesher", "case_keys", "generate", "run_motion", "size", "smooth", "transfer", "__version__",
]
