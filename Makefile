# Quick start: `make demo` (set up, run the demo on bundled data) and `make test` (set up, run the tests).
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
PIP := $(VENV)/bin/pip
STAMP_CORE := $(VENV)/.installed-core
STAMP_ALL := $(VENV)/.installed-all
STAMP_ROS2_MSGS := $(VENV)/.installed-ros2-nav2_msgs $(VENV)/.installed-ros2-tf2_msgs
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

# Nav2's FollowPath / NavigateToPose / NavigateThroughPoses actions and SpeedLimit message (ros2/nav2_msgs/README.md)
# and tf2_msgs' TFMessage, the message of /tf and /tf_static (ros2/tf2_msgs/README.md): none has a wheel. Each is
# generated and compiled with the rosidl and ament_cmake wheels of the extra ros2 (no ROS installation; needs cmake,
# a C/C++ compiler and Python's headers) and installed into the venv like the message wheels: the Python package
# in its site-packages, the libraries in $(VENV)/lib (which the wheels' bootstrap puts on LD_LIBRARY_PATH).
# Each build is checked by importing it and comparing its type hashes with ROS 2 Jazzy's (the module CHECK_<pkg>).
ROS2_CMAKE := -DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DPython3_EXECUTABLE=$(abspath $(PY)) \
	-DCMAKE_PREFIX_PATH=$(abspath $(VENV)) -DCMAKE_INSTALL_PREFIX=$(abspath $(VENV))
CHECK_nav2_msgs := spcotmhp.ros.nav2_types
CHECK_tf2_msgs := spcotmhp.ros.tf_types
.SECONDEXPANSION:
$(VENV)/.installed-ros2-%: $(STAMP_ALL) ros2/%/CMakeLists.txt ros2/%/package.xml ros2/wheel_includes.cmake $$(wildcard ros2/$$*/*/*.*)
	@echo "building $* from ros2/$* (1-2 minutes; log: $(VENV)/build/$*.log)"
	@rm -rf $(VENV)/build/$* && mkdir -p $(VENV)/build/$*
	@(export AMENT_PREFIX_PATH=$(abspath $(VENV)) && cmake -S ros2/$* -B $(VENV)/build/$* $(ROS2_CMAKE) \
	  && cmake --build $(VENV)/build/$* -j 2 && cmake --install $(VENV)/build/$*) >$(VENV)/build/$*.log 2>&1 \
	  || (tail -30 $(VENV)/build/$*.log; echo "$* failed to build (log: $(VENV)/build/$*.log)"; exit 1)
	$(PY) -m $(CHECK_$*)
	touch $@

install: $(STAMP_CORE)
nav2-msgs: $(STAMP_ROS2_MSGS)
install-all: $(STAMP_ALL) $(STAMP_ROS2_MSGS) system-deps

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
