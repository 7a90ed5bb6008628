"""Cattaneo line contact, nu = 0.3, Q/(mu_F P) near 0.7.

Why this case. Cattaneo's problem (1938; K.L. Johnson, Contact Mechanics, 1985, Sect. 7.1, not
read here) is the textbook check of a Coulomb friction code: press a cylinder onto a body, then
shear it without sliding; a stick zone |x| < c stays, surrounded by slip, and
c/a = sqrt(1 - Q/(mu_F P)). This case and cattaneo-line-q03 read the harness's Coulomb discretisation
against it at two load ratios.

What is exact and what is not. Cattaneo's solution (the closed forms in
``harness.problem.closed_forms``; docs/theory/coulomb.md, "Cattaneo and Mindlin") assumes that the
normal and tangential responses uncouple, Dundurs' beta = 0, and half-spaces. Here the body is elastic (nu = 0.3) and the
cylinder rigid: beta = (1 - 2 nu)/(2 (1 - nu)) = 0.286, not 0. The normal step itself produces an
antisymmetric interfacial shear (the block's surface is drawn inward under the pressure and
friction resists it; Spence, J. Elasticity 5 (1975) 297-319, not read), and the tangential step
starts from it (Nowell, Hills & Sackfield, J. Mech. Phys. Solids 36 (1988) 59-75, not read): the
stick zone is neither centred nor of Cattaneo's size.
The block is finite (10 a), as hertz-line's: a and p0 move by a fraction of a percent
(hertz-line's docstring). So the rows' ``qoi_stick_measure`` = 2 c_h against Cattaneo's 2c
(``predicted_friction``, at the row's computed P = ``qoi_force`` and Q = ``qoi_tangential_force``)
and ``err_traction_prediction`` (the shear traction against Cattaneo's q at the same P, Q) measure
the coupling's share (the issue's "rigid-cylinder-on-block Cattaneo with nu = 0.3: the
coupling's share (Spence), measured"), plus discretisation and finite size. Nothing here is
expected to meet Cattaneo's c. The figures: the report's Coulomb section (its table against Cattaneo). The near-incompressible pair (``cattaneo-line-q03-nu47``) shows the
approach to Cattaneo as beta -> 0.

Setup. hertz-line's block, cylinder and mesh (Omega = (-L, L) x (0, H), L = H = 1 = 10 a, R = 1,
E = 1, parabolic gap x^2/(2R), Gamma_C corners at +-2a with maxh a/4 there, maxh 0.25 elsewhere),
Poisson ratio 0.3, Coulomb friction mu_F = 0.3 (steel on steel, and the coefficient of the
dolfinx_contact friction demos, so their Cattaneo comparison and this one share it; with
beta/mu_F 0.95 for the coupling). Load history (``harness.problem.cattaneo.cattaneo_line_case``):
the normal step u = (0, -0.015) on the top, then the tangential step u = (0.0055, -0.015). xi is
data, chosen once so that Q/(mu_F P) comes near 0.7 on this mesh; every
comparison is at the computed ratio, not at 0.7.

Rate. No convergence theorem for Coulomb friction was found (docs/theory/coulomb.md, "What is
proven"): nu, expected_rate and theorem are left out, and the report gives measured rates only,
against nitsche's solution one level finer (``reference_levels``).

Cost. Two load steps per level; the fine profile runs it (its phases: the report's study table).
"""
from harness.problem import cattaneo_line_case

name = "cattaneo-line-q07"
description = "Cattaneo line contact: rigid cylinder pressed into an elastic block (nu = 0.3), then sheared to Q/(mu_F P) near 0.7"
globals().update(cattaneo_line_case(poisson=0.3, mu=0.3, xi=0.0055))
report_levels = {"default": 4, "fine": 5}
