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
