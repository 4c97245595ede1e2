PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
TSTAMP := $(VENV)/.installed-test
DSTAMP := $(VENV)/.installed-docs
# pytest-xdist workers for `make test` (0: one process)
TEST_WORKERS ?= 2

.PHONY: demo test validate bench lint docs clean

$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

# pip's own byte-compilation of the installed packages runs on one core (half of the install's
# time); compileall -j 0 does the same on all of them (BENCHMARKS.md, session 28)
COMPILE := $(BIN)/python -m compileall -q -j 0 $(VENV)/lib > /dev/null

$(STAMP): $(BIN)/python pyproject.toml
	$(BIN)/python -m pip install -q --no-compile -e .
	$(COMPILE)
	touch $@

$(TSTAMP): $(STAMP) pyproject.toml
	$(BIN)/python -m pip install -q --no-compile -e ".[test,records,dask]"
	$(COMPILE)
	touch $@

demo: $(STAMP)
	$(BIN)/murus demo --out out/demo

test: $(TSTAMP)
	$(BIN)/python -m ruff check src tests benchmarks validation
	$(BIN)/python -m pytest -q -n $(TEST_WORKERS) --dist load

validate: $(TSTAMP)
	$(BIN)/python validation/run.py --out VALIDATION.md

bench: $(TSTAMP)
	$(BIN)/python -m pip install -q --no-compile -e ".[bench]"
	$(COMPILE)
	$(BIN)/python benchmarks/run.py

$(DSTAMP): $(STAMP) pyproject.toml
	$(BIN)/python -m pip install -q --no-compile -e ".[docs]"
	$(COMPILE)
	touch $@

# the documentation site, into docs/_build/html/ (offline; warnings are errors). The gallery runs
# its scripts; `make docs SPHINXOPTS="-D plot_gallery=0"` skips running them.
SPHINXOPTS ?=
docs: $(DSTAMP)
	$(BIN)/python -m sphinx -W --keep-going -b html $(SPHINXOPTS) docs docs/_build/html

clean:
	rm -rf $(VENV) out .pytest_cache docs/_build docs/api docs/gallery docs/_generated \
		docs/sg_execution_times.rst
