"""Mindlin's sphere, nu = 0.47: mindlin-sphere's set-up on a near-incompressible block.

Why this case. Of the three approximations that separate a rigid-indenter computation from
Mindlin's c (mindlin-sphere's docstring), the coupling is the largest at nu = 0.3: Dundurs'
beta = (1 - 2 nu)/(2 (1 - nu)) = 0.286 there, 0.057 here, as the cattaneo-line-*-nu47 line cases
do in 2D. What is left is Mindlin's own approximation (the traction parallel to Q; Cerruti's
transverse displacement, of relative size about nu/(2 - nu) = 0.31 here: larger than at nu = 0.3)
and the finite block. Reading the two spheres side by side separates the coupling's share from
Mindlin's: the report's Coulomb section (its table against Cattaneo and Mindlin).

xi = 0.002 as mindlin-sphere (data; every comparison is at the computed P and Q). No rate theorem
for Coulomb: errors against nitsche's solution one level finer. The fine profile runs it on level
0 (23,817 dofs) against level 1: the level-1 row's reference, level 2 (1.4e6 dofs), ran out of
this machine's 24 GB (at nu = 0.47 the V-cycle's GMRES does not converge in its 500 steps, and
Newton's linear solve falls back to a sparse LU; mindlin-sphere at nu = 0.3 runs level 1).
Compare it with mindlin-sphere's level-0 row.
"""
from harness.problem import mindlin_sphere_case

name = "mindlin-sphere-nu47"
description = "Mindlin's sphere: rigid sphere pressed into a near-incompressible block (nu = 0.47), then sheared, 3D"
globals().update(mindlin_sphere_case(poisson=0.47, mu=0.3, xi=0.002))
report_levels = {"fine": 1}
