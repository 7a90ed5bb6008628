"""Stage 2, the problem: what a case declares (``case``: the contract and its loading,
``geometry``, ``functions``: exact-solution helpers), its ``physics`` (every scalar/elastic and
2D/3D difference) and the checks of a case (``validate``). Imports only ``mesh``."""
from ..core.lazy import lazy

# The case protocol and the helpers a case file of your own uses (``examples/cases/``,
# docs/guide/cases.md), imported when first used.
_PUBLIC = {
    "Case": "case", "CaseError": "case", "load_case": "case", "registered_cases": "case",
    "polygon": "geometry", "contact_strip": "geometry", "split_strip": "geometry", "contact_box": "geometry",
    "disc_box": "geometry", "zone_box": "geometry", "zone_rectangle": "geometry",
    "polar": "functions", "transition": "functions", "transition_gradient": "functions",
    "roller_free_mode": "functions", "roller_free_series": "functions", "bracketed_root": "functions", "clamped_free_exponent": "functions",
    "stick_slip_mode": "functions", "stick_slip_series": "functions",
    "coulomb_stick_slip_series": "functions", "coulomb_stick_slip_exponent": "functions",
    "Elasticity": "physics", "Scalar": "physics", "MirrorBody": "bodies",
    "Tresca": "friction", "FRICTIONLESS": "friction", "Coulomb": "friction", "LoadHistory": "friction",
    "LoadStep": "friction", "scalar_stick_slip": "functions",
    # the closed forms of contact mechanics a case is read against, and the rigid-indenter set-ups
    "hertz_line": "closed_forms", "hertz_sphere": "closed_forms", "hertz_pressure": "closed_forms",
    "cattaneo_line_case": "cattaneo", "mindlin_sphere_case": "cattaneo", "cattaneo_two_body_case": "cattaneo",
}
__all__ = list(_PUBLIC)
__getattr__, __dir__ = lazy(__name__, _PUBLIC)
