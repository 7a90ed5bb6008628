"""The paper's mean cone K_h (Section 3, (3.6)) at degree k >= 3: v_h >= alpha at the vertices of
Gamma_C and the mean of v_h - alpha >= 0 over each of k - 1 equal sub-edges of every contact edge.
For k = 2 the one sub-edge is the edge: `mean` (tests/test_degree.py solves both and finds the
same u_h). A ``FunctionalCone`` (level 1 of the method protocol), its rules given per degree
(``functionals_of``), so that on an hp mesh each edge has its own degree's sub-edges.

Why sub-edge means, not moments. K_h asks for a mean of the trace where K~_h asks for values: an
average of v_h - alpha >= 0, the weak form of v_h >= alpha that the paper's mean model uses. Moments
against polynomials of degree >= 1 are not averages (they change sign) and bound nothing; means over
k - 1 sub-edges are averages, and with the two vertex rows they are k + 1 functionals that fix the
edge's degree-k trace (independent rows: the projected multigrid serves them, as for the nodal
cone). Each sub-edge mean is a Gauss rule exact for degree k (ceil((k + 1) / 2) points).

Expected rate: no theorem covers k >= 3; the declared min(nu - 1, k) is a conjecture, as for the
nodal cone of degree k (``_nodal_pk``).
"""
import math

import numpy as np

from ._nodal_pk import expected_for
from .base import FunctionalCone


def sub_edge_means(degree: int) -> tuple:
    """The means over the degree - 1 equal sub-edges of an edge (one for degree <= 2: the edge)."""
    pieces = max(degree - 1, 1)
    t, w = np.polynomial.legendre.leggauss(math.ceil((degree + 1) / 2))
    t, w = 0.5 * (t + 1.0), 0.5 * w
    return tuple(tuple((float((j + x) / pieces), float(y)) for x, y in zip(t, w)) for j in range(pieces))


def at_order(order: int) -> FunctionalCone:
    return FunctionalCone(
        name=f"mean-p{order}",
        order=order,
        contact=f"v_h >= 0 at the vertices and ∫ v_h >= 0 over the {order - 1} equal sub-edges of each edge of Γ_C "
                "(on hp meshes, of each edge's own degree)",
        reference="Belhachmi & Ben Belgacem 2003, Section 3, at degree k",
        expected=expected_for(order),
        functionals_of=sub_edge_means,
        physics=("scalar", "elasticity"),
    )
