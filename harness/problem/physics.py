"""The physics axis: which partial differential equation a case poses, and what its contact
condition constrains.

* ``Scalar`` -- the paper's problem (2.1)-(2.4): -Laplace(u) = f, u - alpha >= 0 on Gamma_C.
* ``Elasticity`` -- Remark 2.3: frictionless unilateral contact of a linear elastic body (plane
  strain in 2D, the body itself in 3D) on a rigid foundation, -div sigma(u) = f,
  sigma(u) = 2 mu eps(u) + lambda tr eps(u) I.

Both are written with one *contact variable* c(v) on Gamma_C and its obstacle, so that each
discrete cone, its solver and the errors on Gamma_C are the same code for both:

    scalar:      c(v) = v,        obstacle alpha,     pressure lambda = d_n u - g_C;
    elasticity:  c(v) = -v . n,   obstacle -alpha,    pressure p = -(sigma_n(u) - g_C . n),

with sigma_n = n . sigma(u) n. The elastic conditions on Gamma_C (sign conventions: n the
outward unit normal, alpha the initial gap, compression negative),

    u . n - alpha <= 0,   sigma_n(u) - g_n <= 0,   (u . n - alpha)(sigma_n(u) - g_n) = 0,
    sigma_t(u) = g_t   (frictionless; g_t = 0 unless a tangential load is manufactured;
                        sigma_t = sigma n - sigma_n n, a vector in 3D),

read c(u) - obstacle >= 0, p >= 0, (c(u) - obstacle) p = 0: the scalar conditions (2.4) of the
contact variable. In the rotated frame (tangential components, c) at each Gamma_C node
(``fem.rotated_frame.RotatedFrame``), the P2 trace of c on a flat piece of Gamma_C is the scalar
problem's trace, so every cone (vertex values and edge means or midpoints of c >= obstacle; in
3D the triangle means) is the scalar one on the contact variable (``fem.cones``,
``fem.face_means``).
"""
from __future__ import annotations

from dataclasses import dataclass

import ngsolve as ngs
import numpy as np

from ..mesh.points import evaluate

COORDINATES = (ngs.x, ngs.y, ngs.z)


def gradient(u: ngs.CoefficientFunction, dim: int = 2) -> ngs.CoefficientFunction:
    """grad u of a scalar CF (a dim-vector), or the Jacobian of a vector CF (row i = grad u_i)."""
    axes = COORDINATES[:dim]
    if u.dim == 1:
        return ngs.CF(tuple(u.Diff(d) for d in axes))
    return ngs.CF(tuple(u[i].Diff(d) for i in range(u.dim) for d in axes), dims=(u.dim, dim))


@dataclass(frozen=True)
class Scalar:
    """The Poisson-Signorini problem of the paper."""

    name = "scalar"
    components = 1
    multigrid = True        # the truncated P1 V-cycle of ``multigrid`` applies
    elastic = False         # the report: H1 error tables, u_h drawn on the domain
    rotated_frame = False   # the contact condition is on u itself: no change of basis on Gamma_C
    traction_load = False   # g_C enters through the Gamma_C quadrature (``fem.assembly.contact_load_vector``)
    modulus = 1.0           # the scale of the flux beside the second derivatives of u
    operator = "-Laplace(u)"

    def constant(self, value: float) -> ngs.CoefficientFunction:
        return ngs.CF(float(value))

    def is_field(self, u: ngs.CoefficientFunction) -> bool:
        """Is ``u`` a field of this physics (a scalar)?"""
        return u.dim == self.components

    def tangential(self, case, mesh, points, normals) -> None:
        """No tangential condition on Gamma_C."""
        return None

    def describe(self) -> str:
        return "scalar (Poisson)"

    def space(self, mesh, order: int):
        return ngs.H1(mesh, order=order, dirichlet="dirichlet")

    def form(self, u, v):
        return ngs.grad(u) * ngs.grad(v)

    def energy_density(self, grad_e):
        return ngs.InnerProduct(grad_e, grad_e)

    def load(self, u: ngs.CoefficientFunction, dim: int = 2) -> ngs.CoefficientFunction:
        """f = -Laplace(u) of (2.1)."""
        return -sum((u.Diff(d).Diff(d) for d in COORDINATES[1:dim]), u.Diff(ngs.x).Diff(ngs.x))

    def flux(self, grad_u, normal):
        """d_n u: the Neumann datum on Gamma_g."""
        return grad_u * normal

    def contact_value(self, case, mesh, points, normals) -> np.ndarray:
        return evaluate(case.u, mesh, points)

    def pressure(self, case, mesh, points, normals) -> np.ndarray:
        """lambda = d_n u - g_C at ``points`` with outward unit ``normals`` (same leading shape)."""
        return self.contact_forces(self.flux_array(_gradient_at(case.grad_u, mesh, points, 1)), normals,
                                   _contact_load(case, mesh, points))[0]

    def divergence(self, gfu) -> ngs.CoefficientFunction:
        """div F(u_h) = Laplace(u_h) of a GridFunction of order >= 2, from NGSolve's Hessian."""
        return ngs.Trace(gfu.Operator("hesse"))

    def flux_array(self, grad: np.ndarray) -> np.ndarray:
        """The flux of (2.1) from gradients given as arrays (..., 1, dim): grad u itself."""
        return grad

    def flux_rows(self, grads: np.ndarray, normals: np.ndarray) -> list:
        """The flux of the contact variable, d_n v, of basis functions with gradients ``grads``
        (q, l, dim) at points with outward ``normals`` (q, dim): [(component 0, (q, l))]."""
        return [(0, np.einsum("qld,qd->ql", grads, normals))]

    def trace_rows(self, values: np.ndarray, normals: np.ndarray) -> list:
        """The contact variable v of basis functions with ``values`` (q, l) at points of Gamma_C:
        [(component 0, (q, l))]."""
        return [(0, values)]

    def contact_forces(self, flux: np.ndarray, normals: np.ndarray, load: np.ndarray) -> tuple:
        """(pressure, tangential force) on Gamma_C from the flux (..., 1, dim) at points with
        outward ``normals`` (..., dim) and the contact load g_C (...): lambda = d_n u - g_C, and
        no tangential force (None)."""
        return (flux[..., 0, :] * normals).sum(axis=-1) - load, None

    def obstacle(self, gap):
        return gap

    def normal_load(self, load: np.ndarray, normals: np.ndarray) -> np.ndarray:
        """The contact load as the contact variable's pressure sees it (pressure = flux - it): g_C."""
        return load

    def contact_variable(self, u):
        """The contact variable of a trial function on Gamma_C: u itself."""
        return u

    def displacement_at_vertices(self, problem, u: np.ndarray) -> np.ndarray:
        return u[: problem.mesh.nv].copy()


# the stiffest material the elastic V-cycle serves (``Elasticity.multigrid``)
MULTIGRID_MAX_LAMBDA_OVER_MU = 20.0


@dataclass(frozen=True)
class Elasticity:
    """Linear elasticity with Young's modulus ``young`` and Poisson's ratio ``poisson``
    (0 <= poisson < 1/2; nearly incompressible as poisson -> 1/2): plane strain for ``dim`` 2,
    the 3D body for ``dim`` 3 (a plane-strain field with u_z = 0 is a 3D field of the same
    material)."""

    young: float = 1.0
    poisson: float = 0.3
    dim: int = 2
    name = "elasticity"
    elastic = True          # the report: energy-norm errors, the deformed shape, the Poisson ratio
    rotated_frame = True    # u . n is constrained: Gamma_C's dofs in the normal-tangential frame
    traction_load = True    # g_C is a traction, integrated into the load vector
    operator = "-div sigma(u)"

    def __post_init__(self):
        if not (self.young > 0 and 0 <= self.poisson < 0.5):
            raise ValueError(f"elasticity needs young > 0 and 0 <= poisson < 1/2, got E = {self.young}, nu = {self.poisson}")
        if self.dim not in (2, 3):
            raise ValueError(f"elasticity is 2D (plane strain) or 3D, got dimension {self.dim}")

    @property
    def components(self) -> int:
        """The displacement's components: one per space dimension."""
        return self.dim

    @property
    def multigrid(self) -> bool:
        """Whether the solves use the truncated vector V-cycle (``solvers.multigrid``: vector P1
        coarse spaces in the rotated frame, Gauss-Seidel smoothing) rather than sparse Cholesky.
        Pointwise smoothers are not robust as lambda/mu grows (the near-kernel of div; Schoeberl,
        Numer. Math. 84 (1999), builds the robust ones): CG's iterations grow with lambda/mu,
        and past MULTIGRID_MAX_LAMBDA_OVER_MU (Poisson ratio 0.476) the factorisation is the
        faster path at the report's sizes."""
        return self.lam / self.mu <= MULTIGRID_MAX_LAMBDA_OVER_MU

    @property
    def mu(self) -> float:
        return self.young / (2 * (1 + self.poisson))

    @property
    def lam(self) -> float:
        return self.young * self.poisson / ((1 + self.poisson) * (1 - 2 * self.poisson))

    @property
    def modulus(self) -> float:
        """lambda + 2 mu: the largest factor between second derivatives of u and the load."""
        return self.lam + 2 * self.mu

    def constant(self, value: float) -> ngs.CoefficientFunction:
        """A constant load ``value`` in every component."""
        return ngs.CF((float(value),) * self.components)

    def is_field(self, u: ngs.CoefficientFunction) -> bool:
        """Is ``u`` a displacement (``components`` entries)?"""
        return u.dim == self.components

    @property
    def kappa(self) -> float:
        """Kolosov's constant of plane strain, 3 - 4 nu (the complex potentials of ``functions``)."""
        return 3 - 4 * self.poisson

    def describe(self) -> str:
        kind = "plane strain" if self.dim == 2 else "3D"
        return f"linear elasticity, {kind}, E = {self.young:g}, Poisson ratio {self.poisson:g} (λ/μ = {self.lam / self.mu:.3g})"

    def strain(self, grad):
        return 0.5 * (grad + grad.trans)

    def stress(self, grad):
        eps = self.strain(grad)
        return 2 * self.mu * eps + self.lam * ngs.Trace(eps) * ngs.Id(self.dim)

    def space(self, mesh, order: int):
        return ngs.VectorH1(mesh, order=order, dirichlet="dirichlet")

    def form(self, u, v):
        return ngs.InnerProduct(self.stress(ngs.Grad(u)), self.strain(ngs.Grad(v)))

    def energy_density(self, grad_e):
        """sigma(e) : eps(e), whose integral is the squared energy norm a(e, e)."""
        return ngs.InnerProduct(self.stress(grad_e), self.strain(grad_e))

    def load(self, u: ngs.CoefficientFunction, dim: int = 2) -> ngs.CoefficientFunction:
        """f = -div sigma(u) (``dim`` is the material's own)."""
        s = self.stress(gradient(u, self.dim))
        axes = COORDINATES[:self.dim]
        return -ngs.CF(tuple(sum((s[i, j].Diff(axes[j]) for j in range(1, self.dim)), s[i, 0].Diff(axes[0]))
                             for i in range(self.dim)))

    def flux(self, grad_u, normal):
        """sigma(u) n: the traction on Gamma_g."""
        return self.stress(grad_u) * normal

    def divergence(self, gfu) -> ngs.CoefficientFunction:
        """div sigma(u_h) = mu Laplace(u_i) + (mu + lambda) d_i div u_h of a GridFunction of order
        >= 2, from NGSolve's Hessian (its row i holds u_i's second derivatives, d_j d_k at column
        d j + k)."""
        hesse, d = gfu.Operator("hesse"), self.dim
        return ngs.CF(tuple(self.mu * sum(hesse[i, d * j + j] for j in range(d))
                            + (self.mu + self.lam) * sum(hesse[j, d * i + j] for j in range(d)) for i in range(d)))

    def flux_array(self, grad: np.ndarray) -> np.ndarray:
        """sigma from displacement gradients given as arrays (..., dim, dim), row i = grad u_i."""
        strain = 0.5 * (grad + np.swapaxes(grad, -1, -2))
        trace = np.trace(strain, axis1=-2, axis2=-1)
        return 2 * self.mu * strain + self.lam * trace[..., None, None] * np.eye(self.dim)

    def flux_rows(self, grads: np.ndarray, normals: np.ndarray) -> list:
        """The flux of the contact variable, -sigma_n(v) = -(2 mu (n . grad v_i) n_i + lambda
        div v), of the vector basis functions e_i phi (i a component, phi a scalar basis function
        with gradients ``grads`` (q, l, dim)) at points with outward ``normals`` (q, dim):
        [(i, (q, l)) for each component i]."""
        dn = np.einsum("qld,qd->ql", grads, normals)
        return [(i, -(2 * self.mu * normals[:, i, None] * dn + self.lam * grads[:, :, i])) for i in range(self.dim)]

    def trace_rows(self, values: np.ndarray, normals: np.ndarray) -> list:
        """The contact variable -v . n of the vector basis functions e_i phi (phi a scalar basis
        function with ``values`` (q, l)) at points with outward ``normals`` (q, dim):
        [(i, (q, l)) for each component i]."""
        return [(i, -normals[:, i, None] * values) for i in range(self.dim)]

    def contact_forces(self, flux: np.ndarray, normals: np.ndarray, load: np.ndarray) -> tuple:
        """(pressure, tangential force) on Gamma_C from sigma (..., dim, dim) at points with
        outward ``normals`` (..., dim) and the contact traction g_C (..., dim): with
        t = sigma n - g_C, p = -t . n and sigma_t - g_t = t - (t . n) n, given as its component
        along the tangent (-n_y, n_x) in 2D and its length in 3D (zero when frictionless)."""
        traction = np.einsum("...ij,...j->...i", flux, normals) - load
        normal = (traction * normals).sum(axis=-1)
        if self.dim == 2:
            return -normal, (traction * np.stack([-normals[..., 1], normals[..., 0]], axis=-1)).sum(axis=-1)
        return -normal, np.linalg.norm(traction - normal[..., None] * normals, axis=-1)

    def _exact_forces(self, case, mesh, points, normals) -> tuple:
        grad = _gradient_at(case.grad_u, mesh, points, self.dim)
        return self.contact_forces(self.flux_array(grad), normals, _contact_load(case, mesh, points, self.dim))

    def contact_value(self, case, mesh, points, normals) -> np.ndarray:
        """c(u) = -u . n."""
        return -(evaluate(case.u, mesh, points) * normals).sum(axis=-1)

    def pressure(self, case, mesh, points, normals) -> np.ndarray:
        """p = -(sigma_n(u) - g_C . n)."""
        return self._exact_forces(case, mesh, points, normals)[0]

    def tangential(self, case, mesh, points, normals) -> np.ndarray:
        """sigma_t(u) - g_t (zero for a frictionless contact): its component along the tangent
        (-n_y, n_x) in 2D, its length in 3D."""
        return self._exact_forces(case, mesh, points, normals)[1]

    def tangential_traction(self, case, mesh, points, normals) -> np.ndarray:
        """sigma_t(u) - g_t as a vector (..., dim): the traction sigma(u) n - g_C less its normal
        part (Tresca's friction force, ``problem.friction``)."""
        grad = _gradient_at(case.grad_u, mesh, points, self.dim)
        traction = np.einsum("...ij,...j->...i", self.flux_array(grad), normals) - _contact_load(case, mesh, points, self.dim)
        return traction - (traction * normals).sum(axis=-1)[..., None] * normals

    def obstacle(self, gap):
        return None if gap is None else -gap

    def normal_load(self, load: np.ndarray, normals: np.ndarray) -> np.ndarray:
        """The contact traction g_C (q, dim) as the contact variable's pressure sees it: -g_C . n
        (the pressure -(sigma_n - g_n) is the flux -sigma_n minus it)."""
        return -(load * normals).sum(axis=-1)

    def contact_variable(self, u):
        """c(u) = -u . n of a trial function (a boundary integrand: n the outward normal)."""
        return -u * ngs.specialcf.normal(self.dim)

    def displacement_at_vertices(self, problem, u: np.ndarray) -> np.ndarray:
        """(nv, dim) Cartesian displacement at the vertices (vertex dofs are nodal values)."""
        cartesian = problem.cartesian(u)
        nv, block = problem.mesh.nv, problem.ndof // self.dim
        return np.stack([cartesian[k * block: k * block + nv] for k in range(self.dim)], axis=1)


def _gradient_at(grad_u: ngs.CoefficientFunction, mesh, points: np.ndarray, components: int) -> np.ndarray:
    """grad u at ``points`` (..., dim) as (..., components, dim): row i = grad u_i."""
    return evaluate(grad_u, mesh, points).reshape(points.shape[:-1] + (components, points.shape[-1]))


def _contact_load(case, mesh, points, components: int = 1) -> np.ndarray:
    if case.contact_load is None:
        return np.zeros(points.shape[:-1] + ((components,) if components > 1 else ()))
    return evaluate(case.contact_load, mesh, points)


SCALAR = Scalar()
PHYSICS = ("scalar", "elasticity")
