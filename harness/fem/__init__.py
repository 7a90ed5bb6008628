"""Stage 3, the discretisation: the assembled problem (``assembly``), element and Gamma_C
quadrature (``element_quadrature``, ``contact_quadrature``), the paper's discrete cones
(``cones``) and the general rows of other cones (``edge_functionals``, ``face_means``), the weak
methods' contact laws (``contact_laws``), two bodies (``mortar``, ``two_body``), nested iteration
from level to level (``nested``) and the polynomial bases of high-order traces
(``polynomials``). Imports ``mesh`` and ``problem``."""
