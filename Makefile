# The two commands of the README:  `make demo`  and  `make test`.
# Both set up everything they need on a fresh Debian 12 machine and are cheap to rerun.
SHELL := /bin/bash
ROOT := $(abspath .)
VENV := $(ROOT)/.venv
PY := $(VENV)/bin/python
BUILD := $(ROOT)/build
STAMPS := $(ROOT)/.stamps
PACKAGE := $(ROOT)/python_bindings/meshlab_symmetry
PLUGIN := $(PACKAGE)/libfilter_symmetry.so

DEB_PACKAGES := g++ cmake ninja-build python3-venv libeigen3-dev libnanoflann-dev libgtest-dev \
  qtbase5-dev libqt5opengl5-dev libqt5svg5-dev libglew-dev libglu1-mesa-dev mesa-common-dev

DEMO_MESH := meshes/demo.ply

.PHONY: all setup build demo test test-cpp test-python benchmark clean
all: build

setup: $(STAMPS)/apt $(STAMPS)/venv third_party/meshlab/.verified

$(STAMPS)/apt: scripts/install_debian_packages.sh
	@scripts/install_debian_packages.sh $(DEB_PACKAGES)
	@mkdir -p $(STAMPS) && touch $@

$(STAMPS)/venv: python_bindings/requirements.txt python_bindings/pyproject.toml $(STAMPS)/apt
	@test -x $(PY) || python3 -m venv $(VENV)
	@$(PY) -m pip install -q --disable-pip-version-check -r python_bindings/requirements.txt
	@$(PY) -m pip install -q --disable-pip-version-check --no-deps -e python_bindings
	@mkdir -p $(STAMPS) && touch $@

third_party/meshlab/.verified: scripts/fetch_meshlab_source.sh $(STAMPS)/apt
	@scripts/fetch_meshlab_source.sh $(ROOT)/third_party

build: setup
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -Wno-dev \
	  -DPYMESHLAB_DIR="$$($(PY) -c 'import os, pymeshlab; print(os.path.dirname(pymeshlab.__file__))')" > $(BUILD).configure.log 2>&1 \
	  || { cat $(BUILD).configure.log; exit 1; }
	@cmake --build $(BUILD)
	@# Replace the plugin by renaming, never in place: a Python process that has it loaded
	@# would crash (SIGBUS) on a file rewritten under it.
	@cmp -s $(BUILD)/plugin/filter_symmetry/libfilter_symmetry.so $(PLUGIN) || \
	  { cp $(BUILD)/plugin/filter_symmetry/libfilter_symmetry.so $(PLUGIN).tmp && mv -f $(PLUGIN).tmp $(PLUGIN); }

demo: build
	$(PY) -m meshlab_symmetry $(DEMO_MESH)

test: build
	cd $(BUILD) && ctest --output-on-failure -j2
	$(PY) -m pytest -q tests/python

benchmark: build
	$(PY) tests/benchmarks/benchmark.py

clean:
	rm -rf $(BUILD) $(STAMPS) $(PLUGIN)
