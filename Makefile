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

.PHONY: setup test demo bench extension clean

setup: $(STAMP)

$(STAMP): requirements.txt
	@test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --disable-pip-version-check -r requirements.txt
	@touch $(STAMP)

test: $(STAMP)
	$(PY) -m pytest -q

demo: $(STAMP)
	@mkdir -p $(OUT)
	$(PY) -m core analyze $(SAMPLE) -o $(OUT)/analysis
	$(PY) -m core paint $(SAMPLE) -o $(OUT)/painting
	@echo "Demo outputs are in $(OUT)/: analysis/ (importance, partition, orientation), painting/ (maps, preview, report)"

bench: $(STAMP)
	$(PY) bench/analysis.py
	$(PY) bench/paint.py

extension: $(STAMP)
	@mkdir -p $(DIST)
	$(PY) $(BLENDER_EXT) build --source-dir . --output-dir $(DIST) --valid-tags $(VALID_TAGS)
	$(PY) $(BLENDER_EXT) validate $(DIST)/paint_relief-$(VERSION).zip

clean:
	rm -rf dist build $(OUT) .pytest_cache
