# Quick start: `make demo` (set up, run the demo on bundled data) and `make test` (set up, run the tests).
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
PIP := $(VENV)/bin/pip
STAMP_CORE := $(VENV)/.installed-core
STAMP_ALL := $(VENV)/.installed-all
STAMP_NAV2 := $(VENV)/.installed-nav2-msgs
NAV2_SRC := ros2/nav2_msgs
NAV2_BUILD := $(VENV)/build/nav2_msgs
DEBIAN_PKGS := chromium espeak-ng

.PHONY: demo test venv install install-all nav2-msgs system-deps bench clean

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PIP) install -q --upgrade pip

# the demo's install: the package and the extra 'server' (the demo's "next:" serves the model it learned);
# then every numba kernel is compiled into its on-disk cache, so the first demo or plan starts warm
$(STAMP_CORE): pyproject.toml | $(PY)
	$(PIP) install -q -e ".[server]"
	$(VENV)/bin/spcotmhp warmup
	touch $@

# the extra ros2's ros-rosidl-parser pulls lark-parser 0.12, which installs its files under the same top-level
# package `lark` as lark 1.x and may overwrite them (the instruction grammars then fail on a fresh machine):
# lark 1.x is put back whole (rosidl's parser, used only to build message types, works with it)
$(STAMP_ALL): pyproject.toml | $(PY)
	$(PIP) install -q -e ".[all]"
	$(PIP) install -q --force-reinstall --no-deps "lark>=1.2"
	$(VENV)/bin/spcotmhp warmup
	touch $@ $(STAMP_CORE)

# Nav2's FollowPath / NavigateToPose / NavigateThroughPoses actions and SpeedLimit message (ros2/nav2_msgs/README.md),
# generated and compiled with the rosidl and ament_cmake wheels of the extra ros2 (no ROS installation; needs cmake,
# a C/C++ compiler and Python's headers) and installed into the venv like the message wheels: the Python package
# nav2_msgs in its site-packages, the libraries in $(VENV)/lib (which the wheels' bootstrap puts on LD_LIBRARY_PATH).
# The build is checked by importing it and comparing its type hashes with Nav2 Jazzy's (spcotmhp/ros/nav2_types.py).
NAV2_CMAKE := -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DPython3_EXECUTABLE=$(abspath $(PY)) \
	-DCMAKE_PREFIX_PATH=$(abspath $(VENV)) -DCMAKE_INSTALL_PREFIX=$(abspath $(VENV))
$(STAMP_NAV2): $(STAMP_ALL) $(NAV2_SRC)/CMakeLists.txt $(NAV2_SRC)/package.xml $(wildcard $(NAV2_SRC)/*/*.*)
	@echo "building nav2_msgs from $(NAV2_SRC) (1-2 minutes; log: $(NAV2_BUILD).log)"
	@rm -rf $(NAV2_BUILD) && mkdir -p $(NAV2_BUILD)
	@(export AMENT_PREFIX_PATH=$(abspath $(VENV)) && cmake -S $(NAV2_SRC) -B $(NAV2_BUILD) $(NAV2_CMAKE) \
	  && cmake --build $(NAV2_BUILD) -j 2 && cmake --install $(NAV2_BUILD)) >$(NAV2_BUILD).log 2>&1 \
	  || (tail -30 $(NAV2_BUILD).log; echo "nav2_msgs failed to build (log: $(NAV2_BUILD).log)"; exit 1)
	$(PY) -m spcotmhp.ros.nav2_types
	touch $@

install: $(STAMP_CORE)
nav2-msgs: $(STAMP_NAV2)
install-all: $(STAMP_ALL) $(STAMP_NAV2) system-deps

# Debian packages the browser and speech tests need (installed only when missing and apt is usable).
system-deps:
	@missing=""; \
	command -v chromium >/dev/null 2>&1 || missing="$$missing chromium"; \
	command -v espeak-ng >/dev/null 2>&1 || missing="$$missing espeak-ng"; \
	if [ -n "$$missing" ]; then \
	  if command -v apt-get >/dev/null 2>&1 && [ "$$(id -u)" = 0 ]; then \
	    mkdir -p $(VENV); echo "installing$$missing (Debian packages for the browser and speech tests; log: $(VENV)/apt.log)"; \
	    (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq $$missing) \
	      >$(VENV)/apt.log 2>&1 \
	      || echo "warning: could not install$$missing (see $(VENV)/apt.log); the tests that need them will skip"; \
	  else echo "warning: missing$$missing (not root or no apt); the tests that need them will skip"; fi; \
	fi

demo: $(STAMP_CORE)
	$(VENV)/bin/spcotmhp demo --out demo-output --overwrite

# lint, format and type checks first (the project's habits, enforced: ruff and mypy settings in pyproject.toml)
test: install-all
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/mypy
	$(PY) -m pytest -q

bench: $(STAMP_ALL)
	$(PY) benchmarks/grid_search.py
	$(PY) benchmarks/learning.py
	$(PY) benchmarks/planning.py
	$(PY) benchmarks/scale.py
	$(PY) benchmarks/load_test.py
	$(PY) benchmarks/speech_accuracy.py

clean:
	rm -rf $(VENV) demo-output .pytest_cache
