# The two commands a new user types: `make demo` and `make test`. Both set themselves up.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
DEV_STAMP := $(VENV)/.installed-dev
SYSTEM_PACKAGES := shellcheck mosquitto libeclipse-emf-ecore-java libeclipse-emf-ecore-xmi-java openjdk-17-jdk-headless chromium chromium-driver iproute2

.PHONY: demo live live-console console test docs lint format bench system-packages clean

$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

# Byte-compiled as pip does for a regular install: an editable install never is, and with
# PYTHONDONTWRITEBYTECODE set every `acordcs-gen` run would compile the toolchain again.
# The demo's extra: `weblab` (what the WebLab experiment needs beyond the toolchain and runtime).
# constraints.txt: the versions the transcripts were checked with (a newer OpenCV moves a figure).
$(STAMP): pyproject.toml constraints.txt | $(BIN)/python
	$(BIN)/python -m pip install -q -c constraints.txt -e '.[weblab]'
	$(BIN)/python -m compileall -q src > /dev/null
	touch $@

$(DEV_STAMP): pyproject.toml constraints.txt | $(BIN)/python
	$(BIN)/python -m pip install -q -c constraints.txt -e '.[dev,weblab,plots]'
	$(BIN)/python -m compileall -q src > /dev/null
	touch $@ $(STAMP)

# Services some tests need (EMF jars + JDK for the EMF load test, mosquitto for MQTT tests).
system-packages:
	@bash scripts/system-packages.sh $(SYSTEM_PACKAGES)

# The WebLab: check the model, generate its application (the WebLab's own code is in the user
# classes the build keeps), run the experiment of the paper's Table 1 (report in build/weblab-demo).
demo: $(STAMP)
	$(BIN)/acordcs-gen validate samples/weblab/weblab.xmi
	$(BIN)/acordcs-gen build -q samples/weblab/weblab.xmi -o samples/weblab/app
	cd samples/weblab && ../../$(BIN)/python -m weblab_experiment --out ../../build/weblab-demo

# The same generated application as two processes over Pyro5 on loopback, in real time, started
# and stopped by its generated scripts (samples/weblab/live.sh; WEBLAB_LIVE_SECONDS=60 caps the run).
live: $(STAMP)
	$(BIN)/acordcs-gen build samples/weblab/weblab.xmi -o samples/weblab/app
	PYTHON=$(abspath $(BIN)/python) sh samples/weblab/live.sh

# The same two processes with the WebLab console attached to them (docs/console.md), until Ctrl-C,
# which stops the console and both processes. LIVE_CONSOLE_ARGS: e.g. --port 8765.
LIVE_CONSOLE_ARGS ?=
live-console: $(STAMP)
	$(BIN)/acordcs-gen build samples/weblab/weblab.xmi -o samples/weblab/app
	PYTHON=$(abspath $(BIN)/python) sh samples/weblab/live.sh console $(LIVE_CONSOLE_ARGS)

# The WebLab console (docs/console.md): builds the application if needed, serves the console on
# 127.0.0.1 and prints its URL with the session's token. CONSOLE_ARGS: e.g. --port 8765 --speed 2.
CONSOLE_ARGS ?= --speed 1
console: $(STAMP)
	$(BIN)/acordcs-gen build samples/weblab/weblab.xmi -o samples/weblab/app > /dev/null
	cd samples/weblab && exec ../../$(BIN)/python -m weblab_console $(CONSOLE_ARGS)

test: $(DEV_STAMP) system-packages
	$(BIN)/python -m pytest -q

# The documentation site (MkDocs, Material theme) into site/; strict: a broken link fails.
docs: $(DEV_STAMP)
	NO_MKDOCS_2_WARNING=1 $(BIN)/python -m mkdocs build --strict

lint: $(DEV_STAMP)
	$(BIN)/ruff format --check src tests benchmarks samples tools
	$(BIN)/ruff check src tests benchmarks samples tools

format: $(DEV_STAMP)
	$(BIN)/ruff format src tests benchmarks samples tools
	$(BIN)/ruff check --fix src tests benchmarks samples tools

# A benchmark that exits 2 cannot run on this machine and said why (the scale test needs root
# for its network namespaces): the others still run, and the end names what was not run.
bench: $(DEV_STAMP)
	@skipped=""; for b in benchmarks/bench_*.py; do echo "== $$b"; $(BIN)/python $$b; rc=$$?; \
	  if [ $$rc -eq 2 ]; then skipped="$$skipped $$b"; elif [ $$rc -ne 0 ]; then exit 1; fi; done; \
	  if [ -n "$$skipped" ]; then echo "not run on this machine (each said why above):$$skipped"; fi

clean:
	rm -rf $(VENV) build site src/*.egg-info .pytest_cache
