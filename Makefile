# scenariominer: the two entry points are `make demo` and `make test` (see README.md).
# Everything is installed into .venv from the package registry; nothing is downloaded at run time.

PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip
EXTRAS ?= llm,embed,av2eval,mine,ann,sim,represent,cbr,server,ray,dev
# llama.cpp is built for a portable AVX2 CPU: a native build enables AMX tiles (segfault in decode on
# some of these machines) and AVX-512 (SIGILL on others).
LLAMA_CMAKE_ARGS := -DGGML_NATIVE=OFF -DGGML_AVX2=ON -DGGML_FMA=ON -DGGML_F16C=ON -DGGML_AVX512=OFF -DGGML_AMX_INT8=OFF -DGGML_AMX_TILE=OFF
STAMP  := $(VENV)/.installed-$(shell cat pyproject.toml | sha256sum | cut -c1-12)
# llama-cpp-python is compiled once into this wheelhouse and reused by every later install
# (CI on the same machine included), because the build takes minutes on 2 cores.
LLAMA_VERSION := 0.3.16
WHEELHOUSE ?= $(HOME)/.cache/scenariominer/wheels
LLAMA_WHEEL_STAMP := $(WHEELHOUSE)/.llama-cpp-python-$(LLAMA_VERSION)
DEMO_OUT ?= demo-out

.PHONY: install browser demo test lint typecheck unit bench clean

install: $(STAMP)

$(STAMP): pyproject.toml $(LLAMA_WHEEL_STAMP)
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PIP) install --quiet --upgrade pip wheel setuptools
	# CPU build of torch from the local wheel (an unpinned torch pulls GB of CUDA packages).
	$(PIP) install --quiet torch==2.13.0
	$(PIP) install --quiet --find-links $(WHEELHOUSE) -e ".[$(EXTRAS)]"
	rm -f $(VENV)/.installed-*
	touch $@

$(LLAMA_WHEEL_STAMP):
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	mkdir -p $(WHEELHOUSE)
	@echo "building llama-cpp-python $(LLAMA_VERSION) for this CPU (AMX off; about 5 minutes, once)"
	CMAKE_ARGS="$(LLAMA_CMAKE_ARGS)" FORCE_CMAKE=1 $(PIP) wheel --quiet --no-deps --no-cache-dir \
		--wheel-dir $(WHEELHOUSE) llama-cpp-python==$(LLAMA_VERSION)
	touch $@

demo: install
	$(VENV)/bin/scenariominer demo --out $(DEMO_OUT)

lint: install
	$(VENV)/bin/ruff check src tests benchmarks
	$(VENV)/bin/ruff format --check src tests benchmarks

typecheck: install
	$(VENV)/bin/mypy

# The UI test (tests/server/test_browser.py) drives the distribution's Chromium and chromedriver:
# installed with apt-get when missing and possible (CI runs as root); otherwise that test is skipped.
browser:
	@if command -v chromium >/dev/null 2>&1 && command -v chromedriver >/dev/null 2>&1; then :; \
	elif command -v apt-get >/dev/null 2>&1 && [ "$$(id -u)" = 0 ]; then \
		(apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium chromium-driver \
			>/dev/null) || echo "could not install chromium: the browser test will be skipped"; \
	else echo "no chromium/chromedriver and no apt-get as root: the browser test will be skipped"; fi

# pytest exits 5 when it collected no tests: that is a failure here, said out loud.
unit: install browser
	$(PY) -m pytest; rc=$$?; \
	if [ $$rc -eq 5 ]; then echo "pytest collected no tests (exit 5): failing" >&2; exit 1; fi; exit $$rc

test: install lint typecheck unit

bench: install
	$(PY) benchmarks/ingest.py --n 50
	$(PY) benchmarks/tagging.py

clean:
	rm -rf $(VENV) $(DEMO_OUT) .pytest_cache .mypy_cache .ruff_cache
