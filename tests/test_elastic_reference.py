"""Reference cases in elasticity (plane strain): the exact vector prolongation, the errors against a
reference checked with the exact errors, and an elastic case without u through the command line."""
import subprocess
import sys
from pathlib import Path

import ngsolve as ngs
import numpy as np
import pandas as pd
import pytest

from harness import run
from harness.measure.reference import LevelNumbering, blockwise, embed, norm_matrices, prolongation, squares
from harness.mesh.levels import coarse_mesh, mesh_hierarchy
from harness.mesh.points import evaluate
from harness.problem.case import CaseError, load_case, registered_cases

DATA = Path(__file__).parent / "data"
TRANSITION_DATA = str(DATA / "elastic_transition_data.py")      # elastic-transition-r32 without its u
PUNCH = str(DATA / "elastic_parabolic_punch.py")


def vector_forms(mesh: ngs.Mesh, order: int) -> list:
    """NGSolve's own VectorH1 matrices of the H^1 seminorm and the L^2 norm on ``mesh``."""
    fes = ngs.VectorH1(mesh, order=order)
    u, v = fes.TnT()
    return [ngs.BilinearForm(integrand * ngs.dx).Assemble().mat for integrand in (ngs.InnerProduct(ngs.Grad(u), ngs.Grad(v)), u * v)]


def ngsolve_square(matrix, vector: np.ndarray) -> float:
    x = matrix.CreateColVector()
    x.FV().NumPy()[:] = vector
    return ngs.InnerProduct(x, matrix * x)


@pytest.mark.parametrize("order", [1, 2])
def test_vector_prolongation_embeds_a_coarse_elastic_function_exactly(order, rng):
    """A random VectorH1 function of ``order`` on the coarse mesh, prolonged block by block
    (kron(I_2, P) on NGSolve's component-blocked dofs) through two red refinements and embedded
    in P2: NGSolve evaluates the same function at random points on both meshes (to 1e-12), and
    its H^1-semi and L^2 norms, the scalar matrices applied per component block, equal those of
    NGSolve's VectorH1 forms on the coarse mesh (to 1e-12 relative)."""
    case = load_case(TRANSITION_DATA)
    copy = coarse_mesh(case)
    numberings = []
    for _, mesh in mesh_hierarchy(case, 3):
        numberings.append(LevelNumbering.of(mesh))
    coarse_fes = ngs.VectorH1(copy, order=order)
    u = rng.standard_normal(coarse_fes.ndof)
    fine = blockwise(prolongation(numberings[1], numberings[2], order),
                     blockwise(prolongation(numberings[0], numberings[1], order), u))
    fine = embed(fine, numberings[2], order)
    coarse_gf, fine_gf = ngs.GridFunction(coarse_fes), ngs.GridFunction(ngs.VectorH1(mesh, order=2))
    coarse_gf.vec.FV().NumPy()[:] = u
    fine_gf.vec.FV().NumPy()[:] = fine
    points = np.column_stack([rng.uniform(-1, 1, 200), rng.uniform(0, 1, 200)])
    assert np.abs(evaluate(coarse_gf, copy, points) - evaluate(fine_gf, mesh, points)).max() < 1e-12
    coarse_norms = [ngsolve_square(matrix, u) for matrix in vector_forms(copy, order)]
    fine_norms = [squares(matrix, fine[:, None])[0] for matrix in norm_matrices(mesh, 2)]
    assert np.allclose(fine_norms, coarse_norms, rtol=1e-12)


NORMS = ["err_h1_semi", "err_l2", "err_energy", "err_trace_l2", "err_pressure_l2"]
# the exact errors' quadrature is accurate to 0.1% (tests/test_errors.py), the reference's exact
QUADRATURE = 1e-3


@pytest.fixture(scope="module", params=["data, flat Gamma_C", "with_reference, tilted Gamma_C"])
def exact_and_reference(request):
    """(exact rows of nodal and p1, rows against the reference k = 2 levels finer, |u - u_R| by
    norm): elastic-transition-r32 declared by its data (no u), 3 levels (P1: 4); and the tilted
    copy of it (rotated frame: Q != I on Gamma_C) measured against a reference by
    ``with_reference``. |u - u_R| is the exact error of nodal on the reference's level, 4."""
    if request.param.startswith("data"):
        exact, reference = registered_cases()["elastic-transition-r32"], load_case(TRANSITION_DATA)
    else:
        exact = load_case(str(DATA / "tilted_elastic.py"))
        reference = exact.with_reference(2)
    assert reference.u is None or request.param.startswith("with_reference")
    exact_rows = pd.concat([run(exact, methods="nodal", levels=5, show_progress=False),
                            run(exact, methods="p1", levels=3, show_progress=False)])
    reference_rows = run(reference, methods=["nodal", "p1"], levels=3, show_progress=False)
    assert (reference_rows.reference_level == 4).all()
    own = exact_rows[(exact_rows.method == "nodal") & (exact_rows.level == 4)].iloc[0]
    return exact_rows, reference_rows, own[NORMS].astype(float)


@pytest.mark.parametrize("method", ["nodal", "p1"])
def test_elastic_errors_against_a_reference_miss_only_the_references_own_error(exact_and_reference, method):
    """On every level, every norm: |err_ref - err_exact| <= |u - u_R| (triangle inequality; plus
    the exact errors' quadrature), and in the energy norm, whose inner product is a(., .),
    Galerkin orthogonality err_exact^2 = err_ref^2 + |u - u_R|^2 to 1e-3 (contact breaks it;
    measured within 1e-4 on both Gamma_C). The reference's own share at k = 2 is small: on
    nodal's finest level |u - u_R|_E / |u - u_h|_E <= 0.15 (4^{-3/2} = 0.125 for h^{3/2};
    measured 0.126) and the energy errors agree within 1% (measured 0.9921)."""
    exact_rows, reference_rows, own = exact_and_reference
    reference = reference_rows[reference_rows.method == method].sort_values("level")
    exact = exact_rows[(exact_rows.method == method) & exact_rows.level.isin(reference.level)].sort_values("level")
    assert (reference.errors_against == "reference").all() and (reference.reference_kkt_residual <= 1e-10).all()
    for norm in NORMS:
        gap = np.abs(reference[norm].values - exact[norm].values)
        assert (gap <= own[norm] + QUADRATURE * exact[norm].values).all(), norm
    pythagoras = np.sqrt(reference.err_energy.values**2 + own.err_energy**2) / exact.err_energy.values
    assert np.abs(pythagoras - 1).max() <= 1e-3
    assert np.abs(reference.err_energy.values / exact.err_energy.values - 1).max() <= 0.01
    if method == "nodal":
        assert own.err_energy / exact.err_energy.values[-1] <= 0.15


def test_an_elastic_reference_case_declares_vector_data():
    """The punch's data are displacements: numbers in every component, vectors kept; a scalar
    function where a displacement is meant is refused in one line."""
    case = load_case(PUNCH)
    assert case.u is None and not case.exact and case.physics.name == "elasticity"
    assert case.f.dim == case.dirichlet.dim == case.neumann.dim == 2


def test_an_elastic_reference_case_with_scalar_dirichlet_data_is_refused(tmp_path):
    source = Path(PUNCH).read_text().replace("dirichlet = CF((0.0, -DELTA))", "dirichlet = -DELTA * x")
    (tmp_path / "scalar_dirichlet.py").write_text(source)
    with pytest.raises(CaseError, match="dirichlet must be a 2-vector for elasticity, got dimension 1"):
        load_case(str(tmp_path / "scalar_dirichlet.py"))


# uniform in `make test`; the other meshes (2-3 s each) in `make test-full`
@pytest.mark.parametrize("mesh", ["uniform", pytest.param("adaptive", marks=pytest.mark.slow),
                                  pytest.param("graded", marks=pytest.mark.slow)])
def test_an_elastic_case_without_u_runs_from_the_command_line(tmp_path, mesh):
    """The block pressed on the parabola, nodal and p1, 3 levels, in a process of its own: every
    row converged and measured against a converged reference (one, k = 2 levels past P2's finest,
    on uniform meshes; each level's own on graded and adaptive ones), with a finite effectivity;
    P2's errors below P1's on the same mesh."""
    subprocess.run([sys.executable, "-m", "harness", "run", "--case", PUNCH, "--method", "nodal", "--method", "p1",
                    "--levels", "3", "--mesh", mesh, "--threads", "1", "--out", str(tmp_path), "--quiet"], check=True)
    frame = pd.read_csv(tmp_path / "results.csv")
    assert set(frame.method) == {"nodal", "p1"} and set(frame["mesh"]) == {mesh}
    assert (frame.status == "converged").all() and (frame.kkt_residual <= 1e-10).all()
    assert (frame.errors_against == "reference").all() and (frame.reference_method == "nodal").all()
    assert (frame.reference_kkt_residual <= 1e-10).all() and (frame.reference_status == "converged").all()
    errors = frame[["err_h1", "err_l2", "err_energy", "err_trace_l2", "err_pressure_l2"]].values
    assert np.isfinite(errors).all() and (errors > 0).all()
    assert np.isfinite(frame.effectivity).all() and (frame.effectivity > 0).all()
    if mesh == "uniform":
        assert (frame.reference_level == 2 + 2).all()
        p1, p2 = (frame[frame.method == m].set_index("level").err_h1 for m in ("p1", "nodal"))
        assert (p2 < p1[p2.index]).all()
    else:
        assert (frame.reference_level == frame.level + np.where(frame.order == 2, 2, 1)).all()
