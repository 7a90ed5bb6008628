"""Cattaneo line contact, nu = 0.47, Q/(mu_F P) near 0.7: cattaneo-line-q03-nu47's set-up sheared further (xi is
data, chosen once so that the computed ratio comes near 0.7; every comparison is at the computed
ratio). What is exact and what is not, and where the figures are: cattaneo-line-q03-nu47's docstring
(cases/cattaneo_line_q03_nu47.py).
"""
from harness.problem import cattaneo_line_case

name = "cattaneo-line-q07-nu47"
description = "Cattaneo line contact: rigid cylinder pressed into an elastic block (nu = 0.47), then sheared to Q/(mu_F P) near 0.7"
globals().update(cattaneo_line_case(poisson=0.47, mu=0.3, xi=0.0066))
report_levels = {"default": 4, "fine": 5}
