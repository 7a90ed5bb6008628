"""
ParaView files
==============

``run --vtk`` (or the ``VtkWriter`` hook in Python) writes every level's u_h on Ω and the
contact fields on Γ_C as VTK files, one collection (``.pvd``) per case and method, whose time
slider steps through the levels.
"""

# %%
import tempfile
from pathlib import Path

import meshio

import harness

folder = Path(tempfile.mkdtemp()) / "vtk"
harness.run("transition-r32", methods=["nodal"], levels=2, show_progress=False, on_level=harness.VtkWriter(folder))
for path in sorted(folder.rglob("*")):
    if path.is_file():
        print(path.relative_to(folder))

# %%
# Each file reads back with meshio (or in ParaView: open ``omega.pvd``):
omega = next(p for p in sorted(folder.rglob("*.vtu")) if "omega" in p.name)
mesh = meshio.read(omega)
print(mesh, "\npoint data:", list(mesh.point_data))
