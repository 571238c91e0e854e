# Every target sets itself up from nothing: a local virtual environment with the package installed.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
# the package alone (what `make demo` needs, as a user's install), then the test extras on top
BASE   := $(VENV)/.installed-base
STAMP  := $(VENV)/.installed
# The studies (study/: analyses of the optics and the tracer for the benchmarks, notebooks and
# paper) are not part of the wheel; the checkout's root goes on the venv's path so they import.
CHECKOUT_PTH = $(PY) -c 'import pathlib, sysconfig; pathlib.Path(sysconfig.get_paths()["purelib"], "bubbleoptics-checkout.pth").write_text("$(CURDIR)\n")'

.PHONY: demo test chromium bench paper clean clean-cache activate

$(BASE): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet -e .
	$(CHECKOUT_PTH)
	touch $(BASE)

$(STAMP): $(BASE)
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

## make demo: the main job: render the built-in bubble scene (960x960), plus the thin-film plots.
## The plots and the render run side by side (the first render's compile is one core's work).
demo: $(BASE)
	mkdir -p demo-output
	$(PY) -m bubbleoptics.demo --out demo-output & plots=$$!; \
	$(PY) -m tracer image demo-output/bubbles.png; status=$$?; \
	wait $$plots && exit $$status
	@echo "$(CURDIR)/demo-output/bubbles.png"

## make activate: print the line that puts `tracer` (and the venv's python) on this shell's PATH.
activate: $(BASE)
	@echo "source $(CURDIR)/$(VENV)/bin/activate"

## make test: the whole test suite, including every notebook in quick mode, on two workers
## (pytest-xdist; each compiles what it needs into numba's shared on-disk cache).
## The scene editor's browser tests drive the system's Chromium (no browser download): when it is
## missing and this runs as root on Debian/Ubuntu, it is installed with apt-get; otherwise those
## tests skip with one line saying how to get it (and fail under CI, where they must run).
test: $(STAMP) chromium
	BUBBLEOPTICS_QUICK=1 $(PY) -m pytest -q -n 2

chromium:
	@if command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 \
	    || [ -n "$$TRACER_CHROMIUM" ]; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing Debian's chromium for the editor's browser tests (apt-get)"; \
	    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; \
	else \
	    echo "no chromium: the editor's browser tests will skip (sudo apt-get install chromium, or set TRACER_CHROMIUM)"; \
	fi

## make bench: the speed benchmarks (not part of the tests; results go to data/derived/), with
## Mitsuba 3 as the peer on a glass sphere (installed here, the `mitsuba` extra).
bench: export NUMBA_THREADING_LAYER ?= workqueue
bench: $(STAMP)
	$(PY) -m pip install --quiet -e '.[mitsuba]'
	$(PY) benchmarks/machine.py
	# the optics on numba's default layer, what a library caller gets (optics_speed.py says why)
	NUMBA_THREADING_LAYER=default $(PY) benchmarks/optics_speed.py
	$(PY) benchmarks/coursework_table.py
	$(PY) benchmarks/coursework_rays.py
	$(PY) benchmarks/bandlimited_colour.py
	$(PY) benchmarks/stability.py
	$(PY) benchmarks/time_vs_error.py
	$(PY) benchmarks/throughput.py
	$(PY) benchmarks/energy.py
	$(PY) benchmarks/two_beam_render.py
	$(PY) benchmarks/editor_latency.py
	$(PY) benchmarks/mesh_scale.py
	$(PY) benchmarks/output_memory.py
	$(PY) benchmarks/movie.py
	$(PY) benchmarks/film_flow.py
	$(PY) benchmarks/film_flow_verification.py
	$(PY) benchmarks/peer_mitsuba.py

## make paper: every figure, table and number from data/, then paper/paper.pdf (needs LaTeX, see README).
paper: $(STAMP)
	$(MAKE) -C paper PYTHON=$(CURDIR)/$(PY)

## numba's on-disk cache is keyed on each function's own file, not on the kernels it calls in
## other modules: after editing a kernel, clear it (a fresh clone never has one).
clean-cache:
	find . -name '*.nbi' -delete -o -name '*.nbc' -delete

clean: clean-cache
	-$(MAKE) -C paper clean
	rm -rf $(VENV) build *.egg-info demo-output

## make peers: Blender's Cycles for the peer benchmark, in its own venv .venv-cycles (bpy 5.0.1
## needs numpy < 2, this project numpy >= 2, so it cannot be an extra; docs/peers.md). ~370 MB.
CYCLES_VENV ?= .venv-cycles
CYCLES_BASE_PYTHON ?= python3.11  # bpy 5.0.1 wheels exist for Python 3.11 only
peers: $(CYCLES_VENV)/bin/python
	@$(CYCLES_VENV)/bin/python -c "import bpy; print('bpy', bpy.app.version_string)"

$(CYCLES_VENV)/bin/python:
	$(CYCLES_BASE_PYTHON) -m venv $(CYCLES_VENV)
	$(CYCLES_VENV)/bin/pip install --quiet bpy==5.0.1

## make bench-peers: our tracer against Cycles (data/derived/peer_cycles*.csv/.npz; ~15 minutes).
bench-peers: $(STAMP) peers
	BUBBLEOPTICS_CYCLES_PYTHON=$(CURDIR)/$(CYCLES_VENV)/bin/python $(PY) benchmarks/peer_cycles.py

.PHONY: peers bench-peers
