# Every target sets itself up from nothing: a local virtual environment with the package installed.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test bench notebooks clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

## make demo: the main job on the built-in default scene (for now: the thin-film plots).
demo: $(STAMP)
	$(PY) -m bubbleoptics.demo

## make test: the whole test suite, including every notebook in quick mode.
test: $(STAMP)
	BUBBLEOPTICS_QUICK=1 $(PY) -m pytest -q

## make bench: the speed benchmarks (not part of the tests; results go to data/derived/).
bench: $(STAMP)
	$(PY) benchmarks/optics_speed.py

clean:
	rm -rf $(VENV) build *.egg-info demo-output
