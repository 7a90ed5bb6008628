# Every target bootstraps .venv at the repository root; nothing else needs installing.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: test test-full test-scale lint report report-fine report-codes readme-figure bench docs codes clean distclean

$(STAMP): pyproject.toml setup.py
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

# the report's jobs and the tests on one process per core (one NGSolve thread each); on one core, in this process
WORKERS ?= $(shell nproc 2>/dev/null || echo 1)
ENGINE  := $(if $(filter 1,$(WORKERS)),,--workers $(WORKERS))
# pytest-xdist, a test file per worker (a module's fixtures are made once)
XDIST   := $(if $(filter 1,$(WORKERS)),,-n $(WORKERS) --dist loadfile)

test: $(STAMP)
	$(PY) -m pytest -q $(XDIST)

# MARKERS: a pytest marker expression; .ci/run leaves out the tutorials, which its `make docs` has
# just executed (sphinx-gallery)
MARKERS ?=
test-full: $(STAMP)
	$(PY) -m pytest -q -m '$(MARKERS)' $(XDIST)

# the acceptance checks of earlier issues at 5e5 to 1e6 dofs (marker `scale`; .ci/run leaves them
# out to keep its 25 minutes, and the fine report computes the same rows)
test-scale: $(STAMP)
	$(PY) -m pytest -q -m scale $(XDIST)

lint: $(STAMP)
	$(VENV)/bin/ruff check harness cases tests docs examples

report: $(STAMP)
	$(PY) -m harness report --profile default $(ENGINE)

report-fine: $(STAMP)
	$(PY) -m harness report --profile fine $(ENGINE)

# the README's figure: the last default report's verdict matrix, the caption naming the version
# that computed it (results/provenance.json); run after `make report`, with every release
readme-figure: $(STAMP)
	$(PY) docs/_ext/readme_figure.py

bench: $(STAMP)
	$(PY) -m harness bench

# the documentation site (Sphinx + MyST), warnings as errors: docs/_build/html/index.html
DOCS_STAMP := $(VENV)/.docs-installed
$(DOCS_STAMP): $(STAMP) pyproject.toml
	$(PY) -m pip install --quiet -e '.[docs]'
	touch $(DOCS_STAMP)

docs: $(DOCS_STAMP)
	$(PY) -m sphinx -W --keep-going -q -b html docs docs/_build/html

# the other finite element codes of examples/codes (`harness export`, `external:DIR`), each in its
# own environment, as a user's code would be: DOLFINx's binary wheel needs Python >= 3.12 (pyenv's,
# called by its path: the `python3.12` shim answers only where pyenv selects 3.12)
CODES_PYTHON ?= $(firstword $(wildcard $(HOME)/.pyenv/versions/3.12*/bin/python3.12) $(shell command -v python3.12))
.venv-%/.installed: examples/codes/requirements-%.txt
	$(CODES_PYTHON) -m venv .venv-$*
	.venv-$*/bin/python -m pip install --quiet --upgrade pip
	.venv-$*/bin/python -m pip install --quiet -r $<
	touch $@

codes: .venv-dolfinx/.installed .venv-skfem/.installed

# the report with other codes beside the harness (its section "Other codes"): transition-r32 and
# elastic-transition-r32 exported, solved by DOLFINx (nodal, Nitsche) and scikit-fem (nodal), and
# measured with the harness's nodal and nitsche; into results/codes and report/codes
CODES_CASES  := transition-r32 elastic-transition-r32
CODES_LEVELS ?= 6
report-codes: $(STAMP) codes
	rm -rf results/codes/solutions
	for c in $(CODES_CASES); do \
	  $(PY) -m harness export --case $$c --levels $(CODES_LEVELS) --out results/codes/export/$$c --quiet && \
	  .venv-dolfinx/bin/python examples/codes/dolfinx_contact.py results/codes/export/$$c results/codes/solutions/dolfinx-nodal/$$c --model nodal && \
	  .venv-dolfinx/bin/python examples/codes/dolfinx_contact.py results/codes/export/$$c results/codes/solutions/dolfinx-nitsche/$$c --model nitsche && \
	  .venv-skfem/bin/python examples/codes/skfem_contact.py results/codes/export/$$c results/codes/solutions/skfem-nodal/$$c || exit 1; \
	done
	$(PY) -m harness report $(foreach c,$(CODES_CASES),--case $(c)) --method nodal --method nitsche \
	  $(foreach m,dolfinx-nodal dolfinx-nitsche skfem-nodal,--method external:results/codes/solutions/$(m)) \
	  --levels $(CODES_LEVELS) --results results/codes --report report/codes $(ENGINE)

clean:
	rm -rf results report

distclean: clean
	rm -rf $(VENV) .venv-dolfinx .venv-skfem
