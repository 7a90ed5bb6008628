# Every target bootstraps .venv at the repository root; nothing else needs installing.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: test test-full lint report report-fine bench clean distclean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q

test-full: $(STAMP)
	$(PY) -m pytest -q -m ''

lint: $(STAMP)
	$(VENV)/bin/ruff check harness cases tests

report: $(STAMP)
	$(PY) -m harness report --profile default

report-fine: $(STAMP)
	$(PY) -m harness report --profile fine

bench: $(STAMP)
	$(PY) -m harness bench

clean:
	rm -rf results report

distclean: clean
	rm -rf $(VENV)
