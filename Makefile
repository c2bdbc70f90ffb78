# Two set-up commands: `make demo` and `make test`. Both create .venv on first use and
# reinstall the project only when pyproject.toml changes.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
PEERS  := $(VENV)/.peers
# setuptools prints a notice about editable installs that concerns folders named as the
# package; optraj's folders are the package (pyproject.toml's package-dir), so it is hidden.
QUIET  := PYTHONWARNINGS="ignore:Editable installation"

.PHONY: demo test bench fuzz lint clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(QUIET) $(BIN)/python -m pip install --quiet -e '.[test,examples,sweeps,viz]'
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/optraj demo

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/python scripts/typecheck.py
	$(BIN)/python -m pytest -n auto --dist loadfile --no-loadscope-reorder

# The peers that benchmarks/peers.py times optraj against; only `make bench` needs them.
$(PEERS): pyproject.toml $(STAMP)
	$(QUIET) $(BIN)/python -m pip install --quiet -e '.[peers]'
	touch $(PEERS)

bench: $(STAMP) $(PEERS)
	$(BIN)/python benchmarks/run_all.py --out benchmarks/results --readme

# 100,000 fuzz cases from a fixed seed (FUZZ_SEED, FUZZ_CASES override), under 10 min on
# 2 cores; rewrites benchmarks/results/fuzz.md.
fuzz: $(STAMP)
	$(BIN)/python benchmarks/fuzz.py --out benchmarks/results

lint: $(STAMP)
	$(BIN)/ruff check --fix .
	$(BIN)/ruff format .

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache .ruff_cache
