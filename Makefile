# Paint Relief: set-up, tests, demo, benchmarks and the extension package.
# Every target installs what it needs first; running a target twice does no extra work.

# Interpreters by version: python3.X on PATH, else the newest pyenv build of 3.X. Blender 4.2 LTS to 5.0
# ship Python 3.11; Blender 5.1 and later ship Python 3.13.
PYENV_ROOT  ?= $(or $(shell pyenv root 2>/dev/null),$(HOME)/.pyenv)
find_python  = $(shell for p in "$$(command -v python$(1))" $$(ls -d $(PYENV_ROOT)/versions/$(1).*/bin/python$(1) 2>/dev/null | sort -V -r); do \
                 [ -n "$$p" ] && "$$p" -c "" 2>/dev/null && { echo "$$p"; break; }; done)
ifndef PYTHON_3.11
PYTHON_3.11 := $(call find_python,3.11)
endif
ifndef PYTHON_3.13
PYTHON_3.13 := $(call find_python,3.13)
endif
# CI=1 (as .ci/run sets it) turns a missing interpreter into a failure instead of a skipped environment.
CI          ?=

# The main environment follows the current Blender, 5.3: Python 3.13, NumPy 2 (requirements.txt).
PYTHON ?= $(PYTHON_3.13)
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
SAMPLE ?= sample_scenes/coffee.png
OUT    ?= out
# Blender's extension tool, from the bpy module in .venv (looked up when a recipe runs, after set-up).
BLENDER_EXT  = $(lastword $(sort $(wildcard $(VENV)/lib/python3.*/site-packages/bpy/*/scripts/addons_core/bl_pkg/cli/blender_ext.py)))
VALID_TAGS   = $(abspath $(dir $(BLENDER_EXT))../../../modules/_bpy_internal/extensions/tags.py)
DIST        ?= dist
VERSION     := $(shell sed -n 's/^version *= *"\(.*\)"/\1/p' blender_manifest.toml)
# The wheels the manifest lists (./wheels/<name>.whl), downloaded on demand.
WHEELS      := $(shell sed -n 's|^ *"\./\(wheels/[^"]*\.whl\)".*|\1|p' blender_manifest.toml)
# The painter's oldest NumPy, Blender 4.2 LTS's 1.24 (Python 3.11): the suite without Blender runs there too.
NUMPY1_VENV := .venv-numpy1
# Blender as shipped, for `make test-shipped`: each environment holds only the bpy module of one Blender
# version on its Python, the NumPy that version bundles and pytest. No PyPI SciPy or OpenImageIO: the
# extension's own wheels come from the zip `make extension` builds, installed the way Blender installs them.
SHIPPED_VERSIONS := 4.2 4.5 5.0 5.2 5.3
SHIPPED_PYTHON_4.2 := 3.11
SHIPPED_PYTHON_4.5 := 3.11
SHIPPED_PYTHON_5.0 := 3.11
SHIPPED_PYTHON_5.2 := 3.13
SHIPPED_PYTHON_5.3 := 3.13
SHIPPED_REQUIREMENTS_4.2 := bpy==4.2.0 numpy==1.24.3 pytest==9.2.0
SHIPPED_REQUIREMENTS_4.5 := bpy==4.5.15 numpy==1.26.4 pytest==9.2.0
SHIPPED_REQUIREMENTS_5.0 := bpy==5.0.1 numpy==1.26.4 pytest==9.2.0
SHIPPED_REQUIREMENTS_5.2 := bpy==5.2.3 numpy==2.2.6 pytest==9.2.0
SHIPPED_REQUIREMENTS_5.3 := bpy==5.3.0 numpy==2.5.5 pytest==9.2.0
# The versions whose Python this machine has; the others are named once and skipped (a failure under CI=1).
SHIPPED_HERE    := $(foreach v,$(SHIPPED_VERSIONS),$(if $(PYTHON_$(SHIPPED_PYTHON_$(v))),$(v)))
SHIPPED_MISSING := $(filter-out $(SHIPPED_HERE),$(SHIPPED_VERSIONS))
PLATFORM_TAG := $(shell $(PYTHON) -c "import platform as p; print({'Linux': 'linux', 'Darwin': 'macos', 'Windows': 'windows'}.get(p.system(), '?') + '_' + {'x86_64': 'x64', 'AMD64': 'x64', 'arm64': 'arm64', 'aarch64': 'arm64'}.get(p.machine(), '?'))" 2>/dev/null)
SHIPPED_ZIP := $(DIST)/paint_relief-$(VERSION)-$(PLATFORM_TAG).zip

.PHONY: setup test test-quick test-core test-numpy1 test-shipped pythons demo bench extension clean

setup: $(STAMP)

$(STAMP): requirements.txt
	@test -n "$(PYTHON)" || { echo "make: Python 3.13 (Blender 5.3's) is needed for .venv: put python3.13 on PATH, install it with pyenv, or pass PYTHON=path"; exit 1; }
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -r requirements.txt
	@touch $(STAMP)

# Everything: the whole suite in .venv (NumPy 2), the suite without Blender on NumPy 1.24, then the extension
# as shipped in bpy-only environments.
test: test-core test-numpy1 test-shipped

# The suite in .venv without the tests that start Blender or a Dask cluster (pytest markers blender and cluster):
# a developer's quick check. CI runs everything (`make test`).
test-quick: $(STAMP)
	$(VENV)/bin/ruff check .
	$(PY) -m pytest -q -m "not blender and not cluster"

# One line naming what this machine cannot test for want of an interpreter; under CI=1 that is a failure.
pythons:
	@$(if $(PYTHON_3.11),,echo "make: no Python 3.11 here (python3.11 on PATH or under pyenv): skipped NumPy 1.24 and Blender $(SHIPPED_MISSING)"; $(if $(CI),exit 1,true))
	@$(if $(PYTHON_3.13),,echo "make: no Python 3.13 here (python3.13 on PATH or under pyenv): skipped Blender $(SHIPPED_MISSING)"; $(if $(CI),exit 1,true))

# The linter first (pyproject.toml: pyflakes, import order, bugbear), then the suite.
test-core: $(STAMP) $(if $(PYTHON_3.11),$(NUMPY1_VENV)/.installed)
	$(VENV)/bin/ruff check .
	$(PY) -m pytest -q

# The suite that needs no Blender, on the oldest NumPy the painter supports (requirements-numpy1.txt). The crash
# matrices (tests/crash_points.py) run once, in .venv: what a crash leaves does not hang on NumPy's version.
test-numpy1: pythons $(if $(PYTHON_3.11),$(NUMPY1_VENV)/.installed)
	$(if $(PYTHON_3.11),$(NUMPY1_VENV)/bin/python -W error::DeprecationWarning -m pytest -q -p no:cacheprovider -m "not blender and not crash_matrix")

$(NUMPY1_VENV)/.installed: requirements-numpy1.txt
	@test -x $(NUMPY1_VENV)/bin/python || $(PYTHON_3.11) -m venv $(NUMPY1_VENV)
	$(NUMPY1_VENV)/bin/python -m pip install --quiet --disable-pip-version-check -r requirements-numpy1.txt
	@touch $@

# The demo: analyse and paint SAMPLE, then the lighting comparison (Cycles renders of the canvas under a sweep
# of 8 lights with and without relief, against the 2-D lighting), then Paint Object on the demo box (its texture
# painted in its UV space, filmed on a DEMO_VIEWS-view turntable), then tools/check_demo.py, which fails when a
# promised output is missing or not a whole picture. Each step prints its seconds.
# BLENDER_USER_RESOURCES keeps Blender's user files inside $(OUT).
DEMO_VIEWS ?= 8
demo: $(STAMP)
	@mkdir -p $(OUT)
	@s=$$(date +%s); echo "$(PY) -m core analyze $(SAMPLE) -o $(OUT)/analysis"; \
	  $(PY) -m core analyze $(SAMPLE) -o $(OUT)/analysis && echo "analyze took $$(( $$(date +%s) - s )) s"
	@s=$$(date +%s); echo "$(PY) -m core paint $(SAMPLE) -o $(OUT)/painting"; \
	  $(PY) -m core paint $(SAMPLE) -o $(OUT)/painting && echo "paint took $$(( $$(date +%s) - s )) s"
	@s=$$(date +%s); echo "$(PY) sample_scenes/compare.py $(SAMPLE) -o $(OUT)/compare"; \
	  BLENDER_USER_RESOURCES=$(abspath $(OUT))/blender_user $(PY) sample_scenes/compare.py $(SAMPLE) -o $(OUT)/compare \
	  && echo "compare took $$(( $$(date +%s) - s )) s"
	@s=$$(date +%s); echo "$(PY) sample_scenes/paint_object.py -o $(OUT)/object --views $(DEMO_VIEWS)"; \
	  BLENDER_USER_RESOURCES=$(abspath $(OUT))/blender_user $(PY) sample_scenes/paint_object.py -o $(OUT)/object \
	  --views $(DEMO_VIEWS) && echo "paint_object took $$(( $$(date +%s) - s )) s"
	$(PY) tools/check_demo.py $(OUT) --views $(DEMO_VIEWS)
	@echo "Demo outputs are in $(OUT)/: analysis/ (importance, partition, orientation), painting/ (maps, preview, report),"
	@echo "compare/ (comparison.png, correlation.png, light_sweep.gif, comparison.md and .json, renders/, scene.blend),"
	@echo "object/ (the demo box's maps/, turntable/ relit, paper, original and side_by_side, object.json, scene.blend)"

bench: $(STAMP)
	$(PY) bench/analysis.py
	$(PY) bench/solve.py
	$(PY) bench/paint.py
	$(PY) bench/strokes.py
	$(PY) bench/speedups.py
	$(PY) bench/hertzmann.py
	$(PY) bench/lighting.py
	$(PY) bench/svg.py
	$(PY) bench/blender.py

extension: $(STAMP) $(WHEELS)
	@mkdir -p $(DIST)
	$(PY) $(BLENDER_EXT) build --source-dir . --output-dir $(DIST) --valid-tags $(VALID_TAGS) --split-platforms
	@for zip in $(DIST)/paint_relief-$(VERSION)-*.zip; do \
	  echo "validate $$zip"; $(PY) $(BLENDER_EXT) validate "$$zip" || exit 1; done

# wheels/<dist>-<version>-<python>-<abi>-<platform>[.<platform>...].whl: one pip download for its first platform tag
# (a pure-Python wheel, platform 'any', is downloaded as it is).
wheels/%.whl:
	@mkdir -p wheels
	$(PY) -m pip download --quiet --disable-pip-version-check --only-binary=:all: --no-deps \
	  $(if $(filter any,$(lastword $(subst -, ,$*))),,--python-version $(patsubst cp3%,3.%,$(word 3,$(subst -, ,$*))) \
	  --platform $(firstword $(subst ., ,$(lastword $(subst -, ,$*))))) --dest wheels \
	  $(word 1,$(subst -, ,$*))==$(word 2,$(subst -, ,$*))
	@test -f $@ || { echo "pip did not download $@"; exit 1; }

# The extension's tests from the built zip, once per Blender version in SHIPPED_VERSIONS (tests/shipped/).
test-shipped: pythons extension $(foreach v,$(SHIPPED_HERE),.venv-shipped-$(v)/.installed)
	@for v in $(SHIPPED_HERE); do \
	  s=$$(date +%s); echo "tests/shipped with Blender $$v (.venv-shipped-$$v)"; \
	  PAINT_RELIEF_ZIP=$(abspath $(SHIPPED_ZIP)) .venv-shipped-$$v/bin/python -m pytest -q -p no:cacheprovider tests/shipped || exit 1; \
	  echo "Blender $$v shipped tests took $$(( $$(date +%s) - s )) s"; done

# pip keeps downloaded wheels in its cache, so a second environment with the same bpy downloads nothing.
.venv-shipped-%/.installed: Makefile
	@test -x .venv-shipped-$*/bin/python || $(PYTHON_$(SHIPPED_PYTHON_$*)) -m venv .venv-shipped-$*
	@s=$$(date +%s); .venv-shipped-$*/bin/python -m pip install --quiet --disable-pip-version-check $(SHIPPED_REQUIREMENTS_$*) && \
	  echo ".venv-shipped-$* installed in $$(( $$(date +%s) - s )) s"
	@touch $@

clean:
	rm -rf dist build $(OUT) .pytest_cache
