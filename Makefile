# The two set-up commands of the README: `make demo` and `make test`.  Both create .venv.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
RESULTS ?= results

.PHONY: demo test bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV) || { \
	  echo "venv failed: installing Debian's python3-venv"; \
	  apt-get update -qq && apt-get install -y -qq python3-venv && $(PYTHON) -m venv $(VENV); }
	$(BIN)/python -m pip install -q --upgrade pip

$(VENV)/.installed-%: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[$*]"
	touch $@

test: $(VENV)/.installed-test
	$(BIN)/python -m pytest -q

demo: $(VENV)/.installed-all
	$(BIN)/fvslider reproduce --out $(RESULTS)

bench: $(VENV)/.installed-all
	$(BIN)/python -m studies.bench --out $(RESULTS)/bench.json
	$(BIN)/python -m studies.bench_sweep --out $(RESULTS)/bench.json

clean:
	rm -rf $(VENV) $(RESULTS) .pytest_cache
