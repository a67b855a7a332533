# `make run`: the default example; `make test`: the test suite.
# Both create .venv on first use and reinstall when pyproject.toml changes.

VENV := .venv
# python3.11 if it is installed and runs, else python3 (pyproject requires >= 3.11).
PYTHON ?= $(shell for candidate in python3.11 python3; do \
	  if $$candidate -c "" >/dev/null 2>&1; then echo $$candidate; break; fi; done)

.PHONY: run test clean

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)

# One stamp per install flavour: the stamp is newer than pyproject.toml until
# pyproject.toml changes, which triggers a reinstall.
$(VENV)/.installed: pyproject.toml | $(VENV)/bin/python
	$(VENV)/bin/python -m pip install --quiet -e .
	touch $@

$(VENV)/.installed-test: pyproject.toml | $(VENV)/bin/python
	$(VENV)/bin/python -m pip install --quiet -e '.[test]'
	touch $@

run: $(VENV)/.installed
	$(VENV)/bin/brushbem run examples/default.toml --out out/default

test: $(VENV)/.installed-test
	$(VENV)/bin/python -m pytest -q

clean:
	rm -rf out .pytest_cache .hypothesis
