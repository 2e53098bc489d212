# armlab: `make run` sets everything up and reproduces every paper into out/; `make test` runs the tests.
SHELL := /bin/bash
VENV := .venv
BIN := $(VENV)/bin
# python3.12: on PATH, or any pyenv 3.12 (pyenv shims answer even when 3.12 is not selected)
PYTHON ?= $(shell for p in python3.12 $$HOME/.pyenv/versions/3.12*/bin/python3.12 /usr/local/bin/python3.12 /usr/bin/python3.12; do \
	"$$p" -c 'import sys; assert sys.version_info[:2] == (3, 12)' >/dev/null 2>&1 && { echo "$$p"; break; }; done)
# system packages as package:command — graphviz's `dot` draws the diagrams, headless Chromium checks the replays
RUN_PACKAGES := graphviz:dot
TEST_PACKAGES := $(RUN_PACKAGES) chromium:chromium

.PHONY: run test check setup run-deps test-deps lint bench clean typecheck docs lock

run: setup run-deps
	$(BIN)/armlab reproduce --out out

test: setup test-deps
	$(BIN)/ruff check .
	$(MAKE) typecheck
	$(BIN)/pytest -q

# the quick subset while working: the numbers, the API, the bad inputs (no slow, browser, cluster or process tests)
check: setup
	$(BIN)/ruff check .
	$(BIN)/pytest -q -m "not slow and not browser and not cluster and not process"

setup: $(VENV)/.installed

# the exact versions the suite last passed with (constraints.txt, refreshed by `make lock`)
CONSTRAINTS := -c constraints.txt

$(VENV)/.installed: pyproject.toml constraints.txt
	@if [ -z "$(PYTHON)" ]; then echo "armlab needs Python 3.12: install it (e.g. 'pyenv install 3.12' or 'apt-get install python3.12') and re-run"; exit 1; fi
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet $(CONSTRAINTS) -e '.[test]'
	@touch $@

# The system packages $(1) (package:command pairs): installed when missing and running as root, else named.
define system_deps
	@missing=""; for pair in $(1); do command -v $${pair#*:} >/dev/null || missing="$$missing $${pair%%:*}"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing system packages:$$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null; \
	  else echo "armlab needs system packages:$$missing — run: sudo apt-get install -y$$missing"; exit 1; fi; \
	fi
endef

run-deps:
	$(call system_deps,$(RUN_PACKAGES))

test-deps:
	$(call system_deps,$(TEST_PACKAGES))

lint: setup
	$(BIN)/ruff check .

# the documentation site, built offline into build/docs/html (a fast reproduction of every paper for the paper
# pages, the notebooks executed); warnings are errors
docs: setup run-deps
	$(BIN)/sphinx-build -W --keep-going -q -b html docs build/docs/html
	@echo "docs: build/docs/html/index.html"

bench: setup
	$(BIN)/python -m pip install --quiet $(CONSTRAINTS) -e '.[test,bench]'
	$(BIN)/python scripts/bench/bench_kinematics.py
	# one BLAS thread: a solve is small matrices, and OpenBLAS threads left waiting by the previous call (Drake, the
	# toolbox) on a loaded machine add tens of ms of wall time to the next (CPU time unchanged)
	OPENBLAS_NUM_THREADS=1 $(BIN)/python scripts/bench/bench_ik.py
	$(BIN)/python scripts/bench/bench_simulate.py
	$(BIN)/python scripts/bench/bench_plan.py
	$(BIN)/python scripts/bench/bench_planner.py
	$(BIN)/python scripts/bench/bench_analysis.py
	$(BIN)/python scripts/bench/bench_reproduce.py
	$(BIN)/python scripts/bench/bench_drives.py
	$(BIN)/python scripts/bench/bench_collision.py
	$(BIN)/python scripts/bench/bench_replay.py

# constraints.txt afresh: the newest versions within pyproject.toml's ranges, resolved in a scratch environment
# (build/lock); run `make test` with them before committing the file
LOCK := build/lock
lock:
	@if [ -z "$(PYTHON)" ]; then echo "armlab needs Python 3.12: install it (e.g. 'pyenv install 3.12') and re-run"; exit 1; fi
	rm -rf $(LOCK) && $(PYTHON) -m venv $(LOCK)
	$(LOCK)/bin/python -m pip install --quiet --upgrade pip
	$(LOCK)/bin/python -m pip install --quiet -e '.[test,bench]'
	{ sed -n '/^#/p' constraints.txt; $(LOCK)/bin/python -m pip freeze --exclude-editable; } > $(LOCK)/constraints.txt
	mv $(LOCK)/constraints.txt constraints.txt && rm -rf $(LOCK)
	@echo "constraints.txt refreshed: now run make test"

clean:
	rm -rf $(VENV) out *.egg-info

# mypy on the package. It cannot follow [tool.setuptools.package-dir] (models/ is armlab.models, ...), so it checks
# a link tree made afresh from that mapping: build/typecheck/armlab/ holds a link to each entry of armlab/ and one
# to each subpackage's folder. Its cache stays in build/typecheck/.mypy_cache between runs.
TYPECHECK := build/typecheck
typecheck: setup
	rm -rf $(TYPECHECK)/armlab && mkdir -p $(TYPECHECK)/armlab
	$(BIN)/python -c 'import tomllib; [print(k, v) for k, v in tomllib.load(open("pyproject.toml", "rb"))["tool"]["setuptools"]["package-dir"].items()]' | \
	while read package folder; do \
	  if [ "$$package" = armlab ]; then \
	    for entry in $$folder/*; do [ "$${entry##*/}" = __pycache__ ] || ln -s $(CURDIR)/$$entry $(TYPECHECK)/armlab/; done; \
	  else ln -s $(CURDIR)/$$folder $(TYPECHECK)/$${package//.//}; fi; \
	done
	cd $(TYPECHECK) && $(CURDIR)/$(BIN)/mypy --config-file $(CURDIR)/pyproject.toml -p armlab
