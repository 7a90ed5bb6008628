"""The registered cases: one module per case (the case contract: docs/guide/cases.md, "The case contract").
Installed with the harness as the package ``signorini_cases``; ``harness.problem.case`` finds
them there (or here, in a checkout that is not installed)."""
