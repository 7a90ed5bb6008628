"""Mindlin's sphere on a near-incompressible block (nu = 0.47, Dundurs' beta = 0.057): mindlin-sphere's
set-up (cases/mindlin_sphere.py) with nu = 0.47, for tests/test_tresca_laws.py (a small slip at one
random state of the law check, level 1). Not registered: a report needs two levels with the
reference beyond, and level 2 (1.4e6 dofs) is out of reach at nu = 0.47. GMRES with the V-cycle
misses its tolerance there (500 steps leave 1.2e-9 against 1.2e-11: the V-cycle alone needs 262
CG iterations against 64 at nu = 0.3), and Newton's fallback to a sparse LU took more than 23
GiB; it is now refused in one line (``solvers.newton.DIRECT_FALLBACK_DOFS_3D``).
"""
from harness.problem import mindlin_sphere_case

name = "mindlin-sphere-nu47"
description = "Mindlin's sphere: rigid sphere pressed into a near-incompressible block (nu = 0.47), then sheared, 3D"
globals().update(mindlin_sphere_case(poisson=0.47, mu=0.3, xi=0.002))
