"""Stage 8, the report: it renders what ``study.cache`` computed (``build``: tables, prose and
the document; ``figures`` and ``figure_jobs``; ``document``: Markdown and HTML). Nothing here
is part of a study's cache key: rewording the report reuses the study."""
