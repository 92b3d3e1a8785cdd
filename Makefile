# The two set-up commands of the README: `make demo` and `make test`.  Both create .venv.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
RESULTS ?= results
# What the vtk wheel loads at run time to render off-screen without a display: glvnd's EGL,
# Mesa's EGL vendor library and Mesa's software rasteriser (llvmpipe).
RENDER_DEBS := libegl1 libegl-mesa0 libgl1-mesa-dri

.PHONY: demo test bench work-precision clean render-libs

$(BIN)/python:
	$(PYTHON) -m venv $(VENV) || { \
	  echo "venv failed: installing Debian's python3-venv"; \
	  apt-get update -qq && apt-get install -y -qq python3-venv && $(PYTHON) -m venv $(VENV); }
	$(BIN)/python -m pip install -q --upgrade pip

$(VENV)/.installed-%: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[$*]"
	$(BIN)/fvslider compile
	touch $@

# Debian only (dpkg-query); elsewhere EGL or OSMesa must be installed by hand.
render-libs:
	@command -v dpkg-query >/dev/null || { echo "not Debian: install EGL or OSMesa"; exit 0; }; \
	missing=$$(for p in $(RENDER_DEBS); do \
	  dpkg-query -W -f='$${db:Status-Status}' $$p 2>/dev/null | grep -qx installed \
	  || echo $$p; done); \
	[ -z "$$missing" ] || { echo "VTK renders off-screen through EGL: installing" $$missing; \
	  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing; }

# Lint, format and type checks first (seconds), then the suite on every core (pytest-xdist:
# 14.7 min on one of this machine's two cores, 5.6 min on both, the numba cache warm).
test: render-libs $(VENV)/.installed-test
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/mypy
	$(BIN)/python -m pytest -q -n auto

demo: render-libs $(VENV)/.installed-all
	$(BIN)/fvslider reproduce --out $(RESULTS)

# One BLAS thread: the solvers' small dense products slow down by tens of times when
# OpenBLAS threads contend for the two cores (docs/sliders.md, "Cost").
bench: export OPENBLAS_NUM_THREADS = 1
bench: $(VENV)/.installed-all
	$(BIN)/python -m studies.bench --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_sweep --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_dynamics --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_engine --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_outputs --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_landing_gear --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_command --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_exact --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_exact_sliders --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_kinematics --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_campaign --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_modes --out $(RESULTS)/bench.json

# Run time against error (docs/performance.md, "Work-precision"): the peer first (Exudyn, the
# `peer` extra), then our grid, whose tables replace the ones in docs/performance.md.
work-precision: export OPENBLAS_NUM_THREADS = 1
work-precision: $(VENV)/.installed-all
	$(BIN)/python -m pip install -q -e ".[peer]"
	$(BIN)/python -m studies.peer_moving_load --out $(RESULTS)
	$(BIN)/python -m studies.work_precision --out $(RESULTS) --docs docs/performance.md

clean:
	rm -rf $(VENV) $(RESULTS) .pytest_cache .mypy_cache
