"""What docs/guide/extending.md says of level 3's basis holds for the NGSolve installed: the
P2 edge dof is a bubble coefficient, u_h at the edge's midpoint (u_a + u_b)/2 - u_e/8."""
import ngsolve as ngs
import pytest
from netgen.geom2d import unit_square


@pytest.mark.parametrize("order", [2, 3])
def test_the_first_edge_dof_is_a_bubble_whose_midpoint_value_is_minus_one_eighth(order):
    mesh = ngs.Mesh(unit_square.GenerateMesh(maxh=0.5))
    fes = ngs.H1(mesh, order=order)
    edge = mesh.edges[0]
    a, b = (mesh.vertices[v.nr].point for v in edge.vertices)
    gf = ngs.GridFunction(fes)
    gf.vec[:] = 0
    gf.vec[fes.GetDofNrs(edge)[0]] = 1
    assert gf(mesh(*a)) == pytest.approx(0, abs=1e-14) and gf(mesh(*b)) == pytest.approx(0, abs=1e-14)
    assert gf(mesh((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)) == pytest.approx(-1 / 8, abs=1e-12)


@pytest.mark.parametrize("order", [1, 2, 3])
@pytest.mark.parametrize("case_name", ["transition-r32", "elastic-transition-r32", "smooth-3d", "elastic-transition-3d"])
def test_level_problem_nodes_give_the_contact_variable_at_gamma_c_lagrange_nodes(case_name, order):
    """``LevelProblem.nodes`` (``fem.contact_quadrature.lagrange_nodes``): ``L @ u`` equals NGSolve's
    own evaluation of c(u_h) (u_h, or -u_h . n on the flat Gamma_C of these cases) at every node, to
    round-off, for a random u; the vertices come first and are the vertex dofs' values; the nodes
    are those of P_k: per edge k - 1 inside (2D), and in 3D (k - 1) per edge and
    (k - 1)(k - 2)/2 per triangle."""
    import numpy as np

    from harness.fem.assembly import discretise
    from harness.mesh.levels import coarse_mesh
    from harness.mesh.points import evaluate
    from harness.methods.protocol import level_problem
    from harness.problem.case import load_case
    case = load_case(case_name)
    problem = discretise(case, coarse_mesh(case), order)
    nodes = level_problem(case, problem, None, None).nodes
    u = np.random.default_rng(1).standard_normal(problem.ndof)
    gf = ngs.GridFunction(problem.fes)
    gf.vec.FV().NumPy()[:] = problem.cartesian(u)
    values = evaluate(gf, problem.mesh, nodes.x)
    if values.ndim == 2:
        assert np.ptp(problem.trace.normals, axis=0).max() == 0          # one normal on Gamma_C
        values = -(values @ problem.trace.normals[0])
    assert np.abs(nodes.L @ u - values).max() <= 1e-13 * max(1.0, np.abs(values).max())
    assert np.array_equal(nodes.L[:nodes.vertices] @ u, u[problem.vertex_dofs])
    trace = problem.trace
    cells = len(trace.a) if trace.faces is None else len(trace.faces.vertices)
    inside = (order - 1) * (len(trace.a) if trace.faces is None else len(trace.edges)) + \
        (0 if trace.faces is None else cells * (order - 1) * (order - 2) // 2)
    assert (nodes.vertices, len(nodes.x)) == (len(trace.vertices), len(trace.vertices) + inside)
