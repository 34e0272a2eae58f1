# Two commands: `make demo` and `make test` (also `make fuzz`, `make bench`). All create .venv on first use.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test fuzz bench clean clean-cache

$(BIN)/activate:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed-demo: pyproject.toml | $(BIN)/activate
	$(BIN)/python -m pip install --quiet -e ".[sim]"
	touch $@

$(VENV)/.installed-test: pyproject.toml | $(BIN)/activate
	$(BIN)/python -m pip install --quiet -e ".[test]"
	touch $@

demo: $(VENV)/.installed-demo
	$(BIN)/armkit lab

test: $(VENV)/.installed-test
	$(BIN)/ruff check src tests benchmarks examples
	$(BIN)/python -m pytest -q

fuzz: $(VENV)/.installed-test  # the CLI fuzz tests with many more random argument lists
	HYPOTHESIS_PROFILE=fuzz $(BIN)/python -m pytest -q tests/test_cli_fuzz.py

bench: $(VENV)/.installed-test
	$(BIN)/python -m pip install --quiet -e ".[bench]"
	$(BIN)/python benchmarks/run_all.py

clean: clean-cache
	rm -rf $(VENV) armkit-report .pytest_cache .hypothesis

clean-cache:  # numba's compiled kernels (after editing one: see docs/architecture.md)
	rm -rf .numba-cache
	find src -name "*.nbi" -delete -o -name "*.nbc" -delete
