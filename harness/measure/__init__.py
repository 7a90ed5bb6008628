"""Stage 6, measurement: errors against an exact solution (``errors``) or a reference
solution (``reference``), the best approximation (``best_approximation``), fitted rates
(``rates``) and cost at equal accuracy (``efficiency``). Imports the stages before it."""
