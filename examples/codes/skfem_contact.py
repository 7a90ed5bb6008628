"""scikit-fem's solution of a problem exported by ``python -m harness export`` (issue 75's exchange
format v1, docs/guide/measure-your-code.md): an external program, run in its own environment
(``make .venv-skfem/.installed``), that never imports the harness.

    .venv-skfem/bin/python examples/codes/skfem_contact.py EXPORT_DIR OUT_DIR [--levels N]

Per level it builds scikit-fem's MeshTri / MeshTet from the exported vertices and cells, P_k
Lagrange elements (ElementTriP2 / ElementTetP2, P1 for an order-1 export; ElementVector of them
for plane-strain or 3D elasticity), assembles the stiffness with scikit-fem's own forms, takes the
right-hand side from the exported moments ``load`` and solves the paper's ``nodal`` model
(Belhachmi & Ben Belgacem 2003, model 2: u >= gap at every P_k node of Gamma_C; u . n <= gap
for elasticity) as a bound-constrained quadratic programme by the primal-dual active set method
(Hintermueller, Ito & Kunisch, SIAM J. Optim. 13 (2003) 865-888) with SciPy's sparse LU. The
coarsest level is cross-checked against SciPy's bounded-variable least squares (Stark & Parker
1995, ``scipy.optimize.lsq_linear(method="bvls")``), an independent algorithm. It writes
OUT_DIR/manifest.json and OUT_DIR/level-L.npz, the solution format ``external:OUT_DIR`` reads.
"""
from __future__ import annotations

import argparse
import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy
import scipy.sparse as sp
import skfem
from scipy.optimize import lsq_linear
from scipy.sparse.linalg import splu
from scipy.spatial import cKDTree
from skfem.models.elasticity import linear_elasticity
from skfem.models.poisson import laplace

TOLERANCE = 1e-10       # the KKT residual per row at which a level is solved (the harness's own)
CROSSCHECK = 1e-6       # PDAS against BVLS on the coarsest level, relative to max |u|
MATCH = 1e-9            # node matching, relative to the domain's size (the format's tolerance)
MAX_ITERATIONS = 200
ELEMENTS = {(2, 1): skfem.ElementTriP1, (2, 2): skfem.ElementTriP2,
            (3, 1): skfem.ElementTetP1, (3, 2): skfem.ElementTetP2}
MESHES = {2: skfem.MeshTri, 3: skfem.MeshTet}


@dataclass
class Problem:
    """K u = b on the free dofs, u = u_fixed on the Dirichlet dofs, sign * u[rows] >= bound."""

    K: sp.csr_matrix
    b: np.ndarray
    dirichlet: np.ndarray   # bool per dof
    u_fixed: np.ndarray     # the Dirichlet values (0 off the Dirichlet dofs)
    rows: np.ndarray        # the constrained dofs (none of them Dirichlet)
    sign: np.ndarray        # +1: u >= bound; -1: -u >= bound (an outward normal +e_k)
    bound: np.ndarray


def basis_of(data, manifest) -> skfem.Basis:
    """scikit-fem's P_k basis on the exported mesh (vector-valued for elasticity)."""
    dim = manifest["case"]["dimension"]
    mesh = MESHES[dim](np.ascontiguousarray(data["vertices"].T), np.ascontiguousarray(data["cells"].T))
    element = ELEMENTS[(dim, manifest["order"])]()
    if manifest["case"]["physics"] == "elasticity":
        element = skfem.ElementVector(element, dim)
    return skfem.Basis(mesh, element)


def dof_layout(basis, components: int) -> tuple[np.ndarray, np.ndarray]:
    """(locations (n, d), index (n, c)): dof index[i, j] is component j at location i. scikit-fem's
    P2 dofs are its vertices, then its edges' midpoints in its own edge order, components
    interleaved: read from the basis, never assumed."""
    if components == 1:
        return basis.doflocs.T, np.arange(basis.N)[:, None]
    index = np.column_stack(basis.split_indices())
    locations = basis.doflocs[:, index[:, 0]].T
    for j in range(1, components):      # the components of one node share its location
        assert np.allclose(basis.doflocs[:, index[:, j]].T, locations, rtol=0, atol=1e-14)
    return locations, index


def match_nodes(locations: np.ndarray, nodes: np.ndarray) -> np.ndarray:
    """``node`` with nodes[node[i]] at locations[i], one to one, within the format's tolerance."""
    size = np.ptp(nodes, axis=0).max()
    distance, node = cKDTree(nodes).query(locations)
    if len(locations) != len(nodes) or distance.max() > MATCH * size or len(np.unique(node)) != len(nodes):
        raise SystemExit(f"skfem_contact: {len(locations)} scikit-fem dofs match {len(np.unique(node))} of the "
                         f"{len(nodes)} exported nodes (largest distance {distance.max():.2e})")
    return node


def stiffness(basis, manifest) -> sp.csr_matrix:
    """The bilinear form: the Laplacian, or linear elasticity with the exported Lame constants (in 2D
    plane strain: the harness's 2D elasticity is plane strain, format section "case")."""
    case = manifest["case"]
    if case["physics"] == "elasticity":
        return linear_elasticity(case["lame_lambda"], case["lame_mu"]).assemble(basis).tocsr()
    return laplace.assemble(basis).tocsr()


def per_dof(values: np.ndarray, node: np.ndarray, index: np.ndarray, n_dofs: int) -> np.ndarray:
    """Node-wise exported values (n, c) as a vector over scikit-fem's dofs."""
    out = np.zeros(n_dofs)
    out[index] = np.asarray(values).reshape(len(node), -1)[node]
    return out


def constraints(data, node, index, physics: str):
    """(rows, sign, bound) of the nodal cone at the contact nodes off Gamma_u: u >= gap (scalar);
    u . n <= gap (elasticity), i.e. -n_k u_k >= -gap for an outward normal n = +-e_k (only
    axis-aligned normals are a bound; another would be a general row)."""
    contact = data["on_contact"][node] & ~data["on_dirichlet"][node]
    where = np.flatnonzero(contact)
    gap = data["gap"][node][where]
    if physics != "elasticity":
        return index[where, 0], np.ones(len(where)), gap
    normal = data["normal"][node][where]
    axis = np.argmax(np.abs(normal), axis=1)
    along = normal[np.arange(len(where)), axis]
    if np.any(np.abs(np.abs(along) - 1) > 1e-12):
        raise SystemExit("skfem_contact: a contact normal not along an axis needs general constraint rows")
    return index[where, axis], -np.sign(along), -gap


def discrete_problem(data, basis, manifest, node, index) -> Problem:
    """The harness's discrete problem on scikit-fem's dofs: its stiffness, the exported load
    moments (the rows of Dirichlet dofs ignored, as the format says), the exported discrete
    Dirichlet values, the nodal cone."""
    K = stiffness(basis, manifest)
    b = per_dof(data["load"], node, index, basis.N)
    dirichlet = np.zeros(basis.N, bool)
    dirichlet[index[data["on_dirichlet"][node]].ravel()] = True
    u_fixed = np.where(dirichlet, per_dof(data["u_dirichlet"], node, index, basis.N), 0.0)
    rows, sign, bound = constraints(data, node, index, manifest["case"]["physics"])
    return Problem(K, b, dirichlet, u_fixed, rows, sign, bound)


def solve_set(problem: Problem, active: np.ndarray) -> np.ndarray:
    """u of the equality-constrained problem of ``active``: the active rows held at their bound,
    the Dirichlet dofs at their values, K u = b on the rest (a sparse LU of that block)."""
    u = problem.u_fixed.copy()
    held = problem.rows[active]
    u[held] = problem.sign[active] * problem.bound[active]      # sign is +-1: sign u = bound
    fixed = problem.dirichlet.copy()
    fixed[held] = True
    free = np.flatnonzero(~fixed)
    K_free = problem.K[free][:, free].tocsc()
    # K_free is symmetric positive definite: diagonal pivots are stable (as in Cholesky), so
    # SuperLU's symmetric mode with a minimum degree ordering of K + K^T (half the fill of COLAMD)
    lu = splu(K_free, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True})
    u[free] = lu.solve(problem.b[free] - problem.K[free] @ u)
    return u


def kkt(problem: Problem, u: np.ndarray, active: np.ndarray) -> tuple[float, np.ndarray]:
    """(the relative KKT residual, the multipliers). lambda = sign (K u - b) on the constrained rows;
    stationarity on free rows off the active set, dual feasibility lambda >= 0 on it, primal
    feasibility sign u >= bound, complementarity lambda (sign u - bound) = 0 -- each per row, the
    forces against the largest load of the reduced problem, the values against the largest of
    u and the obstacle on Gamma_C (the scaling of harness.solvers.pdas.KKT)."""
    force = problem.K @ u - problem.b
    free = ~problem.dirichlet
    load = np.abs(problem.b - problem.K @ problem.u_fixed)[free].max(initial=0.0) or 1.0
    value = max(np.abs(u[problem.rows]).max(initial=0.0), np.abs(problem.bound).max(initial=0.0)) or 1.0
    lam = problem.sign * force[problem.rows]
    slack = problem.sign * u[problem.rows] - problem.bound
    off = free.copy()
    off[problem.rows[active]] = False
    stationarity = np.abs(force[off]).max(initial=0.0) / load
    dual = np.maximum(-lam[active], 0).max(initial=0.0) / load
    primal = np.maximum(-slack, 0).max(initial=0.0) / value
    complementarity = np.abs(lam * slack).max(initial=0.0) / (load * value)
    return max(stationarity, dual, primal, complementarity), lam


def next_set(problem, u, lam, active, seen) -> np.ndarray:
    """The primal-dual update: active where lambda + c (bound - sign u) > 0 with c = diag K on the
    row (a force per length, so the two terms compare; HIK 2003 allow any c > 0). Once a set
    would come back (the P2 stiffness is no M-matrix, so HIK's monotone convergence is not
    guaranteed), Murty's least-index rule: flip only the first row that violates its sign."""
    c = problem.K.diagonal()[problem.rows]
    slack = problem.sign * u[problem.rows] - problem.bound
    proposed = lam - c * slack > 0
    if proposed.tobytes() not in seen or np.array_equal(proposed, active):
        return proposed
    violated = np.flatnonzero((active & (lam < 0)) | (~active & (slack < 0)))
    flipped = active.copy()
    flipped[violated[:1]] = ~flipped[violated[:1]]
    return flipped


def active_set(problem: Problem) -> tuple[np.ndarray, int, float]:
    """(u, iterations, KKT residual) by the primal-dual active set method, from the empty set; it
    stops when the set repeats and the KKT residual is <= TOLERANCE (a repeated set alone is no
    solution when the linear solves are inexact)."""
    active = np.zeros(len(problem.rows), bool)
    seen = set()
    for iteration in range(1, MAX_ITERATIONS + 1):
        seen.add(active.tobytes())
        u = solve_set(problem, active)
        residual, lam = kkt(problem, u, active)
        proposed = next_set(problem, u, lam, active, seen)
        if np.array_equal(proposed, active) and residual <= TOLERANCE:
            return u, iteration, residual
        if np.array_equal(proposed, active):
            raise SystemExit(f"skfem_contact: the active set is stationary but the KKT residual is {residual:.2e}")
        active = proposed
    raise SystemExit(f"skfem_contact: no convergence in {MAX_ITERATIONS} active-set iterations")


def bvls(problem: Problem) -> np.ndarray:
    """The same QP by bounded-variable least squares (independent of the active set code): with
    K_FF = L L^T, 1/2 u^T K_FF u - r^T u = 1/2 |L^T u - L^-1 r|^2 + const, dense, for a coarse level."""
    free = np.flatnonzero(~problem.dirichlet)
    K = problem.K[free][:, free].toarray()
    r = (problem.b - problem.K @ problem.u_fixed)[free]
    L = np.linalg.cholesky(K)
    lower, upper = np.full(len(free), -np.inf), np.full(len(free), np.inf)
    position = np.searchsorted(free, problem.rows)
    lower[position] = np.where(problem.sign > 0, problem.bound, -np.inf)
    upper[position] = np.where(problem.sign < 0, -problem.bound, np.inf)
    fit = lsq_linear(L.T, np.linalg.solve(L, r), bounds=(lower, upper), method="bvls", tol=1e-15)
    u = problem.u_fixed.copy()
    u[free] = fit.x
    return u


def cross_check(problem: Problem, u: np.ndarray) -> float:
    """max |u_PDAS - u_BVLS| / max |u|; refused above CROSSCHECK."""
    difference = np.abs(u - bvls(problem)).max() / np.abs(u).max()
    if difference > CROSSCHECK:
        raise SystemExit(f"skfem_contact: the active set solution and BVLS differ by {difference:.2e} (relative)")
    return difference


def solve_level(export: Path, entry: dict, manifest: dict) -> dict:
    """One level: read, assemble, solve; the solution's arrays and figures. ``seconds`` is
    scikit-fem's assembly (basis, stiffness, load) plus the contact solve; reading the file and
    matching the nodes (interoperability, not the code's work) are left out."""
    data = np.load(export / entry["file"])
    start = time.perf_counter()
    basis = basis_of(data, manifest)
    locations, index = dof_layout(basis, manifest["components"])
    matching = time.perf_counter()
    node = match_nodes(locations, data["nodes"])
    matched = time.perf_counter()
    problem = discrete_problem(data, basis, manifest, node, index)
    assembled = time.perf_counter()
    u, iterations, residual = active_set(problem)
    assembly = (matching - start) + (assembled - matched)
    return dict(points=locations, values=u[index], seconds=assembly + time.perf_counter() - assembled, assembly=assembly,
                iterations=iterations, residual=residual, problem=problem, u=u)


def write_manifest(out: Path, manifest: dict, checked: float | None) -> None:
    """OUT_DIR/manifest.json (the solution format v1)."""
    solution = {"format": "signorini-harness-solution", "format_version": 1,
                "code": f"scikit-fem {skfem.__version__} + SciPy {scipy.__version__} (SuperLU), primal-dual active set",
                "method": "skfem-nodal", "like": "nodal", "case": manifest["case"]["name"], "order": manifest["order"],
                "options": {"model": "nodal cone at the P_k nodes of Gamma_C",
                            "solver": "primal-dual active set (HIK 2003), c = diag K, Murty's rule on a repeated set",
                            "tolerance": TOLERANCE, "coarsest_level_vs_bvls": checked}}
    (out / "manifest.json").write_text(json.dumps(solution, indent=2) + "\n")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("export", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--levels", type=int, default=None, help="the first N levels of the export (default: all)")
    args = parser.parse_args(argv)
    manifest = json.loads((args.export / "manifest.json").read_text())
    if manifest["case"].get("friction"):
        raise SystemExit("skfem_contact: friction is not modelled here (the nodal model is frictionless)")
    args.out.mkdir(parents=True, exist_ok=True)
    checked = None
    for entry in manifest["levels"][:args.levels]:
        level = solve_level(args.export, entry, manifest)
        if checked is None:     # the coarsest level: against an independent solver
            checked = cross_check(level["problem"], level["u"])
        np.savez(args.out / f"level-{entry['level']}.npz", points=level["points"], values=level["values"],
                 seconds=level["seconds"], iterations=level["iterations"], residual=level["residual"])
        print(f"skfem-nodal {manifest['case']['name']} level {entry['level']}: {len(level['u'])} dofs, "
              f"{level['iterations']} active-set iterations, KKT {level['residual']:.1e}, {level['seconds']:.2f} s "
              f"({level['assembly']:.2f} s assembly)",
              flush=True)
    write_manifest(args.out, manifest, checked)
    print(f"skfem-nodal: coarsest level against BVLS {checked:.1e} (relative); wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
