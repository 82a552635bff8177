# frontier_rl: `make demo` and `make test` work on a fresh clone with only Python 3.11.
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

.PHONY: setup ros-deps browser-deps demo test test-fast lint typecheck docs pytest bench clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[rl,ray,dev,docs]"
	touch $(STAMP)

setup: $(STAMP)

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
	$(BIN)/ruff check frontier_rl tests benchmarks experiments examples docs/_ext
	$(BIN)/ruff format --check frontier_rl tests benchmarks experiments examples docs/_ext
	$(BIN)/lint-imports --no-cache

typecheck: $(STAMP)
	$(BIN)/mypy

# the tests one per core at a time (pytest-xdist), then those timed against the wall clock alone
pytest: $(STAMP) ros-deps browser-deps
	$(BIN)/pytest -q -n auto --dist loadfile -m "not serial"
	$(BIN)/pytest -q -m serial

# the documentation site, offline, into docs/_build/html: warnings are errors, references are checked (-n)
docs: $(STAMP)
	$(BIN)/sphinx-build -b html -W --keep-going -n -q docs docs/_build/html

test: lint typecheck docs pytest

# the same checks without the tests marked slow (real maps, training, the ROS node, whole experiments)
test-fast: lint typecheck
	$(BIN)/pytest -q -m "not slow"

bench: $(STAMP)
	$(BIN)/python benchmarks/run.py

clean:
	rm -rf $(VENV) demo_output .pytest_cache .mypy_cache .ruff_cache
