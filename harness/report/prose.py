"""The report's prose: the notes under its headings and the sentences it writes from the
measured rates (which bound the errors follow, what a reference or a belief shows)."""
from __future__ import annotations

import numpy as np
import pandas as pd

from ..measure.rates import TOLERANCE, normalised_errors
from ..methods import PAPER, REFERENCE, names_with_role
from ..problem.case import bound_text

REGULARITY_NOTE = (
    "Does each case have the regularity ν it declares? The Ritz projection R_h u (the Galerkin "
    "solution with u's own flux on Γ_C as Neumann data: the best approximation in |·|₁ with the "
    "methods' Dirichlet lift; no contact involved) converges at min(ν − 1, k) for P_k. Its fitted "
    "rate is set against that (verdict within ±0.1); err / best, the methods' H¹ error over R_h u's "
    "on the finest level, is what the contact discretisation costs beyond best approximation "
    "(Falk's lemma's extra terms, Remark 4.6)."
)


GAMMA_C_NOTE = (
    "Section 5 of the paper: `mean` is \"suitable for checking the contact condition on the normal "
    "constraint\", `nodal` \"for the normal displacement\". Measured on Γ_C, finest level: the trace "
    "error ‖u − u_h‖ in L²(Γ_C); the pressure error, λ_h being for every method the Riesz "
    "representative in the trace space of the residual a(u_h, ·) − L(·) (the discrete contact force: "
    "the multipliers of the cones, the contact terms of penalty and Nitsche), against λ = ∂ₙu − g_C, "
    "in L²(Γ_C) and in ‖h^{1/2}·‖_{L²(Γ_C)}; the largest penetration max(α − u_h) and the largest "
    "tension max(−λ_h). Rates: fitted over the last three levels. Where λ ∉ L²(Γ_C) (λ ~ r^{-1/2}: "
    "corner-r12) the L² pressure error cannot converge (its rate is 0), only the h^{1/2}-weighted one."
)


ELASTICITY_NOTE = (
    "Frictionless unilateral contact of an elastic body (plane strain in 2D; in 3D the body itself) on a "
    "rigid foundation: "
    "−div σ(u) = f, σ = 2μ ε(u) + λ tr ε(u) I; on Γ_C, with n the outward normal and σ_n = n·σ(u)n, "
    "u·n − α ≤ 0, σ_n − g_n ≤ 0, (u·n − α)(σ_n − g_n) = 0 and σ_t = g_t. Both P2 models constrain "
    "the normal displacement: written in the variables (tangential components, −u·n) at the nodes of Γ_C, "
    "the contact variable c = −u·n has the scalar problem's trace, so `mean` (vertex values and edge "
    "means of c ≥ −α; in 3D triangle means) and `nodal` (vertex and midpoint values) are the scalar "
    "cones, solved exactly by the same active-set solvers, each linear solve by CG with the truncated "
    "V-cycle on vector spaces: vector P1 coarse spaces, each in the rotated frame at its own Γ_C, "
    "truncated at the pinned normal variable only (sparse Cholesky for λ/μ > 20, where pointwise "
    "smoothing is not robust: the Poisson ratio 0.49 case). "
    "The pressure p = −(σ_n − g_n) plays λ's part. Singular exponents: a roller (binding, frictionless) "
    "face next to a traction-free one at angle ω reflects to a traction-free wedge of angle 2ω, whose "
    "symmetric exponents solve sin(2lω) + l sin(2ω) = 0 — with no elastic constant in it: l = 3/2 at "
    "a transition (ω = π; 1/2 is excluded by the signs), l = 0.5445 at ω = 3π/4, for every Poisson "
    "ratio. The energy norm a(e, e)^{1/2} is equivalent to the H¹ norm (Korn): same theorem rate; "
    "R_h u is the best approximation in energy, so err / best in H¹ may fall below 1."
)


TWO_BODY_NOTE = (
    "The paper's Section 6 names the mortar method on non-coinciding meshes, for contact between two "
    "bodies, as the next step. Here two bodies touch along Γ_C = {y = 0}: the upper one carries a "
    "one-body exact solution s, the lower one its mirror image (scalar u₂(x, y) = −s(x, −y); "
    "elastic u₂ = (s_x, −s_y)(x, −y)), so the fluxes balance, the opening [u] = 2s, and each regime "
    "of the paper has a two-body counterpart with the same singular exponent. Each body is meshed on "
    "its own (element sizes 2:3 on Γ_C, refined uniformly: the meshes never match; column 'lower / upper "
    "maxh' 0.67), except the control two-body-transition-r32-matching (1.00: every vertex of Γ_C is a "
    "vertex of both meshes). The two-body Cattaneo cases (Coulomb, two identical cylinders pressed and sheared) "
    "are reference cases, measured against mortar-nodal one level finer; their bodies' maxh are equal and "
    "their zones' sizes on Γ_C stand 3:2, so their meshes do not match either (the Coulomb section reads them "
    "against Cattaneo). The contact "
    "condition holds weakly against multipliers on the upper (slave) body's trace, ∫ ψᵢ ([u_h] − 2α) ≥ 0, "
    "integrated exactly on the intersection of the two trace meshes. Dual (biorthogonal) multipliers "
    "(Wohlmuth 2000; for contact Hüeber & Wohlmuth 2005) make each row a bound after a change of "
    "variables local to the slave's trace, solved exactly by the active set method on sparse Cholesky "
    "and cross-checked against the rows as general constraints; on matching meshes they are `nodal` "
    "(`mortar-nodal`), `mean` (`mortar-mean`, K_h on the dual mortar projection of the jump) and `p1` "
    "(`mortar-p1`) on the jump, which the tests check to 1e-8. `mortar-standard` uses the slave's own "
    "quadratic basis (Hild & Laborde's continuous multipliers): general rows, solved on the saddle system. "
    "`mortar-nitsche` (`mortar-nitsche-p1`) has no multipliers: `nitsche`'s law on the jumps at Gauss points "
    "of the intersection, with the slave's flux (the master–slave form), solved by semismooth Newton; its KKT "
    "column is its Newton residual. No theorem we could read states the "
    "rates of quadratic mortar contact on non-matching meshes (Hild & Laborde 2002 analyse quadratic "
    "elements with continuous quadratic multipliers), nor of the master–slave Nitsche method; each method is "
    "held to the one-body rate min(ν − 1, k) (Nitsche's: for ν > 3/2). Errors are over both bodies, "
    "err² = err₁² + err₂²; ndof counts both."
)

THREE_D_NOTE = (
    "The paper's Section 6 names 3D as open. Here Ω = (−1, 1)² × (0, 1) in tetrahedra (netgen, red "
    "refinement: every edge halves, 8 children per tetrahedron), Γ_C its bottom face. `mean` is K_h on "
    "the cells of Γ_C, which are triangles in 3D: vertex values ≥ α and the mean of u_h − α ≥ 0 over each "
    "triangle. A P2 triangle mean is the average of its three edge-midpoint values, and each midpoint "
    "belongs to two triangles, so these are general linear constraints: solved exactly by a primal-dual "
    "active set method on them, each set by projected CG with a V-cycle that keeps the active triangle "
    "means (an exact constrained block on Γ_C's dofs, the P1 coarse spaces truncated at the active "
    "triangles' vertices). No theorem covers it; the 2D rate is its expectation. `nodal` (vertex and "
    "edge-midpoint values ≥ α: the P2 Lagrange cone of the 3D analyses, Drouet & Hild 2015) and P1 are "
    "bounds on single variables, solved as in 2D with the truncated multigrid of the tetrahedral "
    "hierarchy. `mean-edges`, K_h applied edge by edge (vertex values and edge means ≥ α), is the "
    "counterexample: an edge-wise cone does not control the trace inside the triangles (with all vertex "
    "values v > 0 and all edge means 0, the P2 trace of a triangle is −v at its centroid and its mean "
    "is −v/2, yet every constraint holds), and its rate stalls near 1/2. The table shows what the discrete "
    "solutions do with that freedom (the smallest value of u_h − α over Γ_C: penetration is negative). "
    "The pictures show Γ_C from below: red where u_h dips below the obstacle. The elastic cases "
    "(elastic-transition-3d: the plane-strain transition extruded, u_y = 0; elastic-junction-3d: Γ_C "
    "meets Γ_g along a line, r^{1/2}; elastic-transition-circle-3d, in the fine profile: the transition "
    "along a circle) constrain the normal displacement with the same cones on c = −u·n, solved by the "
    "vector V-cycle."
)


def paper_methods(names) -> list[str]:
    """Those of the method names ``names`` whose methods declare the role PAPER: the paper's P2
    models, compared side by side (``methods.names_with_role``)."""
    return names_with_role(PAPER, names)


def which_bound(case, rates: pd.DataFrame, results: pd.DataFrame) -> str:
    """Two sentences: which of the two bounds the P2 cones' errors follow (the cones: the
    methods that declare the role PAPER)."""
    mine = rates[rates.case == case.name]
    cones = paper_methods(mine.method)
    r = mine[mine.method.isin(cones)]
    if r.empty:
        return ""
    fitted = ", ".join(f"{m} {p:.2f}" for m, p in zip(r.method, r.fitted_rate))
    paper = bound_text(case.expected_rate, case.expected_log_exponent)
    first = r.iloc[0]
    dh = bound_text(first.sharper_rate) if np.isfinite(first.sharper_rate) else None
    text = f"Fitted H¹ rates (last three levels, with each theory's log factor) {fitted}; the paper bounds them by {paper}"
    text += (f", Drouet & Hild by {dh}." if dh else "; Drouet & Hild say nothing for ν ≤ 3/2.")
    if not dh:
        return text + " The data follow the paper's bound."
    if not case.expected_log_exponent and np.isclose(first.sharper_rate, case.expected_rate):
        return text + " Both bounds are the same here, and the data " + \
            ("follow it." if (r.verdict == "meets").all() else "beat it (verdicts above).")
    if not case.expected_log_exponent:
        follows = "follow" if (r.verdict == "meets").all() else "reach"
        return text + (f" The data {follows} the paper's {paper} (Remark 4.9, under its finite-transition "
                       f"assumption), beyond Drouet & Hild's {dh}, whose estimate stops at the H^(5/2) "
                       f"regularity of Signorini solutions.")
    # a log factor in the paper's bound: which normalised error levels off? (for the paper's
    # method that also computes references, else the last of them)
    shown = next(iter(names_with_role(REFERENCE, cones)), cones[-1])
    g = results[(results.case == case.name) & (results.method == shown)].sort_values("level")
    with_log = normalised_errors(g.h, g.err_h1, case.expected_rate, case.expected_log_exponent)[-3:]
    plain = normalised_errors(g.h, g.err_h1, case.expected_rate, 0.0)[-3:]
    def drop(v):
        return 1 - v[-1] / v[-2]
    level_off = 0.02
    if abs(drop(plain)) <= level_off < abs(drop(with_log)):
        verdict_text = "e/h has levelled off and the data follow Drouet & Hild's h, without the paper's log factor."
    elif abs(drop(with_log)) <= level_off < abs(drop(plain)):
        verdict_text = f"e/({paper}) has levelled off: the data follow the paper's bound."
    elif abs(drop(plain)) < abs(drop(with_log)):
        verdict_text = ("neither has levelled off (both fall by more than 2%), e/h the less: the data are nearer "
                        "Drouet & Hild's h than the paper's bound, and still faster than both, like the best "
                        "approximation (table above).")
    else:
        verdict_text = "neither has levelled off (both fall by more than 2%)."
    return text + (f" Over the last level, {shown}'s e/({paper}) falls by {drop(with_log):.1%} and e/h by "
                   f"{drop(plain):.1%}: " + verdict_text)


def reference_sentence(case, results: pd.DataFrame) -> str:
    """For a case measured against a reference: against what, how fine, how exactly solved."""
    rows = results[(results.case == case.name) & (results.get("errors_against", "exact") == "reference")]
    if rows.empty:
        return ""
    first = rows.iloc[0]
    method = first.get("reference_method")
    whose = (f"the {method} solution {case.reference_levels} levels finer than the finest studied P2 level, "
             f"with {4 ** case.reference_levels} times the dofs of every method's finest level"
             if isinstance(method, str) else
             f"the method's own solution {case.reference_levels} levels finer than its finest studied level")
    return (f"No closed-form solution: every error is measured against {whose} (level {int(first.reference_level)}, "
            f"{int(rows.reference_ndof.max()):,} dofs; KKT residual of the reference solve "
            f"{rows.reference_kkt_residual.max():.1e}). On nested meshes u_h is exactly a function of the "
            f"reference space, so the errors are exact norms of u_R − u_h; they miss |u − u_R|, which "
            f"for a P2 error like h^p lowers the finest studied level's error by the factor √(1 − 4^(−p·k)) "
            f"(k = {case.reference_levels}: {np.sqrt(1 - 4.0 ** (-1.5 * case.reference_levels)):.3f} for p = 3/2), "
            f"and a P1 error, larger at the same dofs, by less. No best approximation (it would need u).")


def belief_finding(case, rates: pd.DataFrame) -> str:
    """What the data say about a conjectured rate (``Case.conjectured``): supported or a loss."""
    r = rates[rates.case == case.name]
    belief = bound_text(case.expected_rate, case.expected_log_exponent)
    parts = [f"{m} {p:.3f} (pairwise {pw})" for m, p, pw in zip(r.method, r.fitted_rate, r.pairwise_rates)
             if np.isfinite(case.expected_rate)]
    cones = r[r.method.isin(paper_methods(r.method))]
    if cones.empty:
        return f"The expected rate {belief} is a belief, not a theorem (Theorem {case.theorem}). Measured: " + "; ".join(parts) + "."
    low = cones.fitted_rate.min()
    if low >= case.expected_rate - TOLERANCE:
        finding = (f"The data support the authors' belief: both P2 models converge at {belief} "
                   f"(within ±{TOLERANCE}) although Γ_C has infinitely many transition points.")
    else:
        finding = (f"The data show a loss against the authors' belief {belief}: the P2 models' fitted rate is "
                   f"{low:.3f}, {case.expected_rate - low:.3f} below it.")
    best = cones.fitted_rate_best.iloc[0] if "fitted_rate_best" in cones else np.nan
    best_text = f" The best approximation converges at {best:.3f} (ν − 1 = {case.nu - 1:.3g}: the regularity is as derived)." \
        if np.isfinite(best) else ""
    return (f"Remark 4.3's question. {finding} Fitted rates (pairwise rates level by level): " + "; ".join(parts) + "."
            + best_text)


INTRO = (
    "The Poisson-Signorini problem (2.1)-(2.4): -Δu = f in Ω, u = u_D on Γ_u, ∂u/∂n = g on Γ_g and "
    "u ≥ 0, ∂u/∂n ≥ 0, u ∂u/∂n = 0 on Γ_C (with a gap α and a contact load g_C where a case "
    "declares them), on uniformly refined meshes (NGSolve); h halves per level. The paper's two P2 "
    "methods have nonconforming cones: `mean` (K_h, Section 3: vertex values and edge means ≥ 0, the "
    "degrees of freedom of J_h) and `nodal` (K̃_h, Section 5: vertex and midpoint values ≥ 0, the "
    "degrees of freedom of I_h); K̃_h ⊂ K_h by Simpson's rule. The baseline `p1` (linear elements, "
    "vertex values ≥ 0) has an exact cone. Each discrete inequality is solved exactly: every row's KKT "
    "residual is listed. What users of NGSolve or FEniCS write instead impose contact weakly, by a term "
    "on Γ_C with no constraint on the space: `nitsche` (Chouly & Hild 2013; θ-variants of Chouly, Hild "
    "& Renard 2015) and `penalty` (Chouly & Hild 2013), P2 and P1 (`-p1`), ε = γ₀h/M (M = 1, or λ + 2μ "
    "in elasticity, where they act on u·n and σₙ(u)); their nonlinear "
    "equations are solved by semismooth Newton to a relative residual ≤ 1e-10, listed in the same "
    "column. Max penetration is max over Γ_C of α - u_h, between nodes included: the nonconformity of "
    "the cones, and how far the weak methods let u_h through the obstacle. P1 runs one level more than "
    "P2, so that every method ends at about the same number of dofs (P1 on level l+1 has the dofs of "
    "P2 on level l)."
)


MATRIX_NOTE = (
    "Each cell: the fitted H¹ rate over the last three levels / the rate of the method's own theory "
    "(for mean and nodal the paper's theorem, for P1 and the weak methods theirs; – no theory), coloured "
    "by the verdict: green meets it within ±0.1, blue above (the theorems are upper bounds: consistent), "
    "red below, amber pre-asymptotic (below, but so is the best approximation of the same space, and the "
    "method's error is within 1.1 of its: the levels are not yet fine enough, the method loses nothing), "
    "grey no theory. The cases' sections below (Cases) say why each is what it is."
)


RATES_NOTE = (
    "Fitted rate: least squares of log e = log C + p log h + q log|log h| over the last three "
    "levels, q fixed to the log exponent of the method's theory, with its standard error. Verdict: "
    "meets if within 0.1 of that theory's rate; above/below otherwise. The theorems give upper "
    "bounds, so 'above' is consistent with them; 'below' would contradict them, unless the space itself "
    "is the reason: 'pre-asymptotic' where the method's error is within 1.1 of the best approximation's "
    "on the finest level, the best approximation's own rate falls as short of min(ν − 1, k), and the "
    "pairwise rates still climb (Falk's lemma: the contact condition costs nothing there; the levels "
    "are not yet in the asymptotic range)."
)


EFFICIENCY_NOTE = (
    "The paper's claim (abstract, Section 6): its quadratic methods are more accurate than linear "
    "finite elements. Measured as cost at equal accuracy: per case, the target H¹ error is the "
    "largest of the methods' finest errors (so each method reaches it within its own levels; its "
    "fraction of the coarsest error is given), and each method's dofs and seconds to reach it are "
    "read off its levels by log-log interpolation. Seconds are summed over the levels up to the "
    "target (nested iteration needs them): 'solve' the contact solves, 'total' all a user pays for "
    "u_h (mesh refinement, assembly, set-up, solve; not the error measurement). P1 / it > 1: the "
    "method is cheaper than P1. Errors at equal ndof: at the largest ndof both reach (the method's "
    "finest where P1 runs one level past P2, else P1's finest, the method's error interpolated there)."
)


SWEEP_NOTE = (
    "Penalty and Nitsche ask the user for a parameter: ε = ε₀h/M (penalty) or γ₀h/M (Nitsche) on each "
    "contact cell, M = 1 for the scalar problem and λ + 2μ in elasticity. Each curve is one method over "
    "that parameter at one level, every other setting fixed; the dashed line is `nodal`, which has no "
    "parameter. Hollow markers: Newton did not converge (its status is in the table below). Nitsche "
    "with θ = 1 is coercive only while γ₀ (h/M)‖flux(v)‖² < a(v, v) on X_h (flux: ∂ₙv, or σₙ(v) in "
    "elasticity), a bound of about γ₀ < 0.14 for P2 on the registered cases, scalar and elastic "
    "alike (`methods/nitsche.py`); θ = -1 is coercive for every γ₀. The penalty method is not "
    "consistent: in contact u_h sits about ε λ below the obstacle, so its error and penetration grow "
    "with ε₀."
)
