"""Stage 4, the solvers: the truncated multigrid (``multigrid``), the exact active-set
solver of the cones' QP (``active_set``) and the semismooth Newton of the weak methods
(``newton``). Plain linear algebra: imports nothing of the harness outside this package."""
