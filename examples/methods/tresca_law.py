"""A Tresca friction law of your own, from a file (the method protocol's second level,
``harness.methods.ContactLawMethod`` with a friction law, ``harness.methods.FrictionLaw``): at
each Gauss point of Γ_C the law sees the slip u_t and its friction force λ_t = σ_t − g_t (the
scalar model: u and ∂ₙu − g_C; in 3D elasticity 2-vectors), and in elasticity the normal channel
(−u·n, −σₙ) last; it returns a pressure and a flux term per channel and their derivatives; the
harness assembles F(u) = A u − b − Σ ∫ p_j c_j(v) + Σ ∫ f_j flux_j(v) and solves it by semismooth
Newton, residual recorded.

``nitsche-half``: Nitsche for Tresca with θ = 1/2 (the built-in ``nitsche`` allows θ ∈ {1, 0, −1},
the members Chouly, Hild & Renard analyse): p_t = P_s(λ_t − u_t/γ), f_t = θγ(p_t − λ_t),
γ = γ₀h/M, P_s the projection onto the disc of radius s ([−s, s] in 1D), and Nitsche's bilateral
term on the normal channel in elasticity. No theorem covers θ = 1/2: it declares no rate ("no
theory", grey) and the study measures one. Its Jacobian is not symmetric (θ ≠ 1): Newton
factorises.

Run it::

    python -m harness run --case tresca-r32 --method examples/methods/tresca_law.py --levels 3
"""
from dataclasses import dataclass

import numpy as np

from harness.methods import ContactLawMethod


def project(x, s):
    """P_s(x) for x (q, t): x inside the disc, s x/|x| outside; and its Jacobian (q, t, t)."""
    length = np.linalg.norm(x, axis=1)
    outside = length > s
    scale = np.where(outside, s / np.maximum(length, 1e-300), 1.0)
    unit = x / np.maximum(length, 1e-300)[:, None]
    t = x.shape[1]
    jacobian = scale[:, None, None] * (np.eye(t) - np.where(outside, 1.0, 0.0)[:, None, None] * unit[:, :, None] * unit[:, None, :])
    return scale[:, None] * x, jacobian


@dataclass(frozen=True)
class HalfNitscheTresca:
    gamma0: float = 0.05
    theta: float = 0.5
    friction = "tresca"         # the law of ``harness.problem.friction`` it discretises
    branches = (0, 1, 2)        # stick, slip (1D: above s), slip below -s

    def argument(self, at):
        gamma = self.gamma0 * at.h / at.modulus
        return at.friction_force - at.slip / gamma[:, None], gamma

    def branch(self, at):
        x, _ = self.argument(at)
        if at.tangential == 1:
            return np.where(x[:, 0] > at.threshold, 1, np.where(x[:, 0] < -at.threshold, 2, 0))
        return np.where(np.linalg.norm(x, axis=1) > at.threshold, 1, 0)

    def _projection(self, x, at, branch):
        if at.tangential == 1:    # on a forced branch: its own formula (the 1D slip is piecewise constant)
            p = np.select([branch == 1, branch == 2], [at.threshold, -at.threshold], x[:, 0])[:, None]
            return p, np.where(branch == 0, 1.0, 0.0)[:, None, None]
        p, D = project(x, np.where(branch == 0, np.inf, at.threshold))
        return p, D

    def term(self, at, branch):
        x, gamma = self.argument(at)
        p_t = self._projection(x, at, branch)[0]
        p, f = [p_t], [self.theta * gamma[:, None] * (p_t - at.friction_force)]
        if at.normal is not None:
            n = at.normal
            p.append((n.dn - n.load - (n.u - n.gap) / gamma)[:, None])
            f.append((-self.theta * (n.u - n.gap))[:, None])
        return np.concatenate(p, axis=1), np.concatenate(f, axis=1)

    def derivative(self, at, branch):
        x, gamma = self.argument(at)
        D = self._projection(x, at, branch)[1]
        t, (q, m) = at.tangential, at.u.shape
        g = gamma[:, None, None]
        p_u, p_dn, f_u, f_dn = (np.zeros((q, m, m)) for _ in range(4))
        p_u[:, :t, :t], p_dn[:, :t, :t] = -D / g, D
        f_u[:, :t, :t], f_dn[:, :t, :t] = -self.theta * D, self.theta * g * (D - np.eye(t))
        if m > t:
            p_u[:, t, t], p_dn[:, t, t], f_u[:, t, t] = -1.0 / gamma, 1.0, -self.theta
        return p_u, p_dn, f_u, f_dn


nitsche_half = ContactLawMethod(
    name="nitsche-half", order=2, contact="Nitsche for Tresca, θ = 1/2: P_s(σ_t − u_t/γ), γ = γ₀h/M",
    reference="examples/methods/tresca_law.py", expected=None, law=HalfNitscheTresca(),
    friction=("tresca",))

methods = [nitsche_half]
