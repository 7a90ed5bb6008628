"""The report's section "Cases": each case in full, collapsed under its verdicts (its regime and
bound, every method's fitted rates against both theories, the errors on Γ_C, the figures, and
every level of every method). Its figures (convergence, contact, solution, interface, efficiency:
``figures``) are drawn from the case's stored rows and snapshots as soon as the case is stored
(``queue_case_figures``, the figure pool's ``on_stored``; the store is ``study.planning.cache``'s,
its snapshots ``study.chain.snapshots``)."""
from __future__ import annotations

from pathlib import Path

import numpy as np
import pandas as pd

from ...problem.case import Case, fraction
from ..document import Document, anchor
from ..plan import ReportPlan
from ..plots import theorem_label
from ..prose import belief_finding, reference_sentence, which_bound
from ..tables import gamma_c_view, level_table, normalised_view, summary_table
from .friction import draws_stick_slip, stick_slip_caption
from .glance import verdict_counts


def write(doc: Document, plan: ReportPlan) -> None:
    """Each case in full (click to open): the report stays navigable with many."""
    rates = plan.rates
    doc.heading("Cases")
    doc.paragraph("Each case in full (click to open): its regime and bound, every method's fitted rates against "
                  "both theories, the errors on Γ_C, the figures, and every level of every method.")
    for case in plan.cases:
        with doc.details(f"{case.name}: P2 {theorem_label(case.theorem)}", anchor(case.name),
                         verdict_counts(rates[rates.case == case.name]), listed=case.name):
            case_section(doc, case, plan.results, rates, plan.figs)


def expectation_sentence(case: Case) -> str:
    """What bounds the case's P2 H^1 error: the paper's theorem, the authors' belief (Remark 4.3),
    or, with friction, the paper's rate for the same regularity read as a conjecture (no theorem
    covers the friction analogues)."""
    if case.frictional:
        return f"no theorem covers friction: the P2 H¹ error is expected (a conjecture) to behave like {case.expected_bound}."
    if case.conjectured:
        return f"the authors believe (no theorem) the P2 H¹ error behaves like {case.expected_bound}."
    return f"the paper bounds the P2 H¹ error by C {case.expected_bound}."


def case_section(doc: Document, case: Case, results: pd.DataFrame, rates: pd.DataFrame, figs: dict) -> None:
    """One case's part of the report."""
    if case.physics.elastic:
        doc.paragraph(f"Physics: {case.physics.describe()}.")
    if case.frictional:
        doc.paragraph(f"Friction: {case.friction.describe()} (section Tresca friction).")
    doc.paragraph(f"{case.description}. Regime {case.regime or '-'}, "
                  + (f"ν = {fraction(case.nu)}; " if np.isfinite(case.nu) else "ν not declared; ")
                  + expectation_sentence(case))
    against = reference_sentence(case, results)
    if against:
        doc.paragraph(against)
    doc.table(summary_table(rates[rates.case == case.name]), verdict_column="verdict")
    if case.conjectured:
        doc.paragraph(belief_finding(case, rates))
    sentences = "" if case.conjectured else which_bound(case, rates, results)   # no bound to follow
    if sentences:
        doc.paragraph(sentences)
    if case.expected_log_exponent:
        view = normalised_view(case, results)
        if view is not None:
            doc.table(view)
    if "err_trace_l2" in results:
        doc.paragraph("On Γ_C, finest level (the paper's Section 5 remark; the measures are defined "
                      "under 'Errors on Γ_C' above):")
        doc.table(gamma_c_view(rates, results, case.name))
    case_figures_of(doc, case, figs[case.name])
    for method, group in results[results.case == case.name].groupby("method", sort=False):
        doc.heading(f"{case.name}: method {method}", level=3, key=f"{anchor(case.name)}-{method}")
        doc.table(level_table(group, energy=case.physics.elastic))


def case_figures_of(doc: Document, case: Case, f: dict) -> None:
    """One case's figures (``case_figures``) with their captions."""
    doc.figures([(f["convergence"]["png"], "H¹ error against h; dashed: each theory's bound through the coarsest point."),
                 (f["contact"]["png"], contact_caption(case))])
    if f.get("interface") is not None:
        doc.figures([(f["interface"]["png"], "The two bodies' meshes at the interface on level 1: independent, not matching on Γ_C.")],
                    wide=True)
    doc.figures([(f["efficiency"]["png"], "H¹ error against ndof and against seconds summed over the levels; dotted: the target.")],
                wide=True)
    if f["solution"] is not None:
        doc.figures([(f["solution"]["png"], "Deformed shape: the mesh moved by u_h (magnified), coloured by |u_h|; grey: the body at rest."
                      if case.physics.elastic else "u_h on Ω.")])


def contact_caption(case: Case) -> str:
    """What the contact figure of ``case`` shows, by its bodies, dimension and friction."""
    if draws_stick_slip(case):
        return "Stick and slip, " + stick_slip_caption(case)
    if case.bodies == 2:
        return ("Finest level along Γ_C: the opening [u_h] - 2α of the interface (sampled on the intersection of the two "
                "trace meshes) and the mortar pressure per slave edge; shaded: exact contact zone.")
    if case.dimension == 2:
        return "Finest level along Γ_C: u_h - α and the discrete contact pressure; shaded: exact contact zone."
    return "Γ_C from below, finest level: u_h - α and the discrete pressure per triangle."


def contact_figure(case: Case, contact: dict, folder: Path) -> dict:
    """The contact figure: a friction case's stick/slip picture (``friction.stick_slip``) where
    its snapshots hold the slip, else u_h and the pressure along Gamma_C (``figures.contact``)."""
    from .. import figures
    from .friction import stick_slip
    drawn = stick_slip(case, contact, folder) if draws_stick_slip(case) else None
    return drawn if drawn is not None else figures.contact(case, contact, folder)


def queue_case_figures(pool, case: Case, store: Path) -> None:
    """The figure pool's ``on_stored``: ``case``'s figures, from its files in ``store``."""
    stored = tuple(Path(store) / f"{case.name}.{kind}" for kind in ("csv", "npz"))
    pool.job(case.name, case_figures, str(case.source), str(store), inputs=stored)


def case_figures(source: str, store: str, folder: str) -> dict:
    """The job: the figures of the case in file ``source`` from its stored rows and snapshots, in
    a worker."""
    from ...measure.efficiency import efficiency_table
    from ...problem.case import load_case
    from ...study.chain.snapshots import load_snapshots
    from .. import figures
    case, store, folder = load_case(source), Path(store), Path(folder)
    frame = pd.read_csv(store / f"{case.name}.csv")
    contact, domain = load_snapshots(store / f"{case.name}.npz")
    return {
        "convergence": figures.convergence(case, frame, folder),
        "contact": contact_figure(case, contact, folder),
        "solution": figures.domain(case, {k: v for k, v in domain.items() if k != "interface"}, folder),
        "interface": figures.interface(case, domain.get("interface"), folder),
        "efficiency": figures.efficiency(case, frame, efficiency_table(frame).target_err_h1.iloc[0], folder),
    }
