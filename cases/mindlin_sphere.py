"""Mindlin's sphere: a rigid sphere pressed into an elastic block (3D, nu = 0.3), then sheared.

Why this case. The 3D counterpart of the Cattaneo line cases: Mindlin's solution (1949; K.L.
Johnson, Contact Mechanics, 1985, Sect. 7.2, not read here) keeps a stick disc r < c inside the
contact disc r < a, with c/a = (1 - Q/(mu_F P))^(1/3) (``harness.problem.closed_forms``;
docs/theory/coulomb.md, "Cattaneo and Mindlin"). The rows' ``qoi_stick_measure`` is the stick
zone's area, read as c_h = sqrt(area / pi), against pi c^2 (``predicted_friction``) at the row's
computed P = ``qoi_force`` and Q = ``qoi_tangential_force``; ``err_traction_prediction`` is the
shear traction's relative L2(Gamma_C) error against Mindlin's q along Q's direction (a transverse
shear counts as error).

What is exact and what is not. Three approximations separate the discrete solution from
Mindlin's c, besides the discretisation:

1. Mindlin's own: the traction is taken parallel to Q everywhere. The stick disc is exact under
   that assumption, but in the slip annulus Cerruti's transverse surface displacement (its size
   relative to the in-line one is of order nu/(2 - nu): 0.18 at nu = 0.3) makes the slip, and
   so the friction force, not exactly parallel to Q. Its effect on c is small in Johnson's
   account (that passage not read here); it vanishes at nu = 0.
2. The coupling: a rigid sphere on a nu = 0.3 body has Dundurs' beta = 0.286 != 0, as the
   cattaneo-line-q03 / q07 cases (nu = 0.3): the normal step already leaves a radial interfacial
   shear, and the tangential step starts from it. In 2D this coupling alone moves c_h / c to
   well below 1 (the report's Coulomb section); it is the dominant share here too.
3. The block is finite (10 a), as hertz-sphere's.

The figures: the report's Coulomb section (its table against Cattaneo). 

Setup. hertz-sphere's box (-L, L)^2 x (0, H), L = H = 1 = 10 a, R = 1, E = 1, parabolic gap
(x^2 + y^2)/(2R), the zone (-2a, 2a)^2 at maxh a/2, maxh 0.5 elsewhere; Coulomb mu_F = 0.3 (as the
Cattaneo cases). Load history (``harness.problem.cattaneo.mindlin_sphere_case``): the normal step
u = (0, 0, -0.01) on the top, then u = (0.002, 0, -0.01); xi = 0.002 is data, giving Q/(mu_F P)
near 0.5 on level 0 (0.003 gives 0.78).

Rate. No convergence theorem for Coulomb friction (docs/theory/coulomb.md): nu, expected_rate and
theorem are left out; errors against nitsche's solution one level finer.

Cost. Two load steps per level; the fine profile runs it (its phases: the report's study table).
"""
from harness.problem import mindlin_sphere_case

name = "mindlin-sphere"
description = "Mindlin's sphere: rigid sphere pressed into an elastic block (nu = 0.3), then sheared, 3D"
globals().update(mindlin_sphere_case(poisson=0.3, mu=0.3, xi=0.002))
report_levels = {"fine": 2}
