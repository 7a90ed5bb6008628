"""
Writing a case
==============

A case is one Python file: the domain and its boundary parts, the data, the exact solution if
there is one, its regularity ν and the rate the paper's theorem gives. This one moves the r^{3/2}
transition to x = 1/3, a point no mesh of the study has as a vertex
(``examples/cases/transition_off_vertex.py``).
"""

# %%
from pathlib import Path

import harness

here = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()
path = next(p / "examples" / "cases" / "transition_off_vertex.py" for p in [here, *here.parents]
            if (p / "examples" / "cases" / "transition_off_vertex.py").is_file())
print(path.read_text().split('"""')[2])          # the case's code, after its docstring

# %%
# ``harness.load_case`` reads and checks the file as the command line does
# (``--case path/to/file.py``).
case = harness.load_case(str(path))
rows = harness.run(case, methods=["paper", "p1"], levels=4, show_progress=False)
print(harness.rates(rows)[["method", "expected_rate", "fitted_rate", "pairwise_rates"]].to_string(index=False))
