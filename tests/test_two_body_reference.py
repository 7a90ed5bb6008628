"""Two-body reference cases (no u; issue 76): the contract loads one from a file outside the
repository, ``harness.run`` measures each body against `mortar-nodal`'s solution one level finer
(``study.chain.two_body.TwoBodyErrors`` over ``measure.reference.ReferenceErrors``) and the
combined columns equal the errors integrated by hand; the lower body holds its own Dirichlet
data at every load step; what cannot work is refused in one line; the two-body closed forms
(``problem.closed_forms.identical_bodies_modulus``, ``effective_radius``) and, on matching meshes,
cattaneo-two-body-q03's normal step = hertz-line in each body.

The file case: two small blocks (coarse zone a few elements wide), Coulomb mu_F = 0.3, the upper
top pressed by (0, -DELTA), then moved by (XI, -DELTA), the lower one held at (0, -DELTA)."""
from __future__ import annotations

import math
import textwrap
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pytest

import harness
from harness.fem.assembly import discretise
from harness.fem.mortar import mortar_coupling
from harness.fem.two_body import TwoBodyProblem, dual_bound_qp
from harness.mesh.levels import coarse_mesh
from harness.mesh.strategies import parse_mesh
from harness.mesh.strategies import refusal as mesh_refusal
from harness.methods import get_method, methods_named
from harness.methods.mortar import two_body_steps
from harness.problem import closed_forms
from harness.problem.bodies import lower_body
from harness.problem.case import load_case
from harness.study.chain.snapshots import two_body_snapshot
from harness.study.chain.two_body import run_two_body_chain

DELTA, XI = 0.04, 0.01
CASE_FILE = f'''
    """A two-body reference case of one's own: two blocks pressed together, then sheared."""
    from ngsolve import CF, x

    from harness.problem import Coulomb, LoadHistory, LoadStep, MirrorBody, zone_rectangle

    name = "my-two-body-shear"
    description = "two blocks pressed together, then sheared (Coulomb)"
    physics, poisson = "elasticity", 0.3
    geometry, maxh = zone_rectangle(1.0, 1.0, 0.4, 0.2), 0.5
    second_body = MirrorBody(zone_rectangle(1.0, 1.0, 0.4, 0.15), 0.5, dirichlet=CF((0.0, -{DELTA})))
    f, dirichlet, neumann = CF((0.0, 0.0)), CF(({XI}, -{DELTA})), CF((0.0, 0.0))
    gap = x * x / 2
    friction = Coulomb(0.3)
    history = LoadHistory((LoadStep("normal", dirichlet=CF((0.0, -{DELTA}))), LoadStep("tangential")))
    reference_levels = 1
'''


@pytest.fixture(scope="module")
def case_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("outside") / "my_two_body_shear.py"
    path.write_text(textwrap.dedent(CASE_FILE))
    return path


@pytest.fixture(scope="module")
def case(case_file):
    return load_case(str(case_file))


def _body_solutions(case, method, level, problem, solve) -> list:
    """``harness.run``'s on_level hook: each body's u_h as a GridFunction on a mesh of its own
    (the body's coarse mesh refined ``level`` times: the chain refines its meshes in place)."""
    kept = []
    for body, own, part in zip((case, lower_body(case)), problem.bodies, problem.split(solve.u)):
        mesh = coarse_mesh(body)
        for _ in range(level):
            mesh.ngmesh.Refine()        # red refinement, as the chain's (``mesh.levels.mesh_hierarchy``)
        here = ngs.GridFunction(ngs.VectorH1(own.mesh, order=2))
        here.vec.FV().NumPy()[:] = own.cartesian(part)
        copy = ngs.GridFunction(ngs.VectorH1(mesh, order=2))
        copy.Set(here)
        kept.append(copy)
    return kept


SNAPSHOTS = {}


@pytest.fixture(scope="module")
def rows(case):
    """The rows of levels 0-1; each level's report snapshot of Gamma_C kept in ``SNAPSHOTS``."""
    def snapshot(case, method, level, problem, solve):
        SNAPSHOTS[level] = two_body_snapshot(case, problem, solve)
    return harness.run(case, methods=["mortar-nodal"], levels=2, show_progress=False, on_level=snapshot)


def test_a_two_body_reference_case_from_a_file_runs_against_mortar_nodal_one_level_finer(case, rows):
    """Loaded from a file outside the repository, run through ``harness.run`` (`mortar-nodal`,
    levels 0-1): every row converged (KKT <= 1e-10, two load steps) and measured against
    `mortar-nodal` on level 2 (converged too); no best approximation; the error falls."""
    assert case.bodies == 2 and not case.exact and "reference" in case.groups
    assert len(rows) == 2 and (rows.status == "converged").all() and (rows.load_steps == 2).all()
    assert (rows.kkt_residual <= 1e-10).all() and (rows.errors_against == "reference").all()
    assert (rows.reference_method == "mortar-nodal").all() and (rows.reference_level == 2).all()
    assert (rows.reference_kkt_residual <= 1e-10).all() and rows.err_best_h1.isna().all()
    assert rows.err_h1.iloc[1] < rows.err_h1.iloc[0] and rows.err_energy.notna().all()


def test_the_report_draws_no_exact_opening_or_pressure_of_a_two_body_reference_case(rows):
    """``study.chain.snapshots.two_body_snapshot``: u_h's opening and the mortar pressure are
    drawn, the exact ones (no u) are NaN."""
    snapshot = SNAPSHOTS[1]
    assert np.isnan(snapshot["u"]).all() and np.isnan(snapshot["exact_pressure"]).all()
    assert np.isfinite(snapshot["u_h"]).all() and snapshot["pressure"].max() > 0


@pytest.mark.slow       # 1.5-2.6 s: a second chain, three levels studied
def test_the_two_body_reference_errors_are_those_integrated_by_hand(case, rows):
    """err_h1, err_h1_semi and err_l2 of the rows are sqrt(sum over the bodies) of
    || u_R - u_h || integrated by NGSolve on each body's level-2 mesh (u_h evaluated across the
    nested meshes; u_R `mortar-nodal`'s level 2 of a three-level chain), to 1e-8 relative
    (measured: 1e-10)."""
    kept = {}
    harness.run(case, methods=["mortar-nodal"], levels=3, show_progress=False,
                on_level=lambda *args: kept.setdefault(args[2], _body_solutions(*args)))
    for level, row in rows.iterrows():
        squares = np.zeros(2)
        for reference, studied in zip(kept[2], kept[level]):
            e = reference - studied
            squares += [ngs.Integrate(ngs.InnerProduct(e, e), reference.space.mesh, order=6),
                        ngs.Integrate(ngs.InnerProduct(ngs.Grad(e), ngs.Grad(e)), reference.space.mesh, order=6)]
        l2, semi = np.sqrt(squares)
        assert row.err_l2 == pytest.approx(l2, rel=1e-8) and row.err_h1_semi == pytest.approx(semi, rel=1e-8)
        assert row.err_h1 == pytest.approx(math.hypot(l2, semi), rel=1e-8)


def test_the_lower_body_of_a_reference_case_holds_its_own_data_at_both_steps(case):
    """``MirrorBody(..., dirichlet=(0, -DELTA))``: the lower body's lift is (0, -DELTA) at its
    Dirichlet dofs at both load steps; the upper one's moves by XI along x between the steps."""
    meshes = [coarse_mesh(body) for body in (case, lower_body(case))]
    problem = TwoBodyProblem(*(discretise(body, mesh, 2) for body, mesh in zip((case, lower_body(case)), meshes)))
    qp = dual_bound_qp(problem, mortar_coupling(problem.upper, problem.lower, case.obstacle, "dual", "midpoint"), 4.0,
                       tangential=True)
    (_, first), (_, second) = two_body_steps(case, problem, qp)
    n1, lower = problem.upper.ndof, problem.lower
    fixed = np.flatnonzero(~lower.free)
    half = lower.ndof // 2
    vertices = fixed[np.isin(fixed % half, np.arange(lower.mesh.nv))]       # P2 edge coefficients of a constant are 0
    for lift in (first, second):
        values = lift[n1:][vertices]
        np.testing.assert_allclose(values[vertices < half], 0.0, atol=1e-14)
        np.testing.assert_allclose(values[vertices >= half], -DELTA, rtol=1e-13)
    moved = np.flatnonzero(np.abs(second - first) > 1e-14)
    assert len(moved) > 0 and (moved < n1 // 2).all()
    np.testing.assert_allclose((second - first)[moved], XI, rtol=1e-12)


def test_a_reference_case_without_the_lower_bodys_own_data_gives_it_the_upper_ones(case):
    """Without ``MirrorBody.dirichlet`` the lower body solves the upper body's problem (its data
    and load steps: ``problem.bodies.lower_body``)."""
    import dataclasses
    plain = dataclasses.replace(case, second_body=dataclasses.replace(case.second_body, dirichlet=None))
    lower = lower_body(plain)
    assert lower.dirichlet is plain.dirichlet and lower.history is plain.history


@pytest.mark.parametrize("strategy", ["graded", "adaptive"])
def test_graded_and_adaptive_meshes_refuse_a_two_body_reference_case_in_one_line(case, strategy):
    """Each body's errors need its meshes nested in the reference's: uniform pairs only (the
    strategy's refusal, and the chain's own if it is bypassed)."""
    (chosen,) = [s for s in parse_mesh("all") if s.name == strategy]
    reason = mesh_refusal(chosen, case)
    assert reason is not None and "\n" not in reason and "uniform pairs" in reason
    assert mesh_refusal(parse_mesh("uniform")[0], case) is None
    with pytest.raises(ValueError, match=r"^[^\n]*uniform pairs only[^\n]*$"):
        run_two_body_chain(case, methods_named(["mortar-nodal"]), 2, mesh=chosen, plan=_reference_plan())


def _reference_plan():
    from harness.study.chain.walk import ChainPlan
    return ChainPlan({"mortar-nodal": 2}, {"mortar-nodal": 3}, "mortar-nodal")


def test_a_two_body_chain_without_u_needs_its_reference_plan_in_one_line(case):
    with pytest.raises(ValueError, match=r"^[^\n]*measured against a reference[^\n]*$"):
        run_two_body_chain(case, [get_method("mortar-nodal")], 2)


@pytest.mark.parametrize("poisson", [0.0, 0.3, 0.45])
@pytest.mark.parametrize("radius", [0.5, 1.0, 8.0])
def test_identical_bodies_have_the_rigid_indenters_contact_zone(poisson, radius):
    """E* = E/(2 (1 - nu^2)) and R* = R/2 for two identical cylinders of radius R: a and p0 are
    ``hertz_line(P, R, E/(1 - nu^2))``'s, the rigid indenter's at the same P and R."""
    young, force = 2.5, 8.6e-3
    e_star = closed_forms.identical_bodies_modulus(young, poisson)
    assert e_star == pytest.approx(closed_forms.contact_modulus(young, poisson) / 2, rel=1e-15)
    r_star = closed_forms.effective_radius(radius, radius)
    assert r_star == pytest.approx(radius / 2, rel=1e-15)
    two = closed_forms.hertz_line(force, r_star, e_star)
    rigid = closed_forms.hertz_line(force, radius, young / (1 - poisson**2))
    np.testing.assert_allclose(two, rigid, rtol=1e-14)


def test_the_effective_radius_adds_the_curvatures():
    assert closed_forms.effective_radius(2.0, 3.0) == pytest.approx(1.2, rel=1e-15)
    assert closed_forms.effective_radius(1.0, math.inf) == 1.0       # a cylinder against a flat


CASES = Path(__file__).resolve().parent.parent / "cases"


# (method, the one-body method it is on matching meshes, how far apart: relative to max |u|, or
# in absolute terms on the P1 pair) -- mortar-p1's dual linear rows impose the dual projection of
# the parabolic gap, int psi_i x^2/2 / D_i = x_i^2/2 - h^2/12 on a uniform stretch (psi_i = 2 phi_i -
# phi_j on each element), not p1's nodal x_i^2/2: measured 5.2083e-5 = h^2/12 at the zone's h = a/4
MATCHING = [("mortar-nodal", "nodal", 1e-9, None), ("mortar-p1", "p1", None, 1.001 * 0.025**2 / 12)]


@pytest.mark.parametrize("method_name, one_body, relative, absolute", MATCHING)
def test_the_normal_step_of_a_matching_two_body_cattaneo_pair_is_hertz_line_in_each_body(method_name, one_body,
                                                                                         relative, absolute):
    """cattaneo-two-body-q03's normal step (both tops at (0, -delta), Coulomb mu_F = 0.3) on
    hertz-line's block, with the lower body meshed as the upper (matching meshes), level 0: by the mirror symmetry the jump
    vanishes, no friction acts, and each body's u_h is hertz-line's own of the matching one-body
    method (the dual mortar rows on matching meshes are its cones on the jump): `mortar-nodal`'s
    to 1e-9 relative, `mortar-p1`'s up to the h^2/12 its rows move the gap by (``MATCHING``).
    The identical-bodies closed forms give the same a and p0 as the rigid indenter's at the
    same P (``test_identical_bodies_have_the_rigid_indenters_contact_zone``): two-body Hertz is
    rigid Hertz."""
    import dataclasses

    from ngsolve import CF

    from harness.problem.bodies import MirrorBody
    from harness.problem.friction import STATIC
    two = load_case(str(CASES / "cattaneo_two_body_q03.py"))
    pressed = CF((0.0, -0.015))
    hertz = load_case(str(CASES / "hertz_line.py"))
    # on hertz-line's 10 a block (the registered pair's blocks are 20 a)
    two = dataclasses.replace(two, geometry=hertz.geometry, singular_points=hertz.singular_points, dirichlet=pressed, history=STATIC,
                              second_body=MirrorBody(hertz.geometry, two.maxh, dirichlet=pressed))
    method, reference = get_method(method_name), get_method(one_body)
    problem = TwoBodyProblem(*(discretise(body, coarse_mesh(body), method.order) for body in (two, lower_body(two))))
    solved = method.solve(two, problem, None, None)
    one = discretise(hertz, coarse_mesh(hertz), reference.order)
    expected = reference.solve(hertz, one, None, None)
    assert solved.fields["kkt_residual"] <= 1e-10 and expected.fields["kkt_residual"] <= 1e-10
    for body, part in zip(problem.bodies, problem.split(solved.u)):
        assert body.ndof == one.ndof
        difference = np.abs(body.cartesian(part) - one.cartesian(expected.u)).max()
        assert difference <= (absolute if relative is None else relative * np.abs(expected.u).max()), difference
