# Two commands: `make demo` and `make test` (also `make test-fast`, `make fuzz`, `make bench`, `make figures`). All create .venv on first use.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin

.PHONY: demo test test-fast fuzz bench figures clean

$(BIN)/activate:
	@echo "==> creating the virtual environment $(VENV)"
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

# the compiled core is rebuilt (incrementally, in build/) when its sources change
CORE := CMakeLists.txt $(wildcard cpp/src/*.cpp cpp/src/*.hpp cpp/include/armkit/*.hpp)

# pip's own progress (downloads, then "Building editable for armkit": the C++ core, 1-3 minutes)
$(VENV)/.installed-demo: pyproject.toml $(CORE) | $(BIN)/activate
	@echo "==> installing armkit with MuJoCo and the viewer; the C++ core compiles at 'Building editable'"
	$(BIN)/python -m pip install --progress-bar on -e ".[sim,view,plot]"
	@# the [plan] extra's OMPL (wheels for Linux x86_64 and recent macOS arm64 only): without it the
	@# lab's experiment 7 says "not applicable"
	$(BIN)/python -m pip install --progress-bar on "ompl>=2.0" || echo "==> no OMPL wheel for this platform: the lab's experiment 7 (a planned motion) will say 'not applicable'"
	@echo "==> installed"
	touch $@

# the test install binds the core's test-only internals too (CMake's ARMKIT_TEST_BINDINGS, see CMakeLists.txt);
# it depends on this Makefile too, so that a checkout installed before that option was added builds it
$(VENV)/.installed-test: pyproject.toml Makefile $(CORE) | $(BIN)/activate
	@echo "==> installing armkit with the test extras (quietly; the C++ core compiles: 2-4 minutes)"
	$(BIN)/python -m pip install --quiet -e ".[test]" -Ccmake.define.ARMKIT_TEST_BINDINGS=ON
	touch $@

demo: $(VENV)/.installed-demo
	@echo "==> armkit lab: the seed experiments, each section as it finishes"
	$(BIN)/armkit lab

test: $(VENV)/.installed-test  # the whole suite, as CI runs it (.ci/run)
	$(BIN)/ruff check src tests benchmarks examples
	$(BIN)/python -m pytest -q

test-fast: $(VENV)/.installed-test  # the edit-test loop: no browser, no cluster, no slow runs, a small fuzz
	$(BIN)/ruff check src tests benchmarks examples
	ARMKIT_FUZZ_EXAMPLES=30 $(BIN)/python -m pytest -q -m "not slow and not browser"

fuzz: $(VENV)/.installed-test  # the fuzz and property tests (CLI, robot files, URDF, IK) with many more examples
	HYPOTHESIS_PROFILE=fuzz ARMKIT_FUZZ_EXAMPLES=20000 $(BIN)/python -m pytest -q tests/test_cli_fuzz.py \
		tests/test_ik_property.py tests/test_robot_file_fuzz.py tests/test_urdf.py tests/test_params.py \
		-k "fuzz or property or documents or mutated"
	ARMKIT_SWEEP_POSES=40 $(BIN)/python -m pytest -q tests/test_ik_singular_sweeps.py

bench: $(VENV)/.installed-test
	$(BIN)/python -m pip install --quiet -e ".[test,bench]" -Ccmake.define.ARMKIT_TEST_BINDINGS=ON
	$(BIN)/python benchmarks/run_all.py

figures: $(VENV)/.installed-test  # the README's and docs' figures from the current build (docs/figures.py)
	$(BIN)/python docs/figures.py

clean:
	rm -rf $(VENV) build armkit-report .pytest_cache .hypothesis
