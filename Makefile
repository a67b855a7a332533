# `make run`: the default example; `make test`: the test suite.
# Both create .venv on first use and reinstall when pyproject.toml changes.

VENV := .venv
# python3.11 if it is installed and runs, else python3 (pyproject requires >= 3.11).
PYTHON ?= $(shell for candidate in python3.11 python3; do \
	  if $$candidate -c "" >/dev/null 2>&1; then echo $$candidate; break; fi; done)

.PHONY: run test test-fast docs clean chromium

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)

# One stamp per install flavour: the stamp is newer than pyproject.toml until
# pyproject.toml changes, which triggers a reinstall.
$(VENV)/.installed: pyproject.toml | $(VENV)/bin/python
	$(VENV)/bin/python -m pip install --quiet -e .
	touch $@

$(VENV)/.installed-docs: pyproject.toml | $(VENV)/bin/python
	$(VENV)/bin/python -m pip install --quiet -e '.[docs]'
	touch $@

$(VENV)/.installed-test: pyproject.toml | $(VENV)/bin/python
	$(VENV)/bin/python -m pip install --quiet -e '.[test]'
	touch $@

run: $(VENV)/.installed
	$(VENV)/bin/brushbem run examples/default.toml --out out/default --overwrite
	@echo "brushbem is installed in $(VENV): 'source $(VENV)/bin/activate' puts it on the PATH"

# The report test renders report.html in headless Chromium: install Debian's
# chromium when no such browser is on PATH (as root, with apt-get), else warn
# (the test is then skipped, or fails when BRUSHBEM_REQUIRE_CHROMIUM is set).
test: $(VENV)/.installed-test chromium
	$(VENV)/bin/python -m pytest -q -n auto -p no:cacheprovider

# The tests marked neither slow nor docs (the physics against closed forms on small grids, the
# configuration, the CLI), on every core (pytest-xdist); `make test` runs everything, also on
# every core (tests/conftest.py gives the workers back the default SIGINT handler that their
# interrupted-run tests need).
test-fast: $(VENV)/.installed-test
	$(VENV)/bin/python -m pytest -q -n auto -m "not slow and not docs" -p no:cacheprovider

# The documentation site into out/site (warnings are errors); open out/site/index.html.
docs: $(VENV)/.installed-docs
	$(VENV)/bin/python -m mkdocs build --strict

chromium:
	@if command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 \
	  || command -v google-chrome >/dev/null 2>&1; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	  echo "installing chromium (headless report test)"; \
	  (timeout 600 apt-get install -y --no-install-recommends chromium \
	   || (timeout 300 apt-get update && timeout 600 apt-get install -y --no-install-recommends chromium)) \
	  || echo "warning: could not install chromium; the headless report test will be skipped" >&2; \
	else \
	  echo "warning: no chromium on PATH and cannot apt-get install it (not root or no apt-get);" \
	    "the headless report test will be skipped (it fails when BRUSHBEM_REQUIRE_CHROMIUM is set)" >&2; \
	fi

clean:
	rm -rf out .pytest_cache .hypothesis
