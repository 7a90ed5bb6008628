"""Stage 1, meshes: level sequences (``levels``: uniform refinement; mesh strategies go here),
the trace of T_h on Gamma_C (``trace``), the sides of a 2D mesh as arrays (``sides``), point
evaluation (``points``). Imports no stage of the harness."""
from ..core.lazy import lazy

# The mesh-strategy protocol and what a strategy of your own builds on (``examples/meshes/``),
# imported when first used: `import harness.mesh` costs no NGSolve.
_PUBLIC = {
    "Strategy": "strategies", "MeshStrategy": "strategies", "singular_points": "strategies",
    "singular_lines": "strategies", "element_budget": "strategies",
    "Level": "levels", "LevelSequence": "levels", "UniformRefinement": "levels",
    "GradedRefinement": "bisection", "AdaptiveRefinement": "bisection", "dorfler": "bisection",
    "HpRefinement": "hp",
}
__all__ = list(_PUBLIC)
__getattr__, __dir__ = lazy(__name__, _PUBLIC)
