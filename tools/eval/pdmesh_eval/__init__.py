"""Shared code of the evaluation tools (tools/eval/report, tools/eval/compare, tools/cases/make_corpus.py): reading
geometry, node and mesh files, running pdmesh and Gmsh, PNG helpers. Python 3 standard library only, except
metric.py and aniso_tools.py (the anisotropic measures and anchors, tools/eval/aniso_anchors.py), which
need numpy and are imported only by name."""
