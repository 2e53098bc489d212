# armlab: `make run` sets everything up and reproduces every paper into out/; `make test` runs the tests.
SHELL := /bin/bash
VENV := .venv
BIN := $(VENV)/bin
# python3.12: on PATH, or any pyenv 3.12 (pyenv shims answer even when 3.12 is not selected)
PYTHON ?= $(shell for p in python3.12 $$HOME/.pyenv/versions/3.12*/bin/python3.12 /usr/local/bin/python3.12 /usr/bin/python3.12; do \
	"$$p" -c 'import sys; assert sys.version_info[:2] == (3, 12)' >/dev/null 2>&1 && { echo "$$p"; break; }; done)
SYSTEM_PACKAGES := graphviz:dot chromium:chromium

.PHONY: run test setup system-deps lint bench clean

run: setup system-deps
	$(BIN)/armlab reproduce --out out

test: setup system-deps
	$(BIN)/ruff check .
	$(BIN)/pytest -q

setup: $(VENV)/.installed

$(VENV)/.installed: pyproject.toml
	@if [ -z "$(PYTHON)" ]; then echo "armlab needs Python 3.12: install it (e.g. 'pyenv install 3.12' or 'apt-get install python3.12') and re-run"; exit 1; fi
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test]'
	@touch $@

# graphviz's `dot` (diagram SVGs) and headless Chromium (replay tests): installed when missing and root.
system-deps:
	@missing=""; for pair in $(SYSTEM_PACKAGES); do command -v $${pair#*:} >/dev/null || missing="$$missing $${pair%%:*}"; done; \
	if [ -n "$$missing" ]; then \
	  if [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null; then \
	    echo "installing system packages:$$missing"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing >/dev/null; \
	  else echo "armlab needs system packages:$$missing — run: sudo apt-get install -y$$missing"; exit 1; fi; \
	fi

lint: setup
	$(BIN)/ruff check .

bench: setup system-deps
	$(BIN)/python scripts/bench_kinematics.py
	$(BIN)/python scripts/bench_simulate.py

clean:
	rm -rf $(VENV) out *.egg-info
