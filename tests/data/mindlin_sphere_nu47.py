"""Mindlin's sphere on a near-incompressible block (nu = 0.47, Dundurs' beta = 0.057): mindlin-sphere's
set-up (cases/mindlin_sphere.py) with nu = 0.47, for tests/test_tresca_laws.py (a small slip at one
random state of the law check, level 1). Not registered: at nu = 0.47 the level-2 solve (1.4e6
dofs) was killed for memory past 23 GiB (the only large allocation on that path is the sparse LU
Newton falls back to when GMRES with the V-cycle misses its tolerance: likely, not confirmed),
and a report needs two levels with the reference beyond.
"""
from harness.problem import mindlin_sphere_case

name = "mindlin-sphere-nu47"
description = "Mindlin's sphere: rigid sphere pressed into a near-incompressible block (nu = 0.47), then sheared, 3D"
globals().update(mindlin_sphere_case(poisson=0.47, mu=0.3, xi=0.002))
