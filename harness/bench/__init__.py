"""Stage 9, benchmarks: the solver and study tables (``solvers``) and the whole report's
profile (``report``); they time the earlier stages through their public functions."""
