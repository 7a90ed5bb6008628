"""Stage 4, the solvers: the truncated multigrid (``multigrid``, ``projected``), the exact
active-set solvers of the cones' QP (``active_set``: bounds; ``general_constraints``: general
rows), which share one primal-dual active set iteration (``pdas``), and the semismooth Newton
of the weak methods (``newton``); their settings as data (``options.SolverOptions``). Plain
linear algebra: imports nothing of the harness outside this package."""
