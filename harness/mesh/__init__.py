"""Stage 1, meshes: level sequences (``levels``: uniform refinement; mesh strategies go here),
the trace of T_h on Gamma_C (``trace``), the sides of a 2D mesh as arrays (``sides``), point
evaluation (``points``). Imports nothing of the
harness."""
