"""The level chain of a case and its methods: how its levels are set up and walked (``run``:
``run_chain``, the profiles' levels, which methods a case's chain runs; ``walk``: one level
after another, resumable), meshed, discretised and solved (``one_body``, ``two_body``), made into
rows (``rows``) and said in words (``outcome``), and what the report draws of them collected on
the way (``snapshots``). The computing code of the study: its source is part of the cache digest
(``study.storage.digest``)."""
from .rows import study_levels
from .run import PROFILES, BothHooks, chain_levels, chain_methods, is_reference, run_chain

__all__ = ["PROFILES", "BothHooks", "chain_levels", "chain_methods", "is_reference", "run_chain", "study_levels"]
