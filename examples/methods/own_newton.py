"""A method with a solve of its own (the method protocol's third level, ``harness.methods.OwnSolve``):
the harness hands each level over (``LevelProblem``: the stiffness A, the load b, the free dofs,
the Dirichlet values, Γ_C's Gauss points with the rows T of the contact variable and N of its
flux, the obstacle there, the coarser level's solution interpolated) and takes back u_h, the
solver's own residual and status. The rows are the same in every physics and dimension (the
contact variable is u, or −u·n in elasticity), so this solve runs on scalar and elastic cases,
2D and 3D, unchanged.

Here: the penalty method, u_h minimising ½a(v, v) − L(v) + (1/2ε)∫_{Γ_C}[α − c(v)]₊² with ε = ε₀h/M
(Chouly & Hild, Appl. Numer. Math. 65 (2013)), solved by a plain semismooth Newton method with
SciPy's sparse LU: 25 lines a user might write to try an idea before tuning it. It solves the
same discrete problem as the built-in ``penalty`` (ε₀ = 0.05), so its rows agree with that
method's to the solvers' tolerance; the tests check that. Run it::

    python -m harness run --case transition-r32 --method examples/methods/own_newton.py --method penalty --levels 4
    python -m harness run --case elastic-transition-r32 --method examples/methods/own_newton.py --method penalty --levels 4
"""
import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from harness.methods import OwnSolution, OwnSolve

EPS0 = 0.05


def penalty_newton(level, tol=1e-10, max_steps=50):
    A, b, free, c = level.A, level.b, level.free, level.contact
    eps = EPS0 * c.h / c.modulus                        # eps = eps0 h / M (M = lambda + 2 mu in elasticity)
    weights = c.weights / eps                           # W / eps at the Gauss points
    u = np.where(free, level.start if level.start is not None else 0.0, level.lift)
    scale = max(np.abs((b - A @ np.where(free, 0.0, level.lift))[free]).max(), 1e-300)
    for step in range(max_steps + 1):
        active = c.gap - c.T @ u > 0                    # the branch of [alpha - u]_+
        F = A @ u - b - c.T.T @ (weights * np.where(active, c.gap - c.T @ u, 0.0))
        residual = np.abs(F[free]).max() / scale
        if residual <= tol or step == max_steps:
            break
        J = (A + c.T.T @ sp.diags(weights * active) @ c.T).tocsr()[free][:, free]
        u[free] -= spla.spsolve(J.tocsc(), F[free])
    status = "converged" if residual <= tol else f"not converged in {max_steps} steps"
    pressure = np.where(c.gap - c.T @ u > 0, (c.gap - c.T @ u) / eps, 0.0)
    return OwnSolution(u, residual, step, status, pressure)


def chouly_hild(case):
    from harness.methods import METHODS
    return METHODS["penalty"].expected(case)            # the built-in penalty's theory


method = OwnSolve(name="penalty-own-newton", order=2, contact="penalty, ε = ε₀h, by its own Newton + SuperLU",
                  reference="examples/methods/own_newton.py", expected=chouly_hild, solve_level=penalty_newton,
                  physics=("scalar", "elasticity"), dimensions=(2, 3))
