"""DOLFINx + PETSc on the harness's exported contact problems: an external code, run in its own
environment (``make .venv-dolfinx/.installed``), reading an export folder (``python -m harness
export``) and writing a solution folder that ``external:DIR`` imports (docs: the exchange format).

    .venv-dolfinx/bin/python examples/codes/dolfinx_contact.py EXPORT_DIR OUT_DIR --model nodal|nitsche
        [--theta 1] [--gamma0 G] [--levels N] [--options default|best] [--nested] [--threads 1]
        [--petsc KEY=VALUE ...]

Per level: the DOLFINx mesh from the exported vertices and cells (serial, MPI.COMM_SELF), P_k
Lagrange (k from the manifest; vector-valued for elasticity, plane strain in 2D), the bilinear form
a (Laplace, or linear elasticity with the manifest's Lame constants), u = u_dirichlet at the
Dirichlet nodes, and as right-hand side the exported ``load`` moments L(phi_i e_j), put at the dofs
that sit at the same Lagrange nodes (DOLFINx's P2 dofs are the vertices and edge midpoints). So the
discrete problem is the harness's own, and the two solutions agree to the solvers' tolerance.

``nodal``: the model 2 of Belhachmi & Ben Belgacem, Math. Comp. 72 (2003) (the harness's ``nodal``):
the constraint at Gamma_C's P_k nodes only, u >= gap (scalar) or u . n <= gap (elasticity, flat
Gamma_C with n = +-e_i: a bound on that component). The problem is the QP min 1/2 u'Ku - b'u on a
box, solved by PETSc's SNES VI (``vinewtonrsls``, a reduced-space active-set Newton method) on
F(u) = K u - b, Jacobian K.

``nitsche``: Nitsche's law in UFL, the theta family of Chouly & Hild, SIAM J. Numer. Anal. 51 (2013)
(theta = 1) and Chouly, Hild & Renard, Math. Comp. 84 (2015), eq. (10), written on the contact
variable c(v) = v (scalar) or -v . n (elasticity) and its flux d_n v or -sigma_n(v):

    a(u, v) - theta int_C eps (flux(u) - g) flux(v) + int_C (1/eps) [P(u)]_+ P_theta(v) = L(v),
    P(u) = eps (flux(u) - g) + alpha - c(u),   P_theta(v) = theta eps flux(v) - c(v),

eps = gamma0 h / M (M = 1, or lambda + 2 mu), h = the contact facet's length in 2D (ufl.FacetArea),
its longest edge in 3D (ufl.MaxFacetEdgeLength), the contact integrals with the harness's rule
(4 Gauss points per edge in 2D, quadrature degree 7), solved by SNES ``newtonls``. The obstacle
alpha (gap, or -gap) and the normal contact load g inside the bracket: in 2D the export's values
at those Gauss points (q_obstacle, q_load), held exactly there by a discontinuous P3 field; in 3D
the node samples interpolated into P_k, exact when the data are zero or polynomials of degree
<= k (otherwise the bracket differs from the harness's by the interpolation error, and the
driver warns), with basix's degree-7 rule on the triangle, whose points need not be NGSolve's.

Options (``--options``): ``default`` is what DOLFINx users write, CG + GAMG (rtol 1e-12) inside
each Newton step, from zero; ``best`` the fastest found: the same CG + GAMG, started from the coarser
level's solution (nested iteration, ``--nested``; as the harness's study solves), evaluated exactly
in each fine dof's parent cell (the levels are uniform red refinements). Both stop at the same
residual: 1e-12 times the zero start's. Tried on transition-r32 (P2, one thread) and slower than
``best`` from the same start: MUMPS's LU and Cholesky, PETSc's own LU and Cholesky, SuperLU_dist,
GAMG with other thresholds or without smoothed aggregation (hypre is not in the PETSc wheel; from
a nested start one Newton step suffices, so Eisenstat-Walker has nothing to loosen). The figures:
`python -m harness bench --only codes` (the performance page) for ``default`` and ``best``.
``--petsc KEY=VALUE`` adds PETSc options (without the model's prefix).

Timing (``seconds``): the nested start (when used), the assembly of the problem and the solve, not reading the mesh nor the forms'
just-in-time compilation (cached after the first run). One thread (``--threads``).
"""
import os
import sys

# BLAS and OpenMP read these once, when loaded: set them before numpy and PETSc are imported
_THREADS = sys.argv[sys.argv.index("--threads") + 1] if "--threads" in sys.argv else "1"
for _name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_name] = _THREADS

# mpi4py first: it loads the mpich wheel's libmpi, which the DOLFINx wheel's libraries link to
from mpi4py import MPI  # noqa: E402

COMM = MPI.COMM_SELF

import argparse  # noqa: E402
import json  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import basix  # noqa: E402
import basix.ufl  # noqa: E402
import dolfinx  # noqa: E402
import dolfinx.fem.petsc  # noqa: E402
import numpy as np  # noqa: E402
import ufl  # noqa: E402
from petsc4py import PETSc  # noqa: E402

CONTACT = 1  # the export's facet label of Gamma_C

# the linear solver inside each Newton step, and the start: `default` as DOLFINx users write it
# (CG + algebraic multigrid, from zero), `best` the fastest found (the module's docstring: the same
# CG + GAMG from the coarser level's solution, nested iteration as the harness's study solves)
GAMG = {"ksp_type": "cg", "pc_type": "gamg", "ksp_rtol": 1e-12, "ksp_atol": 1e-50, "ksp_max_it": 2000}
LINEAR = {"default": GAMG, "best": GAMG}
NESTED = {"default": False, "best": True}
# Newton: converged when the residual has dropped 1e-12 or reached ~ machine precision of b
NEWTON = {"snes_rtol": 1e-12, "snes_stol": 0.0, "snes_max_it": 100}


def read_level(folder: Path, entry: dict) -> dict:
    with np.load(folder / entry["file"]) as data:
        return {key: data[key] for key in data.files}


def build_mesh(data: dict):
    """The DOLFINx mesh of the exported vertices and cells, and each geometry node's export vertex."""
    x = np.ascontiguousarray(data["vertices"], dtype=np.float64)
    dim = x.shape[1]
    cell = "triangle" if dim == 2 else "tetrahedron"
    domain = ufl.Mesh(basix.ufl.element("Lagrange", cell, 1, shape=(dim,)))
    mesh = dolfinx.mesh.create_mesh(COMM, data["cells"].astype(np.int64), domain, x)
    return mesh


def facet_tags(mesh, data: dict):
    """Tag the DOLFINx facets that carry the export's contact label, matched by vertex sets."""
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim - 1, 0)
    mesh.topology.create_connectivity(tdim - 1, tdim)
    mesh.topology.create_connectivity(0, tdim)
    boundary = dolfinx.mesh.exterior_facet_indices(mesh.topology)
    # topology vertex -> export vertex (P1 geometry: one geometry node per vertex)
    vertex_nodes = dolfinx.mesh.entities_to_geometry(mesh, 0, np.arange(mesh.topology.index_map(0).size_local, dtype=np.int32))
    original = np.asarray(mesh.geometry.input_global_indices)[vertex_nodes[:, 0]]
    f2v = mesh.topology.connectivity(tdim - 1, 0).array.reshape(-1, tdim)
    ours = np.sort(original[f2v[boundary]], axis=1)
    contact = {tuple(f) for f in np.sort(data["facets"][data["facet_labels"] == CONTACT], axis=1)}
    tagged = np.array([tuple(f) in contact for f in ours], dtype=bool)
    if tagged.sum() != len(contact):
        sys.exit(f"dolfinx_contact: {tagged.sum()} of the {len(contact)} contact facets found in the mesh")
    facets = boundary[tagged].astype(np.int32)
    return dolfinx.mesh.meshtags(mesh, tdim - 1, facets, np.full(len(facets), CONTACT, dtype=np.int32))


def match_nodes(points: np.ndarray, targets: np.ndarray, tol: float) -> np.ndarray:
    """For each point, the index of the target at the same position (within tol): both rounded on
    one grid (``same_points``, vectorised), then every pair's distance checked."""
    index = same_points(points, targets)
    if index is None or np.max(np.linalg.norm(targets[index] - points, axis=1)) > tol or len(np.unique(index)) != len(points):
        sys.exit("dolfinx_contact: the export's nodes are not DOLFINx's dofs (P_k node positions differ)")
    return index


class Level:
    """One exported level on DOLFINx: the space, each dof block's export node, the Dirichlet
    condition, the load vector and the contact facets."""

    def __init__(self, manifest: dict, data: dict):
        self.case, self.data = manifest["case"], data
        self.elastic = self.case["physics"] == "elasticity"
        self.mesh = build_mesh(data)
        self.tags = facet_tags(self.mesh, data)
        shape = (manifest["components"],) if self.elastic else ()
        self.V = dolfinx.fem.functionspace(self.mesh, ("Lagrange", manifest["order"], shape))
        dim = self.mesh.geometry.dim
        self.points = self.V.tabulate_dof_coordinates()[:, :dim]
        if len(self.points) != len(data["nodes"]):
            sys.exit(f"dolfinx_contact: {len(self.points)} dof nodes, the export has {len(data['nodes'])}")
        size = np.ptp(data["vertices"], axis=0).max()
        self.node = match_nodes(self.points, data["nodes"], 1e-9 * size)
        dofs = np.flatnonzero(data["on_dirichlet"][self.node]).astype(np.int32)
        self.bc = dolfinx.fem.dirichletbc(self.field(data["u_dirichlet"]), dofs)

    def field(self, values: np.ndarray) -> dolfinx.fem.Function:
        """The P_k function whose value at each export node is values[node] (NaN read as 0)."""
        f = dolfinx.fem.Function(self.V)
        f.x.array[:] = np.nan_to_num(np.asarray(values, float)[self.node]).ravel()
        return f

    def load(self) -> PETSc.Vec:
        """The exported moments L(phi_i e_j) at dof (block i, component j): DOLFINx's layout."""
        b = dolfinx.fem.petsc.create_vector(self.V)
        b.array[:] = self.data["load"][self.node].ravel()
        return b

    def bilinear(self, u, v):
        """a(u, v): Laplace, or linear elasticity sigma = 2 mu eps + lambda tr(eps) I (plane strain)."""
        if not self.elastic:
            return ufl.inner(ufl.grad(u), ufl.grad(v)) * ufl.dx
        return ufl.inner(self.sigma(u), ufl.sym(ufl.grad(v))) * ufl.dx

    def sigma(self, u):
        lam, mu = self.case["lame_lambda"], self.case["lame_mu"]
        e = ufl.sym(ufl.grad(u))
        return 2 * mu * e + lam * ufl.tr(e) * ufl.Identity(len(u))

    def initial(self, coarse=None) -> PETSc.Vec:
        """A start that satisfies the Dirichlet condition (Newton's updates keep it: J's rows there are
        I): zero, or (nested iteration) the coarser level's solution ``coarse``, a P_k function on a
        mesh this one refines uniformly, so its interpolant here is itself."""
        x = dolfinx.fem.petsc.create_vector(self.V)
        if coarse is None:
            x.set(0.0)
        else:
            x.array[:] = prolong(coarse, self.V).ravel()
        dolfinx.fem.petsc.set_bc(x, [self.bc])
        return x


def prolong(coarse: dolfinx.fem.Function, V) -> np.ndarray:
    """The coarse P_k function at V's dofs, V on a uniform red refinement of the coarse mesh: each
    fine dof evaluated in its parent cell (``parents``) by ``Function.eval``, no point search; in 3D
    (or a mesh that is not such a refinement) by DOLFINx's non-matching interpolation."""
    mesh = V.mesh
    cells = np.arange(mesh.topology.index_map(mesh.topology.dim).size_local, dtype=np.int32)
    parent = parents(coarse.function_space, mesh) if mesh.geometry.dim == 2 else None
    if parent is None:
        fine = dolfinx.fem.Function(V)
        fine.interpolate_nonmatching(coarse, cells, dolfinx.fem.create_interpolation_data(V, coarse.function_space, cells))
        return fine.x.array
    dof_parent = np.empty(V.dofmap.index_map.size_local, dtype=np.int32)
    dof_parent[V.dofmap.list] = parent[:, None]                 # any cell holding the dof: all lie in one parent
    return coarse.eval(V.tabulate_dof_coordinates(), dof_parent)


def parents(coarse_V, mesh) -> np.ndarray | None:
    """Each fine cell's coarse cell (2D, red refinement): the fine vertices are the coarse P2 nodes,
    at least two of a fine cell's are midpoints of its parent's edges, and two edges' midpoints
    belong to one triangle only. None when the meshes are not so related (or coarse_V is not P2)."""
    if coarse_V.element.space_dimension // coarse_V.dofmap.index_map_bs != 6:
        return None
    dofs = coarse_V.dofmap.list                                 # (nc, 6): vertices, then edge midpoints
    vertex_of = dolfinx.mesh.entities_to_geometry(mesh, 2, np.arange(mesh.topology.index_map(2).size_local, dtype=np.int32))
    node = same_points(mesh.geometry.x[:, :2], coarse_V.tabulate_dof_coordinates()[:, :2])
    if node is None:
        return None
    fine = node[vertex_of]                                      # (nf, 3) coarse dofs
    midpoint = np.zeros(coarse_V.dofmap.index_map.size_local, dtype=bool)
    midpoint[dofs[:, 3:]] = True
    first_two = np.take_along_axis(fine, np.argsort(~midpoint[fine], axis=1, kind="stable")[:, :2], axis=1)
    if not midpoint[first_two].all():
        return None
    n = np.int64(len(midpoint))
    pairs = dofs[:, [3, 3, 4]], dofs[:, [4, 5, 5]]                # the three pairs of edge midpoints
    keys = np.minimum(*pairs).astype(np.int64) * n + np.maximum(*pairs)
    order = np.argsort(keys.ravel())
    wanted = np.min(first_two, axis=1).astype(np.int64) * n + np.max(first_two, axis=1)
    at = np.minimum(np.searchsorted(keys.ravel()[order], wanted), keys.size - 1)
    if not np.array_equal(keys.ravel()[order][at], wanted):
        return None
    return (order[at] // 3).astype(np.int32)


def same_points(points: np.ndarray, targets: np.ndarray) -> np.ndarray | None:
    """For each point, the index of the target at its position (on a grid of 1e-7 of the domain,
    shifted by 1/pi of a step: the nodes' dyadic coordinates would sit on the rounding's ties), or None."""
    size = np.ptp(targets, axis=0).max()
    keys = np.round(np.vstack([points, targets]) / (1e-7 * size) + 1 / np.pi).astype(np.int64)
    _, group = np.unique(keys, axis=0, return_inverse=True)
    group = group.ravel()
    target_of = np.full(group.max() + 1, -1)
    target_of[group[len(points):]] = np.arange(len(targets))
    index = target_of[group[:len(points)]]
    return None if (index < 0).any() else index


def node_bounds(level: Level) -> tuple[PETSc.Vec, PETSc.Vec]:
    """SNES VI's box of the nodal model at Gamma_C's P_k nodes: u >= gap (scalar); u . n <= gap with
    n = s e_i (elasticity): s u_i <= gap. Unbounded elsewhere, and at Dirichlet nodes (u is given)."""
    data, bs = level.data, level.V.dofmap.index_map_bs
    lower = np.full((len(level.node), bs), PETSc.NINFINITY)
    upper = np.full((len(level.node), bs), PETSc.INFINITY)
    nodes = np.flatnonzero(data["on_contact"][level.node] & ~data["on_dirichlet"][level.node])
    gap = data["gap"][level.node[nodes]]
    if not level.elastic:
        lower[nodes, 0] = gap
    else:
        normal = data["normal"][level.node[nodes]]
        axis = np.argmax(np.abs(normal), axis=1)
        sign = np.sign(normal[np.arange(len(nodes)), axis])
        if np.max(np.abs(normal - sign[:, None] * np.eye(bs)[axis])) > 1e-12:
            sys.exit("dolfinx_contact: --model nodal needs a flat Gamma_C with normal +-e_i (a bound per component)")
        upper[nodes[sign > 0], axis[sign > 0]] = gap[sign > 0]
        lower[nodes[sign < 0], axis[sign < 0]] = -gap[sign < 0]
    return tuple(PETSc.Vec().createWithArray(np.ascontiguousarray(b.ravel()), comm=COMM) for b in (lower, upper))


def first_iterate(snes: PETSc.SNES, level: Level, coarse) -> PETSc.Vec:
    """The start: zero, or the coarser level's solution with the same stopping test as from zero
    (the residual 1e-12 times the zero start's, an absolute tolerance: relative to a start that is
    already close, 1e-12 would be below the round-off of F)."""
    if coarse is None:
        return level.initial()
    zero, F = level.initial(), level.load()
    snes.computeFunction(zero, F)
    snes.setTolerances(atol=NEWTON["snes_rtol"] * F.norm())
    return level.initial(coarse)


def make_snes(kind: str, options: dict, prefix: str) -> PETSc.SNES:
    table = PETSc.Options()
    for key, value in options.items():
        table[prefix + key] = value
    snes = PETSc.SNES().create(COMM)
    snes.setOptionsPrefix(prefix)
    snes.setType(kind)
    return snes


def solve_nodal(level: Level, options: dict, start_from=None) -> tuple[PETSc.SNES, PETSc.Vec]:
    """Belhachmi & Ben Belgacem's model 2: the QP F(u) = K u - b = 0 on the box, K with the Dirichlet
    rows and columns of DOLFINx (identity), b the load lifted by u_dirichlet (b = u_D at those rows)."""
    a = dolfinx.fem.form(level.bilinear(ufl.TrialFunction(level.V), ufl.TestFunction(level.V)))
    start = time.perf_counter()
    K = dolfinx.fem.petsc.assemble_matrix(a, bcs=[level.bc])
    K.assemble()
    b = level.load()
    dolfinx.fem.petsc.apply_lifting(b, [a], bcs=[[level.bc]])
    dolfinx.fem.petsc.set_bc(b, [level.bc])
    snes = make_snes("vinewtonrsls", options, "nodal_")

    def residual(snes, x, F):
        K.mult(x, F)
        F.axpy(-1.0, b)
    snes.setFunction(residual, b.duplicate())
    snes.setJacobian(lambda *args: None, K)  # J = K, assembled once
    snes.setVariableBounds(*node_bounds(level))
    snes.setFromOptions()
    x = first_iterate(snes, level, start_from)
    snes.solve(None, x)
    return snes, x, time.perf_counter() - start


def contact_data(level: Level):
    """(alpha, g): the obstacle and the normal contact load of the contact variable in the bracket.
    2D: the harness's own values at its Gauss points (q_obstacle, q_load), held exactly there by a
    discontinuous P3 field (``gauss_field``). 3D: the node samples interpolated into P_k (scalar:
    alpha = gap, g = g_C; elasticity: alpha = -gap, g = -g_C . n), exact for P_k data only."""
    if level.mesh.geometry.dim == 2:
        return gauss_field(level, level.data["q_obstacle"]), gauss_field(level, level.data["q_load"])
    check_contact_data(level)
    gap = level.data["gap"]
    if not level.elastic:
        return level.field(gap), level.field(level.data["contact_load"][:, 0])
    n = ufl.FacetNormal(level.mesh)
    gap_h = dolfinx.fem.Function(level.V.sub(0).collapse()[0])
    gap_h.x.array[:] = np.nan_to_num(gap[level.node])
    return -gap_h, -ufl.dot(level.field(level.data["contact_load"]), n)


def gauss_field(level: Level, values: np.ndarray) -> dolfinx.fem.Function:
    """A DG P3 function equal to ``values`` at the harness's 4 Gauss points of each contact edge: on
    an edge its trace is the cubic through them, which the degree-7 rule (the same 4 points) samples
    exactly. So data that are not polynomials (corner-r12's g_C jumps and is singular) enter the
    bracket as the harness's do."""
    mesh, tdim = level.mesh, level.mesh.topology.dim
    W = dolfinx.fem.functionspace(mesh, ("DG", 3))
    facets = level.tags.find(CONTACT)
    ends = mesh.geometry.x[dolfinx.mesh.entities_to_geometry(mesh, tdim - 1, facets)][:, :, :2]     # (F, 2, 2)
    q = level.data["q_points"].reshape(-1, 4, 2)                     # the harness's points, edge by edge
    size = np.ptp(level.data["vertices"], axis=0).max()
    block = match_nodes(ends.mean(axis=1), q.mean(axis=1), 1e-9 * size)   # symmetric rule: mean = midpoint
    cells = mesh.topology.connectivity(tdim - 1, tdim).array[mesh.topology.connectivity(tdim - 1, tdim).offsets[facets]]
    dofs = W.dofmap.list[cells]                                       # (F, 10)
    x = W.tabulate_dof_coordinates()[dofs][:, :, :2]
    A, t = ends[:, :1], ends[:, 1:] - ends[:, :1]                     # edge A + s t, s in [0, 1]
    along = np.einsum("fkd,fd->fk", x - A, t[:, 0]) / np.sum(t[:, 0] ** 2, axis=1)[:, None]
    off = np.abs((x - A)[:, :, 0] * t[:, :, 1] - (x - A)[:, :, 1] * t[:, :, 0])   # distance * |t| from the edge's line
    on = np.argsort(off, axis=1)[:, :4]                               # the 4 dofs of P3 on the edge
    s_q = np.einsum("fkd,fd->fk", q[block] - A, t[:, 0]) / np.sum(t[:, 0] ** 2, axis=1)[:, None]
    coef = np.linalg.solve(np.vander(s_q.ravel(), 4).reshape(-1, 4, 4), values.reshape(-1, 4)[block][:, :, None])
    s_dof = np.take_along_axis(along, on, axis=1)
    field, targets = dolfinx.fem.Function(W), np.take_along_axis(dofs, on, axis=1)
    if len(np.unique(targets)) != targets.size:
        warnings.warn("dolfinx_contact: a cell with two contact edges: their cubics share a vertex dof", stacklevel=2)
    field.x.array[targets] = (np.vander(s_dof.ravel(), 4).reshape(-1, 4, 4) @ coef)[:, :, 0]
    return field


def nitsche_form(level: Level, u, v, gamma0: float, theta: float):
    """F(u; v) of Chouly, Hild & Renard 2015, eq. (10) (Chouly & Hild 2013 for the scalar problem),
    without L: a(u, v) - theta int_C eps (flux(u) - g) flux(v) + int_C (1/eps) [P(u)]_+ P_theta(v)."""
    mesh, dim = level.mesh, level.mesh.geometry.dim
    n = ufl.FacetNormal(mesh)
    h = ufl.FacetArea(mesh) if dim == 2 else ufl.MaxFacetEdgeLength(mesh)
    modulus = level.case["lame_lambda"] + 2 * level.case["lame_mu"] if level.elastic else 1.0
    eps = gamma0 * h / modulus
    if level.elastic:
        def c(w): return -ufl.dot(w, n)
        def flux(w): return -ufl.dot(n, ufl.dot(level.sigma(w), n))
    else:
        def c(w): return w
        def flux(w): return ufl.dot(ufl.grad(w), n)
    alpha, g = contact_data(level)
    P = eps * (flux(u) - g) + alpha - c(u)
    positive = ufl.conditional(ufl.gt(P, 0), P, 0)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=level.tags,
                     metadata={"quadrature_degree": contact_degree(level)})
    return (level.bilinear(u, v) - theta * eps * (flux(u) - g) * flux(v) * ds(CONTACT)
            + (1 / eps) * positive * (theta * eps * flux(v) - c(v)) * ds(CONTACT))


def contact_degree(level: Level) -> int:
    """The quadrature degree whose Gauss rule on a facet has the harness's number of points per contact
    facet (2D: 4 Gauss-Legendre points, degree 7; 3D: basix's default rule of that size, whose points
    may differ from the harness's)."""
    facets = int(np.sum(level.data["facet_labels"] == CONTACT))
    per_facet = len(level.data["q_weights"]) // facets
    shape = basix.CellType.interval if level.mesh.geometry.dim == 2 else basix.CellType.triangle
    for degree in range(1, 30):
        if len(basix.make_quadrature(shape, degree)[1]) == per_facet:
            return degree
    sys.exit(f"dolfinx_contact: no basix rule with {per_facet} points per facet")


def solve_nitsche(level: Level, options: dict, gamma0: float, theta: float, start_from=None):
    """Nitsche's law by SNES newtonls: F(u) = F(u; .) - b off the Dirichlet rows, u - u_D on them."""
    u, v = dolfinx.fem.Function(level.V), ufl.TestFunction(level.V)
    F_ufl = nitsche_form(level, u, v, gamma0, theta)
    F_form = dolfinx.fem.form(F_ufl)
    J_form = dolfinx.fem.form(ufl.derivative(F_ufl, u, ufl.TrialFunction(level.V)))
    start = time.perf_counter()
    b = level.load()
    J = dolfinx.fem.petsc.create_matrix(J_form)
    snes = make_snes("newtonls", options, "nitsche_")

    def residual(snes, x, F):
        x.copy(u.x.petsc_vec)
        with F.localForm() as local:
            local.set(0.0)
        dolfinx.fem.petsc.assemble_vector(F, F_form)
        F.axpy(-1.0, b)
        dolfinx.fem.petsc.set_bc(F, [level.bc], x, -1.0)  # F = x - u_D at the Dirichlet rows

    def jacobian(snes, x, J, P):
        x.copy(u.x.petsc_vec)
        J.zeroEntries()
        dolfinx.fem.petsc.assemble_matrix(J, J_form, bcs=[level.bc])
        J.assemble()
    snes.setFunction(residual, b.duplicate())
    snes.setJacobian(jacobian, J)
    snes.setFromOptions()
    x = first_iterate(snes, level, start_from)
    snes.solve(None, x)
    return snes, x, time.perf_counter() - start


def check_contact_data(level: Level) -> None:
    """Warn when the interpolated obstacle differs from the harness's at its contact points: the
    bracket of the Nitsche law then differs by that interpolation error (exact for P_k data)."""
    data = level.data
    nodes = data["on_contact"]
    gap = np.nan_to_num(data["gap"][nodes])
    load = data["contact_load"][nodes]
    if np.ptp(gap) == 0 and np.ptp(load) == 0:
        return  # constant data: in every P_k
    warnings.warn("dolfinx_contact: the obstacle or the contact load varies along Gamma_C: the Nitsche bracket uses "
                  "its P_k interpolant, exact only if the data are polynomials of degree <= k", stacklevel=2)


def options_of(model: str, choice: str, theta: float) -> dict:
    linear = dict(LINEAR[choice])
    if linear["ksp_type"] == "cg" and model == "nitsche" and theta != 1:
        linear["ksp_type"] = "gmres"  # theta != 1: J is not symmetric
    return {**NEWTON, **linear}


def method_name(model: str, theta: float) -> str:
    if model == "nitsche" and theta != 1:
        return f"dolfinx-nitsche-theta{theta:g}"
    return f"dolfinx-{model}"


def solve_level(args, manifest: dict, data: dict, options: dict, coarse=None) -> tuple[dict, dolfinx.fem.Function]:
    """Solve one level (from ``coarse``, the coarser level's solution, if given); the result's arrays
    and the solution as a function (the next level's start under --nested)."""
    level = Level(manifest, data)
    if args.model == "nodal":
        snes, x, seconds = solve_nodal(level, options, coarse)
    else:
        snes, x, seconds = solve_nitsche(level, options, args.gamma0, args.theta, coarse)
    reason = snes.getConvergedReason()
    if reason <= 0:
        sys.exit(f"dolfinx_contact: SNES did not converge (reason {reason})")
    solution = dolfinx.fem.Function(level.V)
    solution.x.array[:] = x.array
    return solution, {"points": level.points, "values": x.array.reshape(len(level.points), -1).copy(),
            "seconds": seconds, "iterations": snes.getIterationNumber(),
            "linear_iterations": snes.getLinearSolveIterations(), "residual": snes.getFunctionNorm()}


def parse(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("export", type=Path)
    parser.add_argument("out", type=Path)
    parser.add_argument("--model", choices=("nodal", "nitsche"), required=True)
    parser.add_argument("--theta", type=float, default=1.0, choices=(1.0, 0.0, -1.0))
    parser.add_argument("--gamma0", type=float, default=None, help="default: the manifest's")
    parser.add_argument("--levels", type=int, default=None, help="the first N levels (default: all)")
    parser.add_argument("--options", choices=tuple(LINEAR), default="best")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--nested", action="store_true", help="start each level from the coarser level's solution")
    parser.add_argument("--petsc", nargs="*", default=[], metavar="KEY=VALUE", help="extra PETSc options (without prefix)")
    return parser.parse_args(argv)


def solution_manifest(args, manifest: dict, options: dict) -> dict:
    like = {"nodal": "nodal", "nitsche": "nitsche"}[args.model]
    solver = "SNES VI (vinewtonrsls)" if args.model == "nodal" else "SNES newtonls, Nitsche in UFL"
    petsc = ".".join(map(str, PETSc.Sys.getVersion()))
    extra = {"gamma0": args.gamma0, "theta": args.theta} if args.model == "nitsche" else {}
    return {"format": "signorini-harness-solution", "format_version": 1,
            "code": f"DOLFINx {dolfinx.__version__} + PETSc {petsc} {solver}",
            "method": method_name(args.model, args.theta), "like": like, "case": manifest["case"]["name"],
            "order": manifest["order"], "options": {"petsc": options, "choice": args.options, "threads": args.threads,
                        "nested": args.nested or NESTED[args.options], **extra}}


def main(argv=None) -> None:
    args = parse(argv)
    manifest = json.loads((args.export / "manifest.json").read_text())
    if args.gamma0 is None:
        args.gamma0 = manifest["nitsche_law"]["gamma0"]
    options = options_of(args.model, args.options, args.theta)
    options.update(item.split("=", 1) if "=" in item else (item, "") for item in args.petsc)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "manifest.json").write_text(json.dumps(solution_manifest(args, manifest, options), indent=2))
    coarse = None
    for entry in manifest["levels"][:args.levels]:
        solution, result = solve_level(args, manifest, read_level(args.export, entry), options, coarse)
        coarse = solution if args.nested or NESTED[args.options] else None
        np.savez(args.out / f"level-{entry['level']}.npz", **result)
        print(f"level {entry['level']}: {len(result['points'])} nodes, {result['seconds']:.3f} s, "
              f"{result['iterations']} Newton, {result['linear_iterations']} linear, residual {result['residual']:.2e}", flush=True)


if __name__ == "__main__":
    main()
