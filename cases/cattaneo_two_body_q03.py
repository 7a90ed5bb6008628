"""Cattaneo line contact between two identical elastic blocks, nu = 0.3, Q/(mu_F P) near 0.3: pressed together, then sheared.

The set-up (``harness.problem.cattaneo.cattaneo_two_body_case``, size=2): each block is
(-2, 2) x (0, 2), 20 a x 20 a with a = 0.1, twice hertz-line's 10 a (the depth delta = 0.0186
keeps a); the upper block's Gamma_C zone +-2a is meshed at a/4, the lower one's (``MirrorBody``,
in its mirrored frame) at a/6, so the two meshes on Gamma_C stand 3:2 and stay non-matching
under refinement. Each block carries the gap x^2/(2R) of a cylinder of radius R = 1: two
cylinders, R* = R/2. Load history: both tops pressed by (0, -delta); then the upper top moves by
(xi, -delta) while the lower holds (0, -delta) (its own Dirichlet data). Coulomb friction
mu_F = 0.3 between the bodies: the dual mortar (``mortar-nodal``, ``mortar-p1``) and Nitsche
(``mortar-nitsche``, ``mortar-nitsche-p1``).

What is exact and what is not. For identical bodies E* = E/(2 (1 - nu^2)) and Dundurs'
beta = 0 (whatever nu): the normal and tangential responses are uncoupled, so Cattaneo's
stick zone c/a = sqrt(1 - Q/(mu_F P)) and shear q hold without the coupling error of the rigid
indenter (cattaneo-line-q03's beta = 0.286), and the normal step leaves no interfacial shear.
That the uncoupling survives the finite blocks: the problem is invariant under the 180 degree
rotation u_2(x, y) = -u_1(-x, -y), which makes p and q even in x; an even p (and delta) drives only
the even opening and no jump, an even q (and xi) only the jump and no opening. What is not
exact: the half-space (the blocks are 20 a, a finite-size effect as hertz-line's, falling like
(a/L)^2 in the normal pressure; on 10 a blocks the shear traction's error levelled off near 3 %
at Q/(mu_F P) = 0.3, 0.15.0's closing note), Hertz's parabolic profile (the gap) and the
non-matching meshes, which break the rotation symmetry discretely only. Moving the upper body alone equals the
symmetric loading +-xi/2 plus a rigid translation, which both finite element spaces contain.

xi is data, chosen once from a level-2 run so that Q/(mu_F P) comes near 0.3 (each body takes
about half the relative motion: twice the rigid indenter's xi); every comparison is at the
computed ratio. No rate theorem for Coulomb: nu, expected_rate and theorem are left out; errors
of each body against `mortar-nodal`'s solution one level finer. Two load steps per level; the
fine profile runs it.
"""
from harness.problem import cattaneo_two_body_case

name = "cattaneo-two-body-q03"
description = ("Cattaneo line contact between two identical elastic blocks (nu = 0.3, non-matching meshes), "
               "pressed together, then sheared to Q/(mu_F P) near 0.3")
globals().update(cattaneo_two_body_case(poisson=0.3, mu=0.3, xi=0.0050, delta=0.0186, size=2.0))
report_levels = {"default": 3, "fine": 5}
