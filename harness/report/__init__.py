"""Stage 8, the report: it renders what ``study.planning.cache`` computed (``build``: tables,
prose and the document; ``figures`` and ``figure_jobs``; ``document``: Markdown and HTML).
Nothing here is part of a study's cache key (``study.storage.digest``): rewording the report
reuses the study. ``harness.report(...)``, which builds the report, is ``harness.api.report``;
this package's modules import as ``from harness.report import plots``."""
