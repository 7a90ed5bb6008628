"""The one thing pyproject.toml cannot say: the registered cases, kept at the top of the
repository in cases/ (the layout of the design card), ship in the wheel as the package
``signorini_cases`` (a mapped package directory needs an explicit package list, which
pyproject's static ``packages.find`` cannot extend). Everything else is in pyproject.toml."""
from setuptools import find_packages, setup

setup(packages=[*find_packages(include=["harness", "harness.*"]), "signorini_cases"],
      package_dir={"signorini_cases": "cases"})
