# Two entry points, each self-contained on a fresh machine with python3, make and git.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

# The shared inputs beside the repository (read-only; override any of them in the environment).
export SILCOUNT_SCENE_DIR ?= $(abspath $(CURDIR)/../shared/scenes)
export SILCOUNT_CORPUS_DIR ?= $(abspath $(CURDIR)/../shared/corpus)
export SILCOUNT_PAPERS_DIR ?= $(abspath $(CURDIR)/../shared/papers)

# Nothing is written into the source tree: numba's cache and Python's bytecode go under .venv.
export NUMBA_CACHE_DIR := $(CURDIR)/$(VENV)/cache/numba
export PYTHONPYCACHEPREFIX := $(CURDIR)/$(VENV)/cache/pycache
export HYPOTHESIS_STORAGE_DIRECTORY := $(CURDIR)/$(VENV)/cache/hypothesis

.PHONY: report test lint install clean mutation

$(STAMP): pyproject.toml constraints.txt
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -c constraints.txt -e '.[test,lint,gl]'
	@echo "byte-compiling the venv and silcount into $(PYTHONPYCACHEPREFIX) (imports cannot when PYTHONDONTWRITEBYTECODE is set)"
	$(BIN)/python -m compileall -q -j 0 $(VENV)/lib silcount
	@echo "compiling numba's kernels into $(NUMBA_CACHE_DIR) (once; about 80 s)"
	$(BIN)/silcount audit data/icosphere4.obj --variant both --quiet --format json --out $(VENV)/warm-up.json
	touch $(STAMP)

install: $(STAMP)

## The main job: regenerate everything under reports/ from built-in data, then the literature's claims, a paper
## given as data (examples/literature-paper/), read with --paper as a user's paper is.
## numpy and OpenBLAS pick their kernels by the CPU, and the AVX-512 ones round differently in the last bits
## (the corpus fits' Akaike weights; a worst-case search that then finds 545 outputs instead of 548): on x86-64
## the report runs on their AVX2 kernels, so that any x86-64-v3 machine writes the same bytes (an AMD EPYC
## without AVX-512 and an Intel Xeon with it do; docs/evidence.md).
ifeq ($(shell uname -m),x86_64)
report: export NPY_DISABLE_CPU_FEATURES := X86_V4 AVX512_ICL AVX512_SPR
report: export OPENBLAS_CORETYPE := Haswell
endif
report: $(STAMP)
	$(BIN)/silcount report --out reports
	$(BIN)/silcount claims --paper examples/literature-paper --no-render --out reports/literature-paper
	$(BIN)/python scripts/readme_findings.py

## The test suite (meshes from ../shared/data when SILCOUNT_MESH_DIR is set).
test: $(STAMP)
	$(BIN)/python -m pytest -q

## ruff (lint and format check) and mypy on the package, the scripts and the benchmarks: zero findings.
lint: $(STAMP)
	$(BIN)/ruff check silcount tests scripts benchmarks
	$(BIN)/ruff format --check silcount scripts benchmarks
	$(BIN)/mypy silcount scripts benchmarks

## Mutation testing (slow, not part of CI): mutmut 2 over the detectors, the counting layer (arithmetic, the
## cost-model loader models.py, cycles) and the re-derivation (papers/formulas.py), each module judged by its own
## hand-counted tests (scripts/mutation.py holds the selection).  mutmut edits the tree in place and restores it.
## MUTATE="<module> ..." narrows the run.
MUTATE ?=
mutation: $(STAMP)
	$(BIN)/python -m pip install --quiet -c constraints.txt 'mutmut>=2.4,<3'
	$(BIN)/python scripts/mutation.py $(MUTATE)

clean:
	rm -rf $(VENV) build *.egg-info
