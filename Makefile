# Paint Relief: set-up, tests, demo, benchmarks and the extension package.
# Every target installs what it needs first; running a target twice does no extra work.

PYTHON ?= python3.11
VENV   := .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
SAMPLE ?= sample_scenes/coffee.png
OUT    ?= out
BPY_DIR     := $(VENV)/lib/python3.11/site-packages/bpy/5.0/scripts
BLENDER_EXT := $(BPY_DIR)/addons_core/bl_pkg/cli/blender_ext.py
VALID_TAGS   = $(abspath $(dir $(BLENDER_EXT))../../../modules/_bpy_internal/extensions/tags.py)
DIST        ?= dist
VERSION     := $(shell sed -n 's/^version *= *"\(.*\)"/\1/p' blender_manifest.toml)
# The wheels the manifest lists (./wheels/<name>.whl), downloaded on demand.
WHEELS      := $(shell sed -n 's|^ *"\./\(wheels/[^"]*\.whl\)".*|\1|p' blender_manifest.toml)
# Blender 4.2 LTS as a Python module, for `make test-compat`: SciPy as in the
# manifest's wheels, NumPy as Blender 4.2 ships it.
COMPAT       := .venv-compat
COMPAT_PY    := $(COMPAT)/bin/python
COMPAT_STAMP := $(COMPAT)/.installed
COMPAT_REQUIREMENTS := bpy==4.2.0 numpy==1.24.3 scipy==1.15.3 OpenImageIO==3.0.21.0 pytest==9.2.0 hypothesis==6.170.15

.PHONY: setup test test-compat demo bench extension clean

setup: $(STAMP)

$(STAMP): requirements.txt
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -r requirements.txt
	@touch $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q

# The demo: analyse and paint SAMPLE, then the lighting comparison (Cycles renders of the canvas under a sweep
# of 8 lights with and without relief, against the 2-D lighting). Each step prints its seconds.
# BLENDER_USER_RESOURCES keeps Blender's user files inside $(OUT).
demo: $(STAMP)
	@mkdir -p $(OUT)
	@s=$$(date +%s); echo "$(PY) -m core analyze $(SAMPLE) -o $(OUT)/analysis"; \
	  $(PY) -m core analyze $(SAMPLE) -o $(OUT)/analysis && echo "analyze took $$(( $$(date +%s) - s )) s"
	@s=$$(date +%s); echo "$(PY) -m core paint $(SAMPLE) -o $(OUT)/painting"; \
	  $(PY) -m core paint $(SAMPLE) -o $(OUT)/painting && echo "paint took $$(( $$(date +%s) - s )) s"
	BLENDER_USER_RESOURCES=$(abspath $(OUT))/blender_user $(PY) sample_scenes/compare.py $(SAMPLE) -o $(OUT)/compare
	@echo "Demo outputs are in $(OUT)/: analysis/ (importance, partition, orientation), painting/ (maps, preview, report),"
	@echo "compare/ (comparison.png, correlation.png, light_sweep.gif, comparison.md and .json, renders/, scene.blend)"

bench: $(STAMP)
	$(PY) bench/analysis.py
	$(PY) bench/paint.py
	$(PY) bench/hertzmann.py
	$(PY) bench/lighting.py
	$(PY) bench/blender.py

extension: $(STAMP) $(WHEELS)
	@mkdir -p $(DIST)
	$(PY) $(BLENDER_EXT) build --source-dir . --output-dir $(DIST) --valid-tags $(VALID_TAGS) --split-platforms
	@for zip in $(DIST)/paint_relief-$(VERSION)-*.zip; do \
	  echo "validate $$zip"; $(PY) $(BLENDER_EXT) validate "$$zip" || exit 1; done

# wheels/<dist>-<version>-<python>-<abi>-<platform>[.<platform>...].whl: one pip download for its first platform tag.
wheels/%.whl:
	@mkdir -p wheels
	$(PY) -m pip download --quiet --disable-pip-version-check --only-binary=:all: --no-deps --python-version 3.11 \
	  --platform $(firstword $(subst ., ,$(lastword $(subst -, ,$*)))) --dest wheels \
	  $(word 1,$(subst -, ,$*))==$(word 2,$(subst -, ,$*))
	@test -f $@ || { echo "pip did not download $@"; exit 1; }

# The add-on tests on Blender 4.2 LTS (bpy 4.2 module, Python 3.11). Not part of `test`.
test-compat: $(COMPAT_STAMP)
	$(COMPAT_PY) -m pytest -q -m blender -p no:cacheprovider tests/test_extension.py tests/test_addon*.py

$(COMPAT_STAMP): Makefile
	@test -x $(COMPAT_PY) || $(PYTHON) -m venv $(COMPAT)
	$(COMPAT_PY) -m pip install --quiet --disable-pip-version-check $(COMPAT_REQUIREMENTS)
	@touch $(COMPAT_STAMP)

clean:
	rm -rf dist build $(OUT) .pytest_cache
