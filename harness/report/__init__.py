"""Stage 8, the report: it renders what ``study.planning.cache`` computed (``build``: tables, prose and
the document; ``figures`` and ``figure_jobs``; ``document``: Markdown and HTML). Nothing here
is part of a study's cache key: rewording the report reuses the study.

The package is callable, so that a notebook builds the report as the command line does:

    >>> harness.report(cases=["transition-r32"], methods=["paper", my_method], levels=3)

(its arguments: ``ReportPackage.__call__``).
"""
from __future__ import annotations

import sys
import types
from pathlib import Path


class ReportPackage(types.ModuleType):
    """This package, callable (a module's class may be a subclass of ModuleType: Python's data
    model, "Customizing module attribute access"): ``harness.report(...)`` runs or reuses the
    study of a profile and writes the report, and ``harness.report.plots`` stays importable."""

    def __call__(self, cases=None, methods=("all",), levels: int | None = None, profile: str = "default",
                 results="results", out="report", engine=None, show_progress: bool = True, vtk: bool = False,
                 check_memory: bool = True) -> Path:
        """The report of ``profile`` ("default" or "fine") into ``out``/report.html, its study's
        rows merged into ``results``/results.csv (rows already there and unchanged are reused).
        ``cases``: registered case names (default: the profile's); ``methods``: as
        ``harness.run`` takes them, your own objects included; ``levels``: instead of the
        profile's. Both folders are owned by this call while it runs. Returns the HTML's path."""
        from .build import make_report
        return make_report(profile, Path(results), Path(out), cases, show_progress=show_progress, levels=levels,
                           methods=methods, engine=engine, check_memory=check_memory, vtk=vtk)


sys.modules[__name__].__class__ = ReportPackage
