"""Stage 2, the problem: what a case declares (``case``: the contract and its loading,
``geometry``, ``functions``: exact-solution helpers), its ``physics`` (every scalar/elastic and
2D/3D difference) and the checks of a case (``validate``). Imports only ``mesh``."""
