"""A case of your own: the r^{3/2} contact/separation transition of `transition-r32`, moved to
x₀ = 1/3, a point no mesh of the study has as a vertex (the meshes halve (−1, 1) again and
again). The registered cases put every transition point at a polygon corner, as the paper's
examples do; a real contact zone ends wherever the physics puts it. Does the transition off
the vertices cost the P2 cones their h^{3/2}? The paper's Theorems 4.1 ii and 5.1 ii assume
u ∈ H^{5/2−ε} and a contact set with finitely many end points, not that they are vertices:
this case declares their rate and the study measures it: on 5 levels `mean`, `nodal` and `p1`
meet their rates (fitted 1.50, 1.50, 1.00), but the pairwise rates of the P2 cones alternate
(about 1.9, 1.1, 1.9, 1.1): 1/3 = 0.0101..._2 sits at 1/3 and 2/3 of its edge on alternate
levels, and the best approximation alternates the same way, so it is the approximation, not
the contact condition, that pays. Run it::

    python -m harness run --case examples/cases/transition_off_vertex.py --method paper --method p1 --levels 5

Ω = (−1, 1) × (0, 1), Γ_C the bottom side, Γ_u the top, Γ_g the two sides; u harmonic,
u = −r^{3/2} sin(3θ/2) about (x₀, 0): binding (u = 0, ∂ₙu ≥ 0) for x > x₀, free for x < x₀.
"""
from ngsolve import atan2, sin, sqrt, x, y

from harness.problem import contact_strip, transition_gradient

X0 = 1.0 / 3.0

name = "transition-off-vertex"
description = "r^{3/2} sin(3 theta/2) transition at x = 1/3, never a mesh vertex"
regime = "2 < nu <= 5/2"
theorem = "4.1 ii, 5.1 ii"
nu = 2.5
expected_rate = 1.5
expected_log_exponent = 0.0

geometry = contact_strip(breaks=[])         # no corner at x0: it falls inside a contact edge
maxh = 0.25

r = sqrt((x - X0) ** 2 + y * y)
u = -(r ** 1.5) * sin(1.5 * atan2(y, x - X0))
grad_u = transition_gradient(X0)
f = 0
# no singular_points: the contract wants them at mesh vertices (graded meshes refine towards
# them, the error quadrature is graded there), and this case's point is none
