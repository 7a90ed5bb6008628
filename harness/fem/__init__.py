"""Stage 3, the discretisation: the assembled problem (``assembly``), element and Gamma_C
quadrature (``element_quadrature``, ``contact_quadrature``), the paper's discrete cones
(``cones``) and the penalty/Nitsche system (``weak_contact``). Imports ``mesh`` and ``problem``."""
