# Two commands: `make demo` and `make test`. Both create .venv on first use.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test bench clean

$(BIN)/activate:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# the compiled core is rebuilt (incrementally, in build/) when its sources change
CORE := CMakeLists.txt $(wildcard cpp/src/*.cpp cpp/src/*.hpp cpp/include/armkit/*.hpp)

$(VENV)/.installed-demo: pyproject.toml $(CORE) | $(BIN)/activate
	$(BIN)/python -m pip install --quiet -e ".[sim]"
	touch $@

$(VENV)/.installed-test: pyproject.toml $(CORE) | $(BIN)/activate
	$(BIN)/python -m pip install --quiet -e ".[test]"
	touch $@

demo: $(VENV)/.installed-demo
	$(BIN)/armkit lab

test: $(VENV)/.installed-test
	$(BIN)/ruff check src tests benchmarks examples
	$(BIN)/python -m pytest -q

bench: $(VENV)/.installed-test
	$(BIN)/python -m pip install --quiet -e ".[bench]"
	$(BIN)/python benchmarks/run_all.py

clean:
	rm -rf $(VENV) build armkit-report .pytest_cache .hypothesis
