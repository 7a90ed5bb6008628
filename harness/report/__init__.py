"""Stage 8, the report: it renders what ``study.planning.cache`` computed. ``build``: the study,
the plan and the document (``make_report``); ``plan``: what the document is written from
(``plan.ReportPlan``); ``sections``: one module per section of the document, each with its text,
tables and figure jobs, in one ordered registry (``sections.SECTIONS``); ``tables`` and ``prose``:
what several sections share; ``figures`` (drawing) and ``figure_jobs`` (drawn in worker
processes), ``figure_cache``; ``document``: Markdown and HTML; ``latex``, ``plots`` and ``vtk``:
booktabs tables, figures from DataFrames, ParaView files.
Nothing here is part of a study's cache key (``study.storage.digest``): rewording the report
reuses the study. ``harness.report(...)``, which builds the report, is ``harness.api.report``;
this package's modules import as ``from harness.report import plots``."""
