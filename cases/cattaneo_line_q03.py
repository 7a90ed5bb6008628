"""Cattaneo line contact, nu = 0.3, Q/(mu_F P) near 0.3: a rigid cylinder pressed into an elastic block, then sheared.

Cattaneo's problem (1938; K.L. Johnson, Contact Mechanics, 1985, Sect. 7.1, not read here) is the
textbook check of a Coulomb code: press, then shear without sliding; a stick zone |x| < c stays,
c/a = sqrt(1 - Q/(mu_F P)). The set-up, the load history and the predictions (Hertz's a, p0 and
Cattaneo's c and shear q at the row's computed P and Q) are ``harness.problem.cattaneo.cattaneo_line_case``'s;
the closed forms ``harness.problem.closed_forms``'s; the mathematics docs/theory/coulomb.md.

What is exact and what is not. Cattaneo assumes uncoupled normal and tangential responses
(Dundurs' beta = 0) and half-spaces. Against a rigid cylinder beta = (1 - 2 nu)/(2 (1 - nu)) =
0.286 here, and the block is finite (10 a). The normal step itself leaves an antisymmetric
interfacial shear (the surface is drawn inward under the pressure; Spence, J. Elasticity 5 (1975)
297-319, not read), from which the tangential step starts: the deviation from Cattaneo measured
here is the coupling's share, not a discretisation error.
The figures: the report's Coulomb section (its table against Cattaneo).

xi (the top's tangential motion) is data, chosen once so that Q/(mu_F P) comes near 0.3 on this
mesh; every comparison is at the computed ratio. mu_F = 0.3, as the dolfinx_contact friction demos.
No rate theorem for Coulomb: nu, expected_rate and theorem are left out; errors against nitsche's
solution one level finer. Two load steps per level; the fine profile runs it.
"""
from harness.problem import cattaneo_line_case

name = "cattaneo-line-q03"
description = "Cattaneo line contact: rigid cylinder pressed into an elastic block (nu = 0.3), then sheared to Q/(mu_F P) near 0.3"
globals().update(cattaneo_line_case(poisson=0.3, mu=0.3, xi=0.0023))
report_levels = {"default": 4, "fine": 5}
