"""
Other codes: DOLFINx and scikit-fem measured like the harness
=============================================================

The harness exports its discrete problems (:doc:`../guide/measure-your-code`): per level the mesh,
the P2 Lagrange nodes, the data, the right-hand side as moments against the Lagrange basis and
the discrete Dirichlet values. Another finite element code solves them and writes its solution's
values at the nodes; the harness rebuilds u_h from them exactly and measures it as one of its own
methods, ``external:DIR``. Two such codes ship in ``examples/codes/``, each an external program
in its own environment (``make codes`` builds both): DOLFINx with PETSc (the paper's ``nodal``
model as bounds of SNES VI, and Nitsche in UFL) and scikit-fem (``nodal`` by a primal-dual active
set method with SciPy). Where an environment is missing, this page says so and measures the
harness's own ``nodal`` solve written in the same format instead.
"""

# %%
import json
import subprocess
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt

import harness

LEVELS = 4
CASE = "transition-r32"
work = Path(tempfile.mkdtemp(prefix="other-codes-"))
manifest = harness.export(CASE, levels=LEVELS, out=work / "export")
print(json.dumps(json.loads(manifest.read_text())["levels"][-1], indent=1))

# %%
# Each driver reads the export and writes a solution folder: a manifest naming the code and the
# harness method it discretises (``like``), and per level the values at the nodes with the
# code's own seconds and iterations. The repository's root holds the drivers and their
# environments (``.venv-dolfinx``, ``.venv-skfem``).
root = Path(harness.__file__).resolve().parents[1]
drivers = {
    "dolfinx-nodal": (".venv-dolfinx", "dolfinx_contact.py", ["--model", "nodal"]),
    "dolfinx-nitsche": (".venv-dolfinx", "dolfinx_contact.py", ["--model", "nitsche"]),
    "skfem-nodal": (".venv-skfem", "skfem_contact.py", []),
}
solved = []
for label, (environment, script, options) in drivers.items():
    python = root / environment / "bin" / "python"
    if not python.exists():
        print(f"{label}: no {environment} here (make codes builds it); left out")
        continue
    out = work / label
    subprocess.run([str(python), str(root / "examples" / "codes" / script), str(work / "export"), str(out), *options],
                   check=True, capture_output=True)
    solved.append(out)

# %%
# Without any other code, the harness's own ``nodal`` solve written as point values shows the
# format's round trip (``harness.solution_writer``): the same errors to round-off.
if not solved:
    harness.run(CASE, methods=["nodal"], levels=LEVELS, show_progress=False,
                on_level=harness.solution_writer(work / "own", CASE, "nodal"))
    solved.append(work / "own")

# %%
# Measure them beside the harness's own ``nodal`` and ``nitsche``: one study, every error the
# harness measures, the rates and their verdicts. Where a code solves the same discrete problem
# as a harness method, its H¹ errors agree with that method's to the solvers' tolerance.
methods = ["nodal", "nitsche", *(f"external:{folder}" for folder in solved)]
rows = harness.run(CASE, methods=methods, levels=LEVELS, show_progress=False)
finest = rows[rows.level == LEVELS - 1].set_index("method")
for folder in solved:
    method = harness.external(folder)
    difference = abs(finest.err_h1[method.name] - finest.err_h1[method.like]) / finest.err_h1[method.like]
    print(f"{method.name:16s} ({method.code}): err_h1 {finest.err_h1[method.name]:.6e}, "
          f"relative difference from {method.like}: {difference:.1e}, {finest.solve_seconds[method.name]:.3g} s per solve")
rates = harness.rates(rows)
print(rates[["method", "expected_rate", "fitted_rate", "verdict"]].to_string(index=False))

# %%
# The convergence plot: each code's H¹ error on the same meshes, on the harness's own lines.
harness.plot(rows)
plt.show()
