# drillfatigue: `make repro` runs the DVC pipeline, `make test` checks the layering
# contracts (import-linter, pyproject.toml) and runs the tests.
# Both create .venv and install the pinned dependencies (requirements.lock) first.
PYTHON ?= $(shell command -v python3)
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
# dvc runs stage commands with `python`: put the venv first on PATH.
export PATH := $(CURDIR)/$(VENV)/bin:$(PATH)
export NUMBA_CACHE_DIR ?= $(CURDIR)/.numba_cache

.PHONY: install repro test bench bench-quick clean

$(STAMP): pyproject.toml requirements.lock
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -r requirements.lock
	$(PY) -m pip install -q --no-deps -e .
	touch $(STAMP)

install: $(STAMP)

repro: install
	$(VENV)/bin/dvc repro

test: install
	$(VENV)/bin/lint-imports
	$(PY) -m pytest -q

bench: install
	$(PY) benchmarks/run_all.py

bench-quick: install
	$(PY) benchmarks/run_all.py --quick

clean:
	rm -rf $(VENV) .numba_cache .pytest_cache
