"""What the report asks of the study: its computations and their cache (``cache``), the mesh and
degree studies (``mesh_study``, ``degree_study``), the parameter sweeps (``sweep``) and where its
minutes go (``timing``); the report's sections that show them are ``report.sections``. Not computing code: rewording a plan keeps every cached case (its
settings are part of each case's key, its source is not: ``study.storage.digest``)."""
