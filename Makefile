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
# The core as a Python extension (python_bindings/core_module.cpp), named for the venv's Python.
CORE_MODULE = _core$(shell $(PY) -c 'import sysconfig; print(sysconfig.get_config_var("EXT_SUFFIX"))')

DEB_PACKAGES := g++ cmake ninja-build python3-venv python3-dev libeigen3-dev libnanoflann-dev libgtest-dev \
  qtbase5-dev libqt5opengl5-dev libqt5svg5-dev libglew-dev libglu1-mesa-dev mesa-common-dev

DEMO_MESH := meshes/demo.ply

.PHONY: all setup build meshlabserver-plugin meshlab demo test test-sanitize benchmark clean
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
	@cmake -S . -B $(BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -Wno-dev -DPYTHON_EXECUTABLE=$(PY) -Dpybind11_DIR="$$($(PY) -m pybind11 --cmakedir)" \
	  -DPYMESHLAB_DIR="$$($(PY) -c 'import os, pymeshlab; print(os.path.dirname(pymeshlab.__file__))')" > $(BUILD).configure.log 2>&1 \
	  || { cat $(BUILD).configure.log; exit 1; }
	@cmake --build $(BUILD)
	@# Replace the plugin by renaming, never in place: a Python process that has it loaded
	@# would crash (SIGBUS) on a file rewritten under it.
	@cmp -s $(BUILD)/plugin/filter_symmetry/libfilter_symmetry.so $(PLUGIN) || \
	  { cp $(BUILD)/plugin/filter_symmetry/libfilter_symmetry.so $(PLUGIN).tmp && mv -f $(PLUGIN).tmp $(PLUGIN); }
	@cmp -s $(BUILD)/python_bindings/$(CORE_MODULE) $(PACKAGE)/$(CORE_MODULE) || \
	  { cp $(BUILD)/python_bindings/$(CORE_MODULE) $(PACKAGE)/$(CORE_MODULE).tmp && mv -f $(PACKAGE)/$(CORE_MODULE).tmp $(PACKAGE)/$(CORE_MODULE); }

# The plugin for Debian 12's meshlabserver (MeshLab 2020.09, issue 7): the same core and
# host-side files built against the 2020.09 plugin API, in float, linked against the
# `meshlab` package's libmeshlab-common.so.  Install it by copying it into
# /usr/lib/x86_64-linux-gnu/meshlab/plugins/ (README, "Headless batch jobs").
MESHLAB_2020_BUILD := $(BUILD)/meshlab-2020.09
MESHLABSERVER_DEB_PACKAGES := meshlab xvfb xauth
$(STAMPS)/apt-meshlabserver: scripts/install_debian_packages.sh $(STAMPS)/apt
	@scripts/install_debian_packages.sh $(MESHLABSERVER_DEB_PACKAGES)
	@touch $@

third_party/meshlab-2020.09/.verified: scripts/fetch_meshlab_source.sh $(STAMPS)/apt
	@scripts/fetch_meshlab_source.sh $(ROOT)/third_party 2020.09

meshlabserver-plugin: setup $(STAMPS)/apt-meshlabserver third_party/meshlab-2020.09/.verified
	@mkdir -p $(BUILD)
	@cmake -S . -B $(MESHLAB_2020_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -Wno-dev -DMESHLAB_API=2020.09 \
	  -DSYMMETRY_BUILD_TESTS=OFF -DCMAKE_DISABLE_FIND_PACKAGE_pybind11=ON > $(MESHLAB_2020_BUILD).configure.log 2>&1 \
	  || { cat $(MESHLAB_2020_BUILD).configure.log; exit 1; }
	@cmake --build $(MESHLAB_2020_BUILD)

# MeshLab 2025.07's GUI with this plugin (issue 7), built by MeshLab's own CMake from the same
# checksummed source: the plugin folder plugin/meshlab_gui is linked into MeshLab's tree and
# named in MESHLAB_PLUGINS, as MeshLab builds its own plugins; MESHLAB_BUILD_MINI builds only
# the targets named, here the application, the io plugin for PLY/OBJ/OFF/STL and ours.
# Single precision, MeshLab's default: build/meshlab-2025.07/src/distrib/plugins/libfilter_symmetry.so
# is also the file to drop into an installed MeshLab 2025.07 (README, "In MeshLab's GUI").
MESHLAB_GUI_BUILD := $(BUILD)/meshlab-2025.07
GUI_TEST_DEB_PACKAGES := xvfb xauth xdotool
$(STAMPS)/apt-gui: scripts/install_debian_packages.sh $(STAMPS)/apt
	@scripts/install_debian_packages.sh $(GUI_TEST_DEB_PACKAGES)
	@touch $@

meshlab: setup $(STAMPS)/apt-gui
	@ln -sfn $(ROOT)/plugin/meshlab_gui third_party/meshlab/src/meshlabplugins/filter_symmetry
	@mkdir -p $(BUILD)
	@cmake -S third_party/meshlab -B $(MESHLAB_GUI_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=Release -Wno-dev \
	  -DMESHLAB_BUILD_MINI=ON "-DMESHLAB_PLUGINS=meshlabplugins/io_base;meshlabplugins/filter_symmetry" \
	  > $(MESHLAB_GUI_BUILD).configure.log 2>&1 || { cat $(MESHLAB_GUI_BUILD).configure.log; exit 1; }
	@cmake --build $(MESHLAB_GUI_BUILD) --target meshlab io_base filter_symmetry

DEMO_OUT := meshes/demo_report
demo: build
	$(PY) -m meshlab_symmetry detect $(DEMO_MESH) -o $(DEMO_OUT) --report

# pytest runs a module per worker, one worker per core (pytest-xdist): much of a test is
# single-threaded Python, pymeshlab or a host process, so one worker left a core idle.  The
# meshes the tests download are fetched first, so that two workers never fetch them at once.
test: build meshlabserver-plugin meshlab
	cd $(BUILD) && ctest --output-on-failure -j2
	@tests/fetch_real_models.sh > /dev/null && tests/fetch_cgal_meshes.sh > /dev/null
	$(PY) -m pytest -q -n 2 --dist loadfile tests/python

# The core, the plugin and the tests again with AddressSanitizer and UndefinedBehaviorSanitizer
# (issue 10): the C++ tests with the fuzzer, then the pymeshlab tests of broken input and of
# the filter's interface with the sanitized plugin loaded into pymeshlab.  Python itself is
# not instrumented, so the sanitizers' runtimes are preloaded and its own leaks not counted.
# Instrumented code runs 4-5 times slower, so three kinds of test that add no code path are
# left to `make test`: Detection.DeterministicForASeed (the same detection twice, 3 minutes),
# the fuzzer's random cases past the first SANITIZE_FUZZ_CASES (the kept corpus always runs),
# and the pytest cases marked long_under_sanitizers (whole scenes, whose core the C++ tests
# run and whose host code the lighter cases run).  The Python extension _core is not built:
# these tests load the sanitized plugin into pymeshlab, and none calls the core engine.
SANITIZE_BUILD := $(ROOT)/build-sanitize
SANITIZER_RUNTIMES = $$(g++ -print-file-name=libasan.so):$$(g++ -print-file-name=libubsan.so)
SANITIZE_PYTESTS := tests/python/test_broken_input.py tests/python/test_filter_api.py tests/python/test_parameter_extremes.py \
  tests/python/test_symmetrization.py
SANITIZE_FUZZ_CASES := 50
# -O1 -g1 (line tables, no local variables: enough for the sanitizers' stack traces) compiles
# in half the time of RelWithDebInfo's -O2 -g; the build was the larger part of this step.
SANITIZE_FLAGS := -O1 -g1 -DNDEBUG
test-sanitize: setup
	@cmake -S . -B $(SANITIZE_BUILD) -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$(SANITIZE_FLAGS)" -DSYMMETRY_SANITIZE=ON -Wno-dev -DPYTHON_EXECUTABLE=$(PY) -DCMAKE_DISABLE_FIND_PACKAGE_pybind11=ON \
	  -DPYMESHLAB_DIR="$$($(PY) -c 'import os, pymeshlab; print(os.path.dirname(pymeshlab.__file__))')" \
	  -DSYMMETRY_FUZZ_CASES=$(SANITIZE_FUZZ_CASES) > $(SANITIZE_BUILD).configure.log 2>&1 \
	  || { cat $(SANITIZE_BUILD).configure.log; exit 1; }
	@cmake --build $(SANITIZE_BUILD)
	cd $(SANITIZE_BUILD) && UBSAN_OPTIONS=print_stacktrace=1 ctest --output-on-failure -j2 -E '^Detection\.DeterministicForASeed$$'
	LD_PRELOAD="$(SANITIZER_RUNTIMES)" ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 \
	  MESHLAB_SYMMETRY_PLUGIN=$(SANITIZE_BUILD)/plugin/filter_symmetry/libfilter_symmetry.so \
	  $(PY) -m pytest -q -p no:cacheprovider -n 2 --dist loadfile -m 'not long_under_sanitizers' $(SANITIZE_PYTESTS)

benchmark: build
	$(PY) tests/benchmarks/benchmark.py

clean:
	rm -rf $(BUILD) $(SANITIZE_BUILD) $(STAMPS) $(PLUGIN) $(PACKAGE)/$(CORE_MODULE)
