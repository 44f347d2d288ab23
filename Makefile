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
# mkdocs-material prints a banner about its successor on every build
export NO_MKDOCS_2_WARNING := 1

.PHONY: install repro test browser postgres serve lint types imports docs docs-serve pytest warm-sim warm-models bench bench-quick clean

# pip compiles the installed modules' bytecode on one core (43 s of a 79 s install
# here); compileall on every core takes 29 s, and compiles the package's own
# sources too. Bytecode is needed: with PYTHONDONTWRITEBYTECODE set (as on CI)
# nothing writes it on import, and every process would compile its imports'
# sources again (0.25 s of each command's 1.45 s start for the package alone).
# Files that do not compile (a package's Python 2 examples) are skipped, as pip
# skips them.
$(STAMP): pyproject.toml requirements.lock
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q --no-compile -r requirements.lock
	$(PY) -m pip install -q --no-compile --no-deps -e .
	-$(PY) -m compileall -q -j 0 "$$($(PY) -c 'import sysconfig; print(sysconfig.get_path("purelib"))')" src >/dev/null
	touch $(STAMP)

install: $(STAMP)

repro: install
	$(VENV)/bin/dvc repro

# CI runs `make test`: lint, types, the import contract, the docs build
# (warnings are errors) and the test suite, within the 10-minute budget.
# `browser` and `postgres` install the system packages the tests drive.
# numba's cache is filled first (tests/testkit/warm_numba.py: the simulator on one
# core, the fatigue kernels and the tiny surrogate on the other, the static checks
# beside them), so no two test processes compile the same kernels.
test: browser postgres
	@$(MAKE) --no-print-directory -j 3 warm-sim warm-models lint types imports docs
	@DRILLFATIGUE_TESTS_WARMED=1 $(MAKE) --no-print-directory pytest

warm-sim warm-models: install
	PYTHONPATH=tests $(PY) -m testkit.warm_numba $(@:warm-%=%)

lint: install
	$(VENV)/bin/ruff check .

types: install
	$(VENV)/bin/mypy

# The import-linter contracts, when the project declares them (.importlinter
# or [tool.importlinter] in pyproject.toml).
imports: install
	@if [ -f .importlinter ] || grep -q '^\[tool.importlinter\]' pyproject.toml; then \
		PYTHONPATH=src $(VENV)/bin/lint-imports; \
	else echo "imports: no import-linter contract declared"; fi

docs: install
	$(VENV)/bin/mkdocs build --strict --site-dir site

docs-serve: install
	$(VENV)/bin/mkdocs serve

# One worker per core, at most 4 (each holds its compiled kernels, ~1.5 GB at
# peak; a third worker on 2 cores made the suite slower, 498 s against 442 s);
# a test file stays on one worker, so module fixtures are built once.
PYTEST_WORKERS ?= $(shell n=$$(nproc 2>/dev/null || echo 1); [ $$n -gt 4 ] && n=4; echo $$n)
pytest: install
	$(PY) -m pytest -q -n $(PYTEST_WORKERS) --dist loadfile

# the web-page test drives a real headless Chromium: install it (as root, CI) when missing
browser:
	@command -v chromium >/dev/null && command -v chromedriver >/dev/null || \
	  { apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium chromium-driver; }

# the ledger's tests start a throwaway PostgreSQL server from the system's
# packages (tests/ledger/conftest.py): install it (as root, CI) when missing
postgres:
	@ls /usr/lib/postgresql/*/bin/initdb >/dev/null 2>&1 || command -v initdb >/dev/null || \
	  { apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q postgresql; }

# the digital twin's API and web page on http://127.0.0.1:8000/
MODEL ?= data/surrogate/model
serve: install
	$(VENV)/bin/drillfatigue serve --model $(MODEL)

bench: install
	$(PY) benchmarks/run_all.py

bench-quick: install
	$(PY) benchmarks/run_all.py --quick

clean:
	rm -rf $(VENV) .numba_cache .pytest_cache .mypy_cache .ruff_cache site
