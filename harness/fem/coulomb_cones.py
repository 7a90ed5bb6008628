"""Coulomb friction (``problem.friction.Coulomb``) on the cones of nodal functionals (2D
elasticity): the frictionless cone's Signorini rows (``fem.cones``) and the Tresca rows of its
friction analogue (``fem.friction``) in ONE change of variables, u = S z, S changing the contact
component's edge bubbles (into the cone's edge variables) and the tangential component's (into
the friction variables), so that both sets of rows are bounds on z:

    z[C] >= alpha (the cone: the contact variable -u . n at Gamma_C's vertices and its edge
    functionals), and the terms c_i |z[F_i] - zprev_i| (the slip at the same nodes).

Row i of F and row i of C sit at the same node (Gamma_C's vertices, then its edges, in the
order of ``fem.assembly.DiscreteProblem``'s vertex_dofs and edge_dofs). The threshold from the multiplier:
Tresca's weight is c_i = w_i s_i (w_i the friction quadrature weight, ``friction.friction_weights``);
Coulomb's s = mu_F p, and the cone's multiplier at a node is its nodal normal reaction
lambda_n,i = int p phi_i, which the same quadrature reads as w_i p_i (Simpson's weights for the
nodal P2 basis, |e| for the edge-mean variable whose basis has mean 1 on its edge, the lumped
|e|/2 for P1). So c_i = w_i mu_F (lambda_n,i / w_i) = mu_F lambda_n,i where w_i > 0, and 0 where
the quadrature puts no weight (the mean analogue's vertices: their basis functions have mean 0
on every edge, their multipliers O(h^2) of either sign). The discrete Coulomb law is then
|lambda_t,i| <= mu_F lambda_n,i row by row, lambda_t the nodal friction force.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .assembly import ContactTraceFunction, DiscreteProblem
from .cones import ContactModel, ProblemQP, contact_trace, transformed_matrix
from .friction import friction_variables, friction_weights
from .p1_embedding import ContactEdges


@dataclass
class CoulombConeQP(ProblemQP):
    """The cone ``model``'s rows C >= alpha and the friction rows F (``weights`` their quadrature
    weights) in the variables z (u = S z), on ``problem`` (the final load step's data; another
    step's by ``at_step``). ``edges``: the P1 embedding in z (both components' changed edges);
    ``points``: each row's node; ``edge_of_row``: the contact edge of each edge row."""

    problem: DiscreteProblem
    model: ContactModel
    S: sp.csr_matrix
    K: sp.csr_matrix
    K_ngs: object
    b: np.ndarray
    C: np.ndarray
    alpha: np.ndarray
    F: np.ndarray
    weights: np.ndarray
    edges: ContactEdges
    points: np.ndarray
    edge_of_row: np.ndarray

    def at_step(self, stepped: DiscreteProblem) -> tuple[np.ndarray, np.ndarray]:
        """(b, lift) in z of a load step's problem (``fem.assembly.at_load_step``): S is the
        identity on the Dirichlet dofs, so the lift is the problem's."""
        return self.S.T @ stepped.b, stepped.lift

    def thresholds(self, coefficient: float, normal_reaction: np.ndarray) -> np.ndarray:
        """c_i = mu_F lambda_n,i at the rows the friction quadrature weighs (the module's note),
        the reaction's round-off negatives (within the KKT tolerance of an active row) read as 0."""
        return np.where(self.weights > 0, coefficient * np.maximum(normal_reaction, 0.0), 0.0)

    def to_u(self, z: np.ndarray) -> np.ndarray:
        return self.S @ z

    def trace_function(self, u: np.ndarray, contact_active: np.ndarray) -> ContactTraceFunction:
        """u_h's trace with the contact rows' status (``fem.cones.contact_trace``)."""
        return contact_trace(self.problem, u, contact_active)


def coulomb_cone_qp(case, problem: DiscreteProblem, model: ContactModel) -> CoulombConeQP:
    """The cone ``model``'s Coulomb problem on ``problem`` (2D elasticity, one body)."""
    model._check(problem)
    if not problem.physics.rotated_frame:
        raise ValueError("Coulomb friction on the cones is elastic: the scalar model has no normal stress")
    t_vertices, t_edges, t_ends = friction_variables(problem)     # refuses 3D
    ne = len(problem.edge_dofs)
    S_n, S_t = model.transform(problem), model.transform(problem, t_edges, t_ends)
    S = (S_n + S_t - sp.identity(problem.ndof, format="csr")).tocsr()
    changed = np.concatenate([problem.edge_dofs, t_edges]).astype(np.int64)
    K, K_ngs = transformed_matrix(problem, S, rows=changed)
    ends = np.concatenate([problem.end_dofs[:ne], t_ends]).reshape(-1, 2)
    edges = ContactEdges.of_edges(problem, changed, ends)
    trace = problem.trace
    return CoulombConeQP(problem, model, S, K, K_ngs, S.T @ problem.b, model.constrained_dofs(problem).astype(np.int64),
                         model.lower_bounds(case, problem), np.concatenate([t_vertices, t_edges]).astype(np.int64),
                         np.concatenate(friction_weights(problem, model)), edges,
                         np.concatenate([trace.vertex_points, trace.midpoints[:ne]]), np.arange(ne, dtype=np.int64))
