"""Cattaneo line contact, nu = 0.47 (near incompressible), Q/(mu_F P) near 0.3.

Why this case. Cattaneo's problem (1938; K.L. Johnson, Contact Mechanics, 1985, Sect. 7.1, not
read here) is the textbook check of a Coulomb friction code: press a cylinder onto a body, then
shear it without sliding; a stick zone |x| < c stays, surrounded by slip, and
c/a = sqrt(1 - Q/(mu_F P)). This case and cattaneo-line-q07-nu47 read the harness's Coulomb discretisation
against it at two load ratios.

What is exact and what is not. Cattaneo's solution (the closed forms in
``harness.problem.closed_forms``; docs/theory/coulomb.md, "Cattaneo and Mindlin") assumes that the
normal and tangential responses uncouple, Dundurs' beta = 0, and half-spaces. Here nu = 0.47 against a rigid cylinder: beta =
(1 - 2 nu)/(2 (1 - nu)) = 0.057, a fifth of the nu = 0.3 pair's 0.286. Cattaneo would be exact at
nu = 1/2 (beta = 0), which a displacement method cannot reach (lambda = infinity); at nu = 0.47
P2 locking is mild (lambda/mu = 15.7), while nearer 1/2 it grows (nu = 0.49, lambda/mu = 49).
The block is finite (10 a), as hertz-line's: a and p0 move by a fraction of a percent
(hertz-line's docstring). So the rows' ``qoi_stick_measure`` = 2 c_h against Cattaneo's 2c
(``predicted_friction``, at the row's computed P = ``qoi_force`` and Q = ``qoi_tangential_force``)
and ``err_traction_prediction`` (the shear traction against Cattaneo's q at the same P, Q) measure
mostly discretisation and the remaining coupling (beta = 0.057). The figures: the report's Coulomb section (its table against Cattaneo). 

Setup. hertz-line's block, cylinder and mesh (Omega = (-L, L) x (0, H), L = H = 1 = 10 a, R = 1,
E = 1, parabolic gap x^2/(2R), Gamma_C corners at +-2a with maxh a/4 there, maxh 0.25 elsewhere),
Poisson ratio 0.47, Coulomb friction mu_F = 0.3 (steel on steel, and the coefficient of the
dolfinx_contact friction demos, so their Cattaneo comparison and this one share it; with
beta/mu_F 0.19 for the coupling). Load history (``harness.problem.cattaneo.cattaneo_line_case``):
the normal step u = (0, -0.015) on the top, then the tangential step u = (0.0027, -0.015). xi is
data, chosen once so that Q/(mu_F P) comes near 0.3 on this mesh; every
comparison is at the computed ratio, not at 0.3.

Rate. No convergence theorem for Coulomb friction was found (docs/theory/coulomb.md, "What is
proven"): nu, expected_rate and theorem are left out, and the report gives measured rates only,
against nitsche's solution one level finer (``reference_levels``).

Cost. Two load steps per level; the fine profile runs it (its phases: the report's study table).
"""
from harness.problem import cattaneo_line_case

name = "cattaneo-line-q03-nu47"
description = "Cattaneo line contact: rigid cylinder pressed into an elastic block (nu = 0.47), then sheared to Q/(mu_F P) near 0.3"
globals().update(cattaneo_line_case(poisson=0.47, mu=0.3, xi=0.0027))
report_levels = {"default": 4, "fine": 5}
