"""3D residual estimator and 3D adaptive meshes (issue 53, part 2): the estimator's volume and
jump terms against NGSolve's own element-boundary integration, the estimator vanishing on a P2
exact solution in contact (scalar and elastic), its tangential term, and the SOLVE -> ESTIMATE
-> MARK -> REFINE chain on 3D exact cases with a finite effectivity on every row."""
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pandas as pd
import pytest
from conftest import assert_volume_and_jumps_are_ngsolves

from harness.fem.assembly import discretise
from harness.fem.element_quadrature import ElementQuadrature
from harness.measure.errors import error_norms
from harness.measure.estimator import ResidualEstimator, estimate
from harness.measure.estimator_3d import MeshFaces
from harness.mesh.bisection import AdaptiveRefinement
from harness.mesh.levels import coarse_mesh
from harness.mesh.strategies import MeshStrategy, element_budget
from harness.methods import get_method
from harness.problem.case import load_case, registered_cases
from harness.problem.validate import validate_case
from harness.study.chain import run_chain

DATA = Path(__file__).parent / "data"
TOLERANCE = 1e-10


# `make test` checks each (case, mesh) once, P1 and P2 between them; the other three (1.5-5 s each) in `make test-full`
ESTIMATOR_MESHES = [("transition-line-3d", "uniform", 2), ("elastic-junction-3d", "graded", 1),
                    ("elastic-transition-3d", "uniform", 2)]
ESTIMATOR_MESHES += [pytest.param(name, strategy, 3 - order, marks=pytest.mark.slow)
                     for name, strategy, order in ESTIMATOR_MESHES]


@pytest.mark.parametrize("name, strategy, order", ESTIMATOR_MESHES)
def test_the_3d_estimators_volume_and_jump_terms_are_ngsolves_integrals(name, strategy, order):
    """The element residual and the flux jumps on tetrahedra, made from F(u_h) at the vertices
    (``estimator_3d.TetrahedronTerms``), agree with NGSolve's own integration of the same terms
    on each element, for a function that is no solution (every jump nonzero), on uniform and
    graded meshes, with and without a volume load, scalar and elastic (sigma(u_h) n jumps,
    div sigma(u_h)), across the glued 'interior' faces too."""
    case = load_case(name)
    # the coarse mesh, or graded level 1 (bisected tetrahedra of several shapes)
    for level in MeshStrategy(strategy).sequence(case, order).levels(1 if strategy == "uniform" else 2):
        mesh = level.mesh
    assert_volume_and_jumps_are_ngsolves(case, mesh, order)


def test_every_interior_face_of_a_tetrahedral_mesh_is_paired_once():
    """Each tetrahedron has four faces: the interior ones pair up, the others are the boundary's
    surface elements (less the glued 'interior' ones, which are faces between two tetrahedra)."""
    mesh = coarse_mesh(load_case("transition-line-3d"))
    faces = MeshFaces.make(mesh)
    assert 2 * len(faces.interior) + len(faces.boundary) == 4 * mesh.ne
    outer = sum(1 for element in mesh.Elements(ngs.BND) if element.mat != "interior")
    assert len(faces.boundary) == outer
    assert np.allclose(faces.volume.sum(), 4.0)          # (-1, 1)^2 x (0, 1)
    paired = faces.cells[faces.interior[:, :, 0, None], faces.corners_by_number[faces.interior[:, :, 0], faces.interior[:, :, 1]]]
    assert (paired[:, 0] == paired[:, 1]).all() and (np.diff(paired[:, 0], axis=1) > 0).all()


@pytest.mark.parametrize("name", ["transition-line-3d", "elastic-junction-3d"])
def test_the_3d_neumann_residual_is_taken_on_every_tetrahedron_along_gamma_g(name):
    """The Neumann residual is integrated on the boundaries of the tetrahedra with a face on
    Gamma_g only (``along_neumann``, from the surface elements' labels): the same integral over
    every element's boundary gives the same element values (elastic-junction-3d: Gamma_g on the
    sides and on part of the bottom)."""
    case = load_case(name)
    mesh = coarse_mesh(case)
    problem = discretise(case, mesh, 2)
    u = np.where(problem.free, np.random.default_rng(2).standard_normal(problem.ndof), problem.lift)
    estimator = ResidualEstimator(case, problem)
    gfu, terms = problem.gridfunction(u), estimator.terms
    n = ngs.specialcf.normal(3)
    residual = case.neumann_data(n) - case.physics.flux(ngs.Grad(gfu), n)
    integrand = ngs.specialcf.mesh_size * terms.neumann * ngs.InnerProduct(residual, residual)
    everywhere = ngs.Integrate(integrand * ngs.dx(element_boundary=True, bonus_intorder=2), mesh, element_wise=True).NumPy()
    ours = estimator.indicators(u) - terms.volume_and_jumps(gfu, 2, case.physics)
    np.subtract.at(ours, estimator.element_of_edge, estimator.contact_terms(u, gfu))
    assert everywhere.sum() > 0
    assert np.abs(ours - everywhere).max() <= 1e-9 * everywhere.max()


def _exact_p2_solve(data):
    case = load_case(str(DATA / data))
    validate_case(case)             # u = gap on all of Gamma_C: validation allows its round-off
    mesh = ngs.Mesh(case.geometry.GenerateMesh(maxh=case.maxh))
    problem = discretise(case, mesh, 2)
    solve = get_method("nodal").solve(case, problem, None, None)
    assert solve.fields["kkt_residual"] <= TOLERANCE
    assert error_norms(case, [problem.gridfunction(solve.u)], ElementQuadrature.of(case, mesh))[0]["err_h1"] < 1e-10
    return case, mesh, problem, solve.u


@pytest.mark.parametrize("data", ["quadratic_binding_3d.py", "quadratic_binding_elastic_3d.py"])
def test_the_3d_estimator_vanishes_where_u_h_is_u(data):
    """u in P2 and in the nodal cone (scalar: x z + z^2; elastic: (x z + z^2, y z + x y,
    x z + z^2), frictionless by its contact traction): the solve gives u_h = u and every term
    of eta (the residuals, the flux against the discrete pressure, penetration, complementarity,
    and in elasticity the tangential traction) vanishes to round-off."""
    case, mesh, problem, u = _exact_p2_solve(data)
    eta2 = ResidualEstimator(case, problem).indicators(u)
    assert eta2.shape == (mesh.ne,)
    assert estimate(eta2) < 1e-8


def test_the_3d_elastic_estimator_sees_a_tangential_traction():
    """The frictionless condition is a term of its own in 3D too: the same elastic P2 solution,
    with a contact traction whose tangential part is off by 1/2 along x, has eta > 0 on Gamma_C
    through that term alone (|sigma_t - g_t| = 1/2 at every point)."""
    case, _, problem, u = _exact_p2_solve("quadratic_binding_elastic_3d.py")
    estimator = ResidualEstimator(case, problem)
    estimator.load = estimator.load + np.array([0.5, 0.0, 0.0])     # g_t off by 1/2, g_n unchanged
    contact = estimator.contact_terms(u, problem.gridfunction(u))
    assert contact.sum() == pytest.approx(0.5**2 * (estimator.q.h * estimator.q.weights).sum(), rel=1e-10)


def test_the_3d_estimator_puts_the_contact_terms_on_the_tetrahedra_on_gamma_c():
    """On a coarse transition-line-3d solve each kind of term is nonzero somewhere, and the
    Gamma_C part goes to the tetrahedra with a face there."""
    case = load_case("transition-line-3d")
    mesh = coarse_mesh(case)
    problem = discretise(case, mesh, 2)
    u = get_method("nodal").solve(case, problem, None, None).u
    estimator = ResidualEstimator(case, problem)
    total = estimator.indicators(u)
    contact = estimator.contact_terms(u, problem.gridfunction(u))
    assert contact.shape == (len(problem.trace.faces.volumes),)
    assert contact.sum() > 0 and (total >= 0).all() and total.sum() > contact.sum()
    on_contact = np.zeros(mesh.ne, bool)
    on_contact[problem.trace.faces.volumes] = True
    assert total[on_contact].sum() >= contact.sum()


def test_adaptive_meshes_apply_to_3d_exact_cases_only():
    """3D cases with u get adaptive meshes (curved transition lines too: the estimator needs no
    declared singular set); a 3D case without u is still refused, for its reference."""
    for name in ("transition-line-3d", "transition-circle-3d", "elastic-transition-3d", "elastic-junction-3d"):
        assert MeshStrategy("adaptive").applies_to(load_case(name)) is None
    assert "reference" in MeshStrategy("adaptive").applies_to(load_case("transition-line-3d").with_reference(1))


def test_an_adaptive_level_past_the_budget_of_elements_is_not_made():
    """Each marked element is bisected at least once: when that alone passes the budget, the
    sequence stops before refining (the level would be dropped; in 3D it is the chain's largest
    mesh by a factor of 3 or 4), and the mesh is left as it was."""
    case = load_case("transition-line-3d")
    sequence = AdaptiveRefinement(case)
    levels = sequence.levels(3)
    mesh = next(levels).mesh
    coarse = mesh.ne
    sequence.limit_elements(coarse + 10)
    sequence.observe(np.ones(coarse))                  # Dörfler marks half of the elements
    assert list(levels) == [] and mesh.ne == coarse
    sequence = AdaptiveRefinement(case)
    levels = sequence.levels(2)
    mesh = next(levels).mesh
    sequence.limit_elements(4 * coarse)
    sequence.observe(np.ones(coarse))
    assert next(levels).mesh.ne > coarse * 1.5


# the 3D chains (2-3 s each) in `make test-full`; `make test` runs the 2D chains (test_meshes.py)
@pytest.mark.slow
@pytest.mark.parametrize("name, method", [("transition-line-3d", "nodal"), ("transition-line-3d", "p1"),
                                          ("transition-line-3d", "mean"), ("elastic-transition-3d", "nodal")])
def test_a_3d_adaptive_chain_runs_and_its_rows_carry_a_finite_effectivity(name, method):
    """SOLVE -> ESTIMATE -> MARK -> REFINE on tetrahedra: each level refines the last (more
    dofs), within the uniform level 1's budget of elements, every solve converged exactly, and
    every row has eta > 0 and the effectivity eta / ||u - u_h||_a."""
    case = load_case(name)
    meshes = []
    # P1 within P2's budget of elements (not one uniform level more, its default): seconds
    chosen = get_method(method).with_extra_levels(0)
    output = run_chain(case, [chosen], 2, mesh=MeshStrategy("adaptive"),
                       on_level=lambda case, method, level, problem, solve: meshes.append(problem.mesh.ne))
    frame = pd.DataFrame(output.rows)
    assert len(frame) >= 2 and (frame["mesh"] == "adaptive").all() and (frame.dimension == 3).all()
    assert (frame.status == "converged").all() and (frame.kkt_residual <= TOLERANCE).all()
    assert (np.diff(frame.ndof) > 0).all()
    assert max(meshes) <= element_budget(case, 2)
    assert np.isfinite(frame.estimator).all() and (frame.estimator > 0).all()
    assert np.allclose(frame.effectivity, frame.estimator / frame.err_energy)
    assert np.isfinite(frame.effectivity).all()


@pytest.mark.slow
def test_3d_adaptive_p2_beats_the_uniform_rate_on_the_transition_line():
    """transition-line-3d (u ~ rho^{3/2} across the line x = z = 0): uniform P2 gives
    h^{3/2} = N^{-1/2}, the best isotropic meshes N^{-2/3} (Apel & Nicaise's grading). Adaptive
    `nodal` within the uniform level 3's budget (six levels, 4.7e5 dofs, about 3 minutes on one
    thread) measured N^{-0.62} over its last three levels; held at >= 0.6, with the effectivity
    in [1, 10] and steady (max/min <= 2) over the last four levels, as in 2D."""
    from harness.measure.rates import fit_ndof_rate

    output = run_chain(load_case("transition-line-3d"), [get_method("nodal")], 4, mesh=MeshStrategy("adaptive"))
    frame = pd.DataFrame(output.rows)
    assert len(frame) >= 5 and (frame.status == "converged").all()
    assert fit_ndof_rate(frame.ndof, frame.err_h1) >= 0.6
    effectivity = frame.effectivity.to_numpy()
    assert ((effectivity >= 1) & (effectivity <= 10)).all(), effectivity
    assert effectivity[-4:].max() / effectivity[-4:].min() <= 2, effectivity


# every registered one-body 3D case with u in the default report profile (elastic-transition-circle-3d,
# of the fine profile, is left out for its cost), scalar and elastic
EXACT_3D = sorted(name for name, case in registered_cases(3).items()
                  if case.bodies == 1 and case.exact and case.report_profile == "default")


@pytest.mark.slow
@pytest.mark.parametrize("method", ["nodal", "p1"])
@pytest.mark.parametrize("case_name", EXACT_3D)
def test_the_3d_effectivity_is_bounded_and_steady_on_every_exact_3d_case(case_name, method):
    """The 2D criterion (tests/test_meshes.py) on tetrahedra: on every exact 3D case x cone of
    each order x adaptive level, within the uniform level 2's budget of elements (3 to 6 levels,
    3 minutes for all of them), the effectivity lies in [0.5, 10] and max/min <= 2 over the
    last four levels (measured: 2.3 to 7.8, max/min <= 1.4)."""
    case = load_case(case_name)
    frame = pd.DataFrame(run_chain(case, [get_method(method).with_extra_levels(0)], 3, mesh=MeshStrategy("adaptive")).rows)
    effectivity = frame.effectivity.to_numpy()
    assert len(effectivity) >= 3
    assert ((effectivity >= 0.5) & (effectivity <= 10)).all(), effectivity
    assert effectivity[-4:].max() / effectivity[-4:].min() <= 2, effectivity
