"""Validation of a Coulomb case (``harness.problem.validate.check_coulomb``): a field that breaks
one of Coulomb's conditions is refused in one line naming it."""
import pytest

from harness.problem.case import CaseError, load_case
from harness.problem.validate import validate_case

HEADER = ("from ngsolve import CF, IfPos, x, y\n"
          "from harness.problem import Coulomb, Elasticity, contact_strip, stick_slip_mode\n"
          "name = 'probe'\ndescription = 'probe'\ntheorem = ''\nnu = 2.5\nexpected_rate = 1.5\n"
          "physics = 'elasticity'\npoisson = 0.3\ngeometry = contact_strip(breaks=[0.0])\nmaxh = 0.5\n"
          "material = Elasticity(1.0, 0.3)\nfriction = Coulomb(coefficient=0.5)\n")


def _case_file(tmp_path, body: str):
    path = tmp_path / "case.py"
    path.write_text(HEADER + body)
    return str(path)


def _stick_slip(amplitude: float, coefficient: float = 0.5, pressure: float = 2.0) -> str:
    """elastic-coulomb-r32's field with the mode's amplitude c, its mode's mu_F and P0."""
    return (f"b = {pressure} / (material.lam + 2 * material.mu)\n"
            f"u = CF((y / material.mu, -b * y)) + {amplitude} * stick_slip_mode(material, coefficient={coefficient})\n"
            "f = 0\nsingular_points = [(0.0, 0.0)]\n")


def test_the_manufactured_field_passes(tmp_path):
    validate_case(load_case(_case_file(tmp_path, _stick_slip(1.0))))


def test_a_stick_zone_whose_force_exceeds_mu_f_p_is_refused(tmp_path):
    """c = 2 > 2 s / l: on the stick side sigma_xy = s - c l |x|^{l-1} leaves [-mu_F p, mu_F p]
    (p = P0 = 2 there) near x = -1."""
    with pytest.raises(CaseError, match=r"^case 'probe' violates the Coulomb condition \|sigma_t\| <= mu_F p "
                                        r"on Gamma_C at \(-[^\n]*$"):
        validate_case(load_case(_case_file(tmp_path, _stick_slip(2.0))))


def test_a_slip_against_the_force_is_refused(tmp_path):
    """u_x = x^3 > 0 on x > 0 under the shear sigma_xy = -1 (u = (-y/mu + x^3, -b y), P0 = 4:
    |sigma_xy| <= mu_F p everywhere): the force pushes along the slip, not against it."""
    body = ("b = 4.0 / (material.lam + 2 * material.mu)\n"
            "u = CF((-y / material.mu + IfPos(x, x * x * x, 0.0), -b * y))\n"
            "singular_points = []\nderivative_jumps = [((0.0, 0.0), (0.0, 1.0))]\n")
    with pytest.raises(CaseError, match=r"^[^\n]*Coulomb condition sigma_t = -mu_F p u_t/\|u_t\| where u_t != 0 "
                                        r"on Gamma_C at \(0\.[^\n]*$"):
        validate_case(load_case(_case_file(tmp_path, body)))


def test_the_tresca_mode_is_not_coulomb(tmp_path):
    """Tresca's r^{3/2} mode (mu_F = 0 in the mode) has a normal stress of its own on the slip
    side: the slip-side shear s is not mu_F p there (elastic-coulomb-r32's docstring)."""
    with pytest.raises(CaseError, match=r"Coulomb condition sigma_t = -mu_F p u_t/\|u_t\| where u_t != 0"):
        validate_case(load_case(_case_file(tmp_path, _stick_slip(1.0, coefficient=0.0))))


@pytest.mark.parametrize("body, condition", [
    # separation (u . n = -0.1) under a pressure: complementarity
    ("u = CF((0.0, 0.1 - y))\nsingular_points = []\n", r"p \(u.n - gap\) = 0"),
    # a pull on Gamma_C: p < 0
    ("u = CF((0.0, y))\nsingular_points = []\n", r"p = -\(sigma_n\(u\) - g_n\) >= 0"),
    # penetration (u . n = 0.1)
    ("u = CF((0.0, y - 0.1))\nsingular_points = []\n", r"u.n - gap <= 0"),
])
def test_the_unilateral_conditions_are_coulombs_too(tmp_path, body, condition):
    with pytest.raises(CaseError, match=r"violates the Coulomb condition " + condition):
        validate_case(load_case(_case_file(tmp_path, body)))
