"""Stage 1, meshes: level sequences (``levels``: uniform refinement; mesh strategies go here),
the trace of T_h on Gamma_C (``trace``), point evaluation (``points``). Imports nothing of the
harness."""
