# Two entry points, each self-contained on a fresh machine with python3, make and git.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: report test install clean

$(STAMP): pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	touch $(STAMP)

install: $(STAMP)

## The main job: regenerate everything under reports/ from built-in data.
report: $(STAMP)
	$(BIN)/silcount report --out reports

## The test suite (meshes from ../shared/data when SILCOUNT_MESH_DIR is set).
test: $(STAMP)
	$(BIN)/python -m pytest -q

clean:
	rm -rf $(VENV) build *.egg-info
