"""The theorems, one by one: every case x method converges at least at its own theory's rate."""
import numpy as np
import pytest
from conftest import METHOD_NAMES, MODEL_NAMES

from harness import run
from harness.measure.rates import fit_rate, normalised_errors, pairwise_rates, rate_table
from harness.methods import METHODS
from harness.problem.case import registered_cases

# Levels 0..5: the finest has about 1.2e5 to 1.4e5 dofs, in the asymptotic range of every case.
RATE_LEVELS = 6
# one body (3D: tests/test_three_d.py; two bodies, whose 6-level chains would double this
# module's slow study: tests/test_two_body.py)
# frictionless: the Tresca cases' rates and solves are tests/test_tresca*.py's and test_friction_solver's
CASES = {name: case for name, case in registered_cases(dimension=2).items() if case.bodies == 1 and not case.frictional}
EXACT_CASES = [name for name, case in CASES.items() if case.exact]   # those with a best approximation


# `make test`: every case x method of order 1 and 2 on 3 levels (every solve exact, no method below
# the best approximation); the methods of degree k >= 3 on every case, and the rates, which need
# the asymptotic range, under `make test-full` (the degree's fast checks: tests/test_degree.py)
SMALL_LEVELS = 3
SMALL_METHODS = [name for name in METHOD_NAMES
                 if METHODS[name].order <= 2 and any(METHODS[name].supports(c) for c in CASES.values())]
# the 6-level study of every case: every method but the mean cones of degree 3 and 4 (a conjecture,
# no theorem), whose rates tests/test_degree.py measures on the cases that show them
# (smooth-quintic, transition-r32): on every case they cost CI 90 s of its 25 minutes
RATE_METHODS = [name for name in METHOD_NAMES if name not in ("mean-p3", "mean-p4")]
slow = pytest.mark.slow


_STUDIES = {}


def _study(levels: int):
    """Every 2D case x every method (on ``SMALL_LEVELS``: of order 1 and 2) on ``levels`` levels,
    run once per test session."""
    if levels not in _STUDIES:
        methods = SMALL_METHODS if levels == SMALL_LEVELS else [m for m in RATE_METHODS
                                                                if any(METHODS[m].supports(c) for c in CASES.values())]
        _STUDIES[levels] = run(list(CASES.values()), methods=methods, levels=levels, show_progress=False)
    return _STUDIES[levels]


@pytest.fixture(scope="module")
def study():
    return _study(RATE_LEVELS)


@pytest.fixture(scope="module", params=[SMALL_LEVELS, pytest.param(RATE_LEVELS, marks=slow)], ids=lambda n: f"{n}-levels")
def any_study(request):
    return _study(request.param)


@pytest.fixture(scope="module")
def rates(study):
    return rate_table(study).set_index(["case", "method"])


# (case, method) pairs with a proven rate, and those without (e.g. penalty and Nitsche below H^{3/2})
PAIRS = [(c, m) for c in CASES for m in RATE_METHODS if METHODS[m].supports(CASES[c])]
PROVEN = [(c, m) for c, m in PAIRS if np.isfinite(METHODS[m].expected(CASES[c]).rate)]
UNPROVEN = [(c, m) for c, m in PAIRS if (c, m) not in PROVEN]


@slow
@pytest.mark.parametrize("case_name, method", PROVEN)
def test_fitted_h1_rate_reaches_its_theory_rate(rates, case_name, method):
    row = rates.loc[(case_name, method)]
    assert row.fitted_rate >= row.expected_rate - 0.1, row.pairwise_rates


@slow
@pytest.mark.parametrize("case_name, method", UNPROVEN)
def test_rate_without_theory_is_measured_and_says_so(rates, case_name, method):
    row = rates.loc[(case_name, method)]
    assert row.verdict == "no theory" and np.isfinite(row.fitted_rate) and row.fitted_rate > 0


@pytest.mark.parametrize("model", MODEL_NAMES)
def test_transition_rate_is_three_halves_already_on_five_levels(model):
    """`make test`'s rate check (a few seconds): transition-r32 is asymptotic early; its last
    pairwise rate on levels 0..4 (about 3.6e4 dofs) is at least 1.4."""
    g = run(["transition-r32"], methods=[model], levels=5, show_progress=False)
    assert pairwise_rates(g.h, g.err_h1)[-1] >= 1.4, list(g.err_h1)


@slow
@pytest.mark.parametrize("model", MODEL_NAMES)
def test_transition_rate_between_last_two_levels_is_three_halves(study, model):
    """Issue 2's acceptance: transition-r32, >= 5 levels, last pairwise rate >= 1.4."""
    g = study[(study.case == "transition-r32") & (study.method == model)]
    assert len(g) >= 5 and pairwise_rates(g.h, g.err_h1)[-1] >= 1.4


@slow
@pytest.mark.parametrize("model", MODEL_NAMES)
def test_borderline_error_over_h_log_quarter_does_not_grow(study, model):
    """Thm 4.2 ii / 5.2 ii: e / (h |log h|^{1/4}) stays bounded over the last levels."""
    g = study[(study.case == "borderline-h2") & (study.method == model)]
    normalised = normalised_errors(g.h, g.err_h1, 1.0, 0.25)[-3:]
    assert np.all(np.diff(normalised) <= 0), normalised


@pytest.mark.parametrize("method", [m for m in METHOD_NAMES if any(METHODS[m].supports(c) for c in CASES.values())])
def test_every_discrete_solution_is_solved_to_its_residual_tolerance(any_study, method):
    """KKT residual of the cones, relative Newton residual of penalty and Nitsche: <= 1e-10."""
    g = any_study[any_study.method == method]
    if g.empty and METHODS[method].order > 2 and any_study.level.max() < RATE_LEVELS - 1:
        pytest.skip("degree k >= 3 on every case: the slow tier's 6-level study")
    if g.empty and method not in RATE_METHODS:
        pytest.skip("measured on the cases that show its rate: tests/test_degree.py")
    assert not g.empty and (g.status == "converged").all() and (g.kkt_residual <= 1e-10).all()


def test_fit_recovers_a_known_rate_and_log_exponent():
    h = 0.5 ** np.arange(2, 8)
    e = 3.0 * h**1.0 * np.abs(np.log(h)) ** 0.25
    p, se = fit_rate(h, e, log_exponent=0.25, levels=4)
    assert p == pytest.approx(1.0, abs=1e-12) and se < 1e-10
    p0, _ = fit_rate(h, e, log_exponent=0.0, levels=4)
    assert p0 < 0.95   # ignoring the log factor underestimates the rate


@slow
@pytest.mark.parametrize("order, method", [(2, "nodal"), (1, "p1")])
@pytest.mark.parametrize("case_name", EXACT_CASES)
def test_best_approximation_rate_measures_the_declared_regularity(rates, case_name, order, method):
    """The Ritz projection, no contact involved, converges at min(nu - 1, order): the case has the
    regularity it declares. borderline-h2 (its docstring: best approximation ~ h |log h|^{1/2 - beta},
    the only case whose theorem carries a log factor) at least at nu - 1 - 0.1, its pairwise
    rates falling towards nu - 1."""
    case = CASES[case_name]
    row = rates.loc[(case_name, method)]
    expected = min(case.nu - 1.0, order)
    assert row.best_expected_rate == expected
    if case.expected_log_exponent and case.nu - 1.0 < order:
        pairwise = np.array(row.pairwise_rates_best.split(), float)
        assert row.fitted_rate_best >= expected - 0.1 and np.all(np.diff(pairwise) < 0), row.pairwise_rates_best
    else:
        assert abs(row.fitted_rate_best - expected) <= 0.1, row.pairwise_rates_best


@slow
@pytest.mark.parametrize("method", [m for m in METHOD_NAMES if METHODS[m].sharper_theory is not None])
def test_no_case_falls_below_the_drouet_hild_bound(rates, method):
    verdicts = rates.xs(method, level="method").sharper_verdict
    assert set(verdicts) <= {"meets", "above", "no theory"}, verdicts.to_dict()


def test_no_method_beats_the_best_approximation_in_the_energy_norm(any_study):
    """R_h u minimises a(u - v_h, u - v_h) over X_h with the Dirichlet lift (|u - v_h|_1 for the
    Laplacian; the elastic energy in elasticity, where the H^1 error of u_h may be smaller): no
    method's u_h does better (up to the error integration's accuracy). Every row, smooth's P3/P4
    ones too, whose D^3 u jumps across x = 0 inside elements (its ``derivative_jumps``:
    test_the_error_integral_of_smooth_is_converged_across_its_derivative_jump)."""
    exact = any_study[any_study.errors_against == "exact"]
    assert (exact.err_energy >= exact.err_best_energy * (1 - 1e-6)).all()


# smooth's P4 errors on the levels whose elements are largest against the line x = 0
JUMP_LEVELS = 2
# the much finer integration: one more level of subdivision (4 times the pieces, each crossed one
# half as large), Gauss order 16 on each piece
FINE_ORDER = 16


def test_the_error_integral_of_smooth_is_converged_across_its_derivative_jump():
    """smooth's D^3 u jumps across x = 0, inside elements, where |grad(u - R_h u)|^2 of P4 is
    piecewise smooth with a kink: the study's error integral (``fem.element_quadrature``: the
    crossed elements split) agrees with a much finer one (one more level of splitting, Gauss
    order 16) to 1e-7 on levels 0 and 1, where the plain Gauss rule of the same order (what the
    study would use without the case's ``derivative_jumps``) misses by more than 1e-3."""
    import ngsolve as ngs

    from harness.fem.assembly import discretise
    from harness.fem.element_quadrature import SPLIT_DEPTH, ElementQuadrature
    from harness.measure.best_approximation import ritz_projection
    from harness.measure.errors import error_order
    from harness.mesh.levels import mesh_hierarchy
    case = CASES["smooth"]
    for level, mesh in mesh_hierarchy(case, JUMP_LEVELS):
        quadrature = ElementQuadrature.of(case, mesh)
        assert len(quadrature.crossed_elements) > 0
        problem = discretise(case, mesh, 4, quadrature)
        e = ngs.grad(problem.gridfunction(ritz_projection(case, problem))) - case.grad_u
        square = ngs.CF((ngs.InnerProduct(e, e),))
        study = quadrature.integrate(square, error_order(4))[0] ** 0.5
        fine = ElementQuadrature.of(case, mesh, split_depth=SPLIT_DEPTH + 1).integrate(square, FINE_ORDER)[0] ** 0.5
        plain = ngs.Integrate(square[0], mesh, order=error_order(4)) ** 0.5
        assert abs(study - fine) <= 1e-7 * fine, (level, study, fine)
        assert abs(plain - fine) > 1e-3 * fine, (level, plain, fine)


# Measured, not understood yet: on oscillating-r34 (infinitely many transitions, nu = 7/4) the
# P3 penalty method's pressure error ||h^{1/2} (lambda - lambda_h)|| falls at 0.25 over the last
# three of six levels (its P1 and P2 versions, and P4 on one level fewer, above 0.4)
GAMMA_C_PAIRS = [pytest.param(c, m, marks=pytest.mark.xfail(strict=True, reason="measured pressure rate 0.25"))
                 if (c, m) == ("oscillating-r34", "penalty-p3") else (c, m) for c, m in PAIRS]


@slow
@pytest.mark.parametrize("case_name, method", GAMMA_C_PAIRS)
def test_errors_on_gamma_c_converge(study, rates, case_name, method):
    """The trace error in L^2(Gamma_C) and the pressure error in ||h^{1/2} .||_{L^2(Gamma_C)}
    (lambda_h: the Riesz representative of the residual) fall under refinement for every
    method, also where lambda is not in L^2(Gamma_C) (corner-r12, lambda ~ r^{-1/2}). Where all
    of Gamma_C binds and every contact node is pinned at the obstacle (elastic-wedge), the trace
    is exact (error 0 on every level) and has no rate."""
    row = rates.loc[(case_name, method)]
    trace = study[(study.case == case_name) & (study.method == method)].err_trace_l2
    assert row.fitted_rate_trace > 0.9 or (trace == 0).all(), (row.fitted_rate_trace, list(trace))
    assert row.fitted_rate_pressure_h12 > 0.4, row.fitted_rate_pressure_h12


# Measured on oscillating-r34 (6 P2 levels, P1 7), fitted over the last three levels.
REMARK_43_MEASURED = {"mean": 0.736, "nodal": 0.743, "p1": 0.705}


@slow
@pytest.mark.parametrize("method, measured", REMARK_43_MEASURED.items())
def test_infinitely_many_transitions_cost_no_rate(rates, method, measured):
    """Remark 4.3: with infinitely many transition points (oscillating-r34, nu = 7/4) the paper
    proves nothing; the authors believe the rate stays h^{nu - 1} = h^{3/4}. Measured: both P2
    models converge at 0.74 (P1 0.70), like the best approximation (0.73; P1 0.70)
    and with err / best about 1: the data support the belief, no loss of rate. Pinned at the
    measured value +-0.1, so that a change of the harness that moves it is noticed."""
    row = rates.loc[("oscillating-r34", method)]
    assert row.fitted_rate == pytest.approx(measured, abs=0.1), row.pairwise_rates
    assert abs(row.fitted_rate - row.fitted_rate_best) <= 0.05


def _chain(rates: list[float], best_rates: list[float], over_best: float, expected: float = 2.0, nu: float = 3.5):
    """A synthetic uniform chain of five levels whose pairwise H¹ rates are ``rates`` and whose best
    approximation's are ``best_rates``, the method's error ``over_best`` times the best's on the
    finest level."""
    import pandas as pd
    h = 0.5 ** np.arange(5)
    def errors(pairwise):
        e = [1.0]
        for r in pairwise:
            e.append(e[-1] * 0.5 ** r)
        return np.array(e)
    best = errors(best_rates)
    err = errors(rates)
    err *= over_best * best[-1] / err[-1]
    return pd.DataFrame({"case": "c", "mesh": "uniform", "method": "m", "order": 2, "level": range(5), "h": h,
                         "ndof": 100 / h**2, "err_h1": err, "err_best_h1": best, "err_h1_over_best": err / best,
                         "expected_rate": expected, "expected_log_exponent": 0.0, "reference": "r", "nu": nu})


@pytest.mark.parametrize("rates, best_rates, over_best, expected, verdict", [
    ([2.0] * 4, [2.0] * 4, 1.0, 2.0, "meets"),
    ([2.5] * 4, [2.0] * 4, 1.0, 2.0, "above"),
    ([1.0] * 4, [2.0] * 4, 8.0, 2.0, "below"),                          # loses against its own space
    ([1.6, 1.7, 1.75, 1.85], [1.6, 1.7, 1.75, 1.85], 1.002, 2.0, "pre-asymptotic"),   # as smooth-3d's
    ([1.6, 1.7, 1.75, 1.85], [1.6, 1.7, 1.75, 1.85], 1.5, 2.0, "below"),             # costs beyond the space
    ([1.8, 1.75, 1.7, 1.7], [1.8, 1.75, 1.7, 1.7], 1.0, 2.0, "below"),                # not climbing
    ([1.5, 1.6, 1.7, 1.8], [2.0] * 4, 1.05, 2.0, "below"),                           # the space is not short
    ([2.0] * 4, [2.0] * 4, 1.0, np.nan, "no theory"),
])
def test_each_verdict_of_a_synthetic_chain(rates, best_rates, over_best, expected, verdict):
    """Issue 54: 'pre-asymptotic' is a 'below' that the space explains (err/best <= 1.1 on the
    finest level, the best approximation short of min(nu - 1, k) by as much, pairwise rates still
    climbing); 'below' stays for a method that loses against its own space."""
    assert rate_table(_chain(rates, best_rates, over_best, expected)).iloc[0].verdict == verdict
