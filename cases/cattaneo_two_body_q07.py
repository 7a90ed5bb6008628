"""Cattaneo line contact between two identical elastic blocks, nu = 0.3, Q/(mu_F P) near 0.7: cattaneo-two-body-q03's
set-up sheared further (xi is data, chosen once so that the computed ratio comes near 0.7; every
comparison is at the computed ratio). What is exact and what is not: cattaneo-two-body-q03's
docstring (cases/cattaneo_two_body_q03.py).
"""
from harness.problem import cattaneo_two_body_case

name = "cattaneo-two-body-q07"
description = ("Cattaneo line contact between two identical elastic blocks (nu = 0.3, non-matching meshes), "
               "pressed together, then sheared to Q/(mu_F P) near 0.7")
globals().update(cattaneo_two_body_case(poisson=0.3, mu=0.3, xi=0.0120, delta=0.0186, size=2.0))
report_levels = {"default": 3, "fine": 5}
