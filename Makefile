# Two entry points, each self-contained on a fresh machine with python3, make and git.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

# Nothing is written into the source tree: numba's cache and Python's bytecode go under .venv.
export NUMBA_CACHE_DIR := $(CURDIR)/$(VENV)/cache/numba
export PYTHONPYCACHEPREFIX := $(CURDIR)/$(VENV)/cache/pycache

.PHONY: report test lint install clean

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test,lint]'
	touch $(STAMP)

install: $(STAMP)

## The main job: regenerate everything under reports/ from built-in data.
report: $(STAMP)
	$(BIN)/silcount report --out reports

## The test suite (meshes from ../shared/data when SILCOUNT_MESH_DIR is set).
test: $(STAMP)
	$(BIN)/python -m pytest -q

## ruff (lint and format check) and mypy on the package: zero findings.
lint: $(STAMP)
	$(BIN)/ruff check silcount tests scripts
	$(BIN)/ruff format --check silcount
	$(BIN)/mypy silcount

clean:
	rm -rf $(VENV) build *.egg-info
