"""A cone of your own, given only by its constraint functionals on Γ_C: P2 with v_h ≥ α at the
vertices of Γ_C and at the points 1/4 and 3/4 of each contact edge (two functionals per edge:
general rows, solved exactly by the harness's general-constraint active set method with its
multigrid, KKT residual recorded). Between `nodal` (the midpoint) and the paper's `mean`, it
controls the trace at two points per edge instead of one. No theorem covers it: its expected rate
is the paper's for a nonconforming P2 cone whose interpolant is as accurate as I_h (our guess,
marked as such); the study measures it. Run it::

    python -m harness run --case transition-r32 --method examples/methods/quarter_points.py --method nodal --levels 5
"""
from harness.methods import Expectation, FunctionalCone


def expected(case):
    # a conjecture, not a theorem: the rate of the paper's cones (Theorems 4.1, 4.2, 5.1, 5.2)
    return Expectation(case.expected_rate, case.expected_log_exponent, "conjecture: as the paper's P2 cones")


method = FunctionalCone(
    name="quarter-points",
    order=2,
    contact="v_h ≥ α at the vertices and at t = 1/4, 3/4 of each contact edge",
    reference="examples/methods/quarter_points.py",
    expected=expected,
    functionals=(((0.25, 1.0),), ((0.75, 1.0),)),
)
