# Two commands: `make demo` and `make test`. Both create .venv on first use.
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

fuzz: $(VENV)/.installed-test  # the parser fuzz tests (robot files, URDF) with 20,000 examples each
	ARMKIT_FUZZ_EXAMPLES=20000 $(BIN)/python -m pytest -q tests/test_robot_file_fuzz.py tests/test_urdf.py -k "documents or mutated"

bench: $(VENV)/.installed-test
	$(BIN)/python -m pip install --quiet -e ".[bench]"
	$(BIN)/python benchmarks/run_all.py

clean: clean-cache
	rm -rf $(VENV) armkit-report .pytest_cache .hypothesis

clean-cache:  # numba's compiled kernels (after editing one: see docs/architecture.md)
	rm -rf .numba-cache
	find src -name "*.nbi" -delete -o -name "*.nbc" -delete
