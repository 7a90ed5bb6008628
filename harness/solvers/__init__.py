"""Stage 4, the solvers: the truncated multigrid (``multigrid``; with general rows kept,
``projected_multigrid`` and ``row_projection``; two bodies, ``two_body_multigrid`` on the
operator ``two_body_operator``), the exact active-set solvers of the cones' QP
(``bound_constraints``: bounds; ``general_constraints``: general rows), which share one
primal-dual active set iteration (``pdas``), and the semismooth Newton of the weak methods
(``newton``); their settings as data (``options.SolverOptions``). Imports ``mesh``, ``problem``
and ``fem``: the multigrid builds its P1 levels from the mesh hierarchy and the case's physics
and enters the problem's variables through ``fem.p1_embedding.ContactEdges``; the rest is
linear algebra on the matrices and vectors it is given."""
