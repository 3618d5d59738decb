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
# Blender as shipped, for `make test-shipped`: each environment holds only the bpy module of one Blender
# version, the NumPy that version bundles and pytest. No PyPI SciPy or OpenImageIO: the extension's own
# wheels come from the zip `make extension` builds, installed the way Blender installs them.
SHIPPED_VERSIONS := 5.0 4.2
SHIPPED_REQUIREMENTS_5.0 := bpy==5.0.1 numpy==1.26.4 pytest==9.2.0
SHIPPED_REQUIREMENTS_4.2 := bpy==4.2.0 numpy==1.24.3 pytest==9.2.0
PLATFORM_TAG := $(shell $(PYTHON) -c "import platform as p; print({'Linux': 'linux', 'Darwin': 'macos', 'Windows': 'windows'}.get(p.system(), '?') + '_' + {'x86_64': 'x64', 'AMD64': 'x64', 'arm64': 'arm64', 'aarch64': 'arm64'}.get(p.machine(), '?'))" 2>/dev/null)
SHIPPED_ZIP := $(DIST)/paint_relief-$(VERSION)-$(PLATFORM_TAG).zip

.PHONY: setup test test-core test-shipped demo bench extension clean

setup: $(STAMP)

$(STAMP): requirements.txt
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -r requirements.txt
	@touch $(STAMP)

# Everything: the whole suite in .venv, then the extension as shipped in bpy-only environments.
test: test-core test-shipped

# The linter first (pyproject.toml: pyflakes, import order, bugbear), then the suite.
test-core: $(STAMP)
	$(VENV)/bin/ruff check .
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
	$(PY) bench/strokes.py
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

# The extension's tests from the built zip, once per Blender version in SHIPPED_VERSIONS (tests/shipped/).
test-shipped: extension $(foreach v,$(SHIPPED_VERSIONS),.venv-shipped-$(v)/.installed)
	@for v in $(SHIPPED_VERSIONS); do \
	  s=$$(date +%s); echo "tests/shipped with Blender $$v (.venv-shipped-$$v)"; \
	  PAINT_RELIEF_ZIP=$(abspath $(SHIPPED_ZIP)) .venv-shipped-$$v/bin/python -m pytest -q -p no:cacheprovider tests/shipped || exit 1; \
	  echo "Blender $$v shipped tests took $$(( $$(date +%s) - s )) s"; done

# pip keeps downloaded wheels in its cache, so a second environment with the same bpy downloads nothing.
.venv-shipped-%/.installed: Makefile
	@test -x .venv-shipped-$*/bin/python || $(PYTHON) -m venv .venv-shipped-$*
	@s=$$(date +%s); .venv-shipped-$*/bin/python -m pip install --quiet --disable-pip-version-check $(SHIPPED_REQUIREMENTS_$*) && \
	  echo ".venv-shipped-$* installed in $$(( $$(date +%s) - s )) s"
	@touch $@

clean:
	rm -rf dist build $(OUT) .pytest_cache
