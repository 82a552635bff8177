# frontier_rl: `make demo` and `make test` work on a fresh clone with only Python 3.11 (`make test` also
# needs cmake and a C/C++ compiler, for the ROS 2 interfaces).
PYTHON ?= python3.11
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
# ROS 1 from Debian's own packages, for the frontier node and its test against a real roscore
ROS_APT := ros-core python3-rospy python3-nav-msgs python3-geometry-msgs python3-visualization-msgs \
           python3-std-msgs python3-tf2-ros
ROS_CHECK := command -v roscore >/dev/null && /usr/bin/python3 -c "import rospy, nav_msgs.msg, geometry_msgs.msg, visualization_msgs.msg" 2>/dev/null
# Chromium from Debian, for the test that renders the HTML report as a reader's browser does
BROWSER_APT := chromium chromium-driver
BROWSER_CHECK := command -v chromium >/dev/null && command -v chromedriver >/dev/null
# ROS 2 (Kilted) from PyPI's wheels: what tools/build_ros2_interfaces.py needs to generate the vendored nav2_msgs
# (frontier_rl/ros2/interfaces) with cmake and a C/C++ compiler; rclpy and the message wheels come with the ros2 extra
ROS2_WHEELS := ros-kilted-ament-cmake ros-kilted-ament-cmake-core ros-kilted-ament-cmake-export-definitions \
               ros-kilted-ament-cmake-export-dependencies ros-kilted-ament-cmake-export-include-directories \
               ros-kilted-ament-cmake-export-interfaces ros-kilted-ament-cmake-export-libraries \
               ros-kilted-ament-cmake-export-link-flags ros-kilted-ament-cmake-export-targets \
               ros-kilted-ament-cmake-gen-version-h ros-kilted-ament-cmake-include-directories \
               ros-kilted-ament-cmake-libraries ros-kilted-ament-cmake-python ros-kilted-ament-cmake-ros-core \
               ros-kilted-ament-cmake-target-dependencies ros-kilted-ament-cmake-test ros-kilted-ament-cmake-version \
               ros-kilted-ament-package ros-kilted-rosidl-adapter ros-kilted-rosidl-cli ros-kilted-rosidl-cmake \
               ros-kilted-rosidl-core-generators ros-kilted-rosidl-core-runtime ros-kilted-rosidl-default-generators \
               ros-kilted-rosidl-default-runtime ros-kilted-rosidl-dynamic-typesupport \
               ros-kilted-rosidl-dynamic-typesupport-fastrtps ros-kilted-rosidl-generator-c \
               ros-kilted-rosidl-generator-cpp ros-kilted-rosidl-generator-py \
               ros-kilted-rosidl-generator-type-description ros-kilted-rosidl-parser ros-kilted-rosidl-pycommon \
               ros-kilted-rosidl-runtime-c ros-kilted-rosidl-runtime-cpp ros-kilted-rosidl-typesupport-c \
               ros-kilted-rosidl-typesupport-cpp ros-kilted-rosidl-typesupport-fastrtps-c \
               ros-kilted-rosidl-typesupport-fastrtps-cpp ros-kilted-rosidl-typesupport-interface \
               ros-kilted-rosidl-typesupport-introspection-c ros-kilted-rosidl-typesupport-introspection-cpp \
               ros-kilted-action-msgs ros-kilted-builtin-interfaces ros-kilted-std-msgs ros-kilted-geometry-msgs \
               ros-kilted-nav-msgs \
               catkin_pkg numpy
ROS2_INTERFACES := $(VENV)/.ros2-interfaces
ROS2_SOURCES := tools/build_ros2_interfaces.py \
                $(shell find frontier_rl/ros2/interfaces -type f -not -path '*/__pycache__/*' 2>/dev/null)

.PHONY: setup ros2-wheels ros-deps browser-deps demo test test-fast lint typecheck docs pytest bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[rl,ray,dev,docs,ros2]"
	touch $(STAMP)

# NavigateToPose and FollowPath (nav2_msgs has no wheel) generated from their vendored .action files and built into the venv
$(ROS2_INTERFACES): $(STAMP) $(ROS2_SOURCES)
	$(BIN)/python -m pip install --quiet $(ROS2_WHEELS)
	$(BIN)/python tools/build_ros2_interfaces.py
	touch $(ROS2_INTERFACES)

setup: $(STAMP) $(ROS2_INTERFACES)

# the wheels the interfaces' build needs, for an install by hand (docs/guides/ros2.md)
ros2-wheels:
	@echo $(ROS2_WHEELS)

# $(call apt_deps,CHECK,PACKAGES,WHAT,WHICH TEST): install Debian packages unless CHECK passes, where apt-get runs as root
define apt_deps
	@if $(1); then :; \
	elif command -v apt-get >/dev/null && [ "$$(id -u)" = 0 ]; then \
		echo "installing $(3) from Debian: $(2)"; \
		(apt-get update -q && DEBIAN_FRONTEND=noninteractive apt-get install -y -q $(2)) >/dev/null; \
	else echo "$(3) is not installed and apt-get as root is not available: $(4) will be skipped"; fi
endef

ros-deps:
	$(call apt_deps,$(ROS_CHECK),$(ROS_APT),ROS 1,the ROS node test)

browser-deps:
	$(call apt_deps,$(BROWSER_CHECK),$(BROWSER_APT),Chromium,the report's browser test)

demo: $(STAMP)
	$(BIN)/frontier-rl demo --out demo_output

lint: $(STAMP)
	$(BIN)/ruff check frontier_rl tests benchmarks experiments examples docs/_ext tools
	$(BIN)/ruff format --check frontier_rl tests benchmarks experiments examples docs/_ext tools
	$(BIN)/lint-imports --no-cache

typecheck: $(STAMP) $(ROS2_INTERFACES)
	$(BIN)/mypy

# the tests one per core at a time (pytest-xdist), then those timed against the wall clock alone
pytest: $(STAMP) $(ROS2_INTERFACES) ros-deps browser-deps
	$(BIN)/pytest -q -n auto --dist loadfile -m "not serial"
	$(BIN)/pytest -q -m serial

# the documentation site, offline, into docs/_build/html: warnings are errors, references are checked (-n)
docs: $(STAMP) $(ROS2_INTERFACES)
	$(BIN)/sphinx-build -b html -W --keep-going -n -q docs docs/_build/html

test: lint typecheck docs pytest

# the same checks without the tests marked slow (real maps, training, the ROS node, whole experiments)
test-fast: lint typecheck
	$(BIN)/pytest -q -m "not slow"

bench: $(STAMP)
	$(BIN)/python benchmarks/run.py

clean:
	rm -rf $(VENV) demo_output .pytest_cache .mypy_cache .ruff_cache
