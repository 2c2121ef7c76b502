# Every target sets itself up on a fresh machine: a local .venv with the Python tools, and
# the extension built in release mode. `make help` lists the targets.

PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
DEPS := $(VENV)/.deps-stamp
# NumPy's OpenBLAS threads busy-wait after each call; in benchmarks they took a core from
# the renderers being timed (about a tenth of the samples in a profile).
BENCH_ENV := OPENBLAS_NUM_THREADS=1 PYTHONPATH=$(CURDIR)
ENVS := VIRTUAL_ENV=$(abspath $(VENV)) PATH="$(abspath $(VENV))/bin:$$PATH"

.PHONY: help demo test test-bins lint build bench bench-aa bench-auto bench-batch bench-threads bench-shadows bench-textures bench-reflect bench-cold bench-peers docs-images wheel wheel-check clean fuzz

help:  ## list targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed 's/:.*## /\t/'

$(DEPS): pyproject.toml requirements-dev.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -r requirements-dev.txt
	touch $@

# The Python package is installed editable, so only the Rust sources (and the build
# configuration) make the extension stale; this stamp lets `make demo` skip a rebuild.
BUILT := $(VENV)/.build-stamp
RUST_SOURCES := $(shell find crates -name '*.rs' -o -name Cargo.toml) Cargo.toml Cargo.lock pyproject.toml

$(BUILT): $(DEPS) $(RUST_SOURCES)
	$(ENVS) $(PY) -m maturin develop --release -q
	touch $@

build: $(DEPS)  ## build the extension (release) into .venv
	$(ENVS) $(PY) -m maturin develop --release -q
	touch $(BUILT)

demo: $(BUILT)  ## render the built-in demo scene to demo.png (builds only when a source changed)
	$(PY) -m shadelab_rs demo -o demo.png

# Clippy and the test binaries build in a target directory of their own: cargo locks a
# target directory for a whole build, and the release build of the extension (one codegen
# unit, thin LTO) keeps one core busy for minutes, so `make test` builds the tests and runs
# clippy on the other core meanwhile.
TEST_TARGET := target/tests

lint: $(DEPS)  ## rustfmt, clippy (warnings are errors), ruff
	cargo fmt --all -- --check
	CARGO_TARGET_DIR=$(TEST_TARGET) PYO3_PYTHON=$(abspath $(PY)) cargo clippy --workspace --all-targets --features shadelab-raster/fuzzing -- -D warnings
	$(VENV)/bin/ruff check python tests bench shadelab_ref docs/lighting docs/first_minutes docs/antialiasing docs/edges docs/reflect docs/textures examples
	$(VENV)/bin/ruff format --check python tests bench shadelab_ref docs/lighting docs/first_minutes docs/antialiasing docs/edges docs/reflect docs/textures examples

test: $(DEPS)  ## lint, stub check, cargo test, pytest
	$(MAKE) --no-print-directory -j2 build test-bins lint
	$(PY) -m mypy.stubtest shadelab_rs._core
	$(PY) -m mypy python/shadelab_rs
	CARGO_TARGET_DIR=$(TEST_TARGET) cargo test --features fuzzing
	$(PY) -m pytest -q

# The Rust test binaries, built beside the extension (see TEST_TARGET).
test-bins: $(DEPS)
	CARGO_TARGET_DIR=$(TEST_TARGET) cargo test --features fuzzing --no-run

FUZZ_SECONDS ?= 60
FUZZ_TARGETS := obj_loader pipeline

# cargo-fuzz needs nightly; the crate in fuzz/ is its own workspace. New corpus entries go to
# fuzz/corpus/<target> (not committed), crashes to fuzz/artifacts/<target>; the committed
# seeds in fuzz/seeds/<target> are read too. No sanitizer (`-s none`), debug assertions on (`-a`):
# the targets look for panics and wrong results; the crate's few `unsafe` blocks (unaligned
# stores, unchecked float-to-int conversions, target-feature calls) each state why they are sound.
fuzz:  ## run each cargo-fuzz target for FUZZ_SECONDS seconds (default 60; needs nightly)
	@rustc +nightly --version >/dev/null 2>&1 || { echo "make fuzz: no nightly Rust toolchain (cargo-fuzz needs one): rustup toolchain install nightly" >&2; exit 1; }
	@cargo fuzz --version >/dev/null 2>&1 || cargo install cargo-fuzz --locked
	cd fuzz && cargo +nightly fuzz build -s none -a
	cd fuzz && for t in $(FUZZ_TARGETS); do \
		mkdir -p corpus/$$t logs && \
		cargo +nightly fuzz run -s none -a $$t corpus/$$t seeds/$$t -- \
			-max_total_time=$(FUZZ_SECONDS) -max_len=4096 -timeout=10 -rss_limit_mb=4096 \
			$$( [ -f $$t.dict ] && echo -dict=$$t.dict ) > logs/$$t.log 2>&1; \
		status=$$?; grep -E '^#[0-9]+[[:space:]]+DONE|^Done' logs/$$t.log; \
		[ $$status -eq 0 ] || { tail -30 logs/$$t.log; echo "make fuzz: $$t failed; see fuzz/logs/$$t.log and fuzz/artifacts/$$t" >&2; exit 1; }; \
	done

BENCH_DEPS := $(VENV)/.bench-stamp

$(BENCH_DEPS): bench/peers/install.sh bench/requirements-bench.txt $(DEPS)
	VENV=$(VENV) sh bench/peers/install.sh
	touch $@

bench-peers: $(BENCH_DEPS)  ## install the peers: Mesa llvmpipe (headless EGL, apt), moderngl, VTK, matplotlib

bench: build $(BENCH_DEPS)  ## benchmarks, speed against error, llvmpipe at 1 and 2 threads, shadows, textures, reflections, feature costs, many views, anti-aliasing, auto shading -> docs/BENCHMARKS.md, docs/FEATURE_COSTS.md, docs/ANTIALIASING.md, docs/COLD_START.md, docs/AUTO_SHADING.md (~60 min)
	$(BENCH_ENV) $(PY) bench/bench_render.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/speed_error.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/speed_error_vtk.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/bench_features.py --write docs/FEATURE_COSTS.md $(if $(AGAINST),--against-commit $(AGAINST))
	$(BENCH_ENV) $(PY) bench/bench_batch.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/bench_threads.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/bench_shadows.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/bench_textures.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/bench_reflect.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/bench_antialiasing.py --write docs/ANTIALIASING.md
	$(BENCH_ENV) $(PY) bench/bench_cold_start.py --write docs/COLD_START.md
	$(BENCH_ENV) $(PY) bench/bench_auto.py --write docs/AUTO_SHADING.md

bench-aa: build  ## anti-aliasing only: edge error against exact coverage, time per setting -> docs/ANTIALIASING.md (~3 min)
	$(BENCH_ENV) $(PY) bench/bench_antialiasing.py --write docs/ANTIALIASING.md

bench-threads: build $(BENCH_DEPS)  ## ours against llvmpipe at 1 and at 2 threads, one process per thread count -> docs/BENCHMARKS.md (~8 min)
	$(BENCH_ENV) $(PY) bench/bench_threads.py --write docs/BENCHMARKS.md

bench-shadows: build $(BENCH_DEPS)  ## shadow maps against llvmpipe's (GLSL depth pass + sampler2DShadow PCF) and exact rays at 1 and 2 threads, one process per thread count: time and error -> docs/BENCHMARKS.md (~1 min)
	$(BENCH_ENV) $(PY) bench/bench_shadows.py --write docs/BENCHMARKS.md

bench-textures: build $(BENCH_DEPS)  ## texture filters against the exact area-filtered checkerboard, ours and llvmpipe's: RMSE and time per filter -> docs/BENCHMARKS.md (~2 min)
	$(BENCH_ENV) $(PY) bench/bench_textures.py --write docs/BENCHMARKS.md

bench-reflect: build $(BENCH_DEPS)  ## reflections and refractions: environment lookup vs Whitted rays, error against the float64 tracer and time, llvmpipe's environment lookup at 1 and 2 threads -> docs/BENCHMARKS.md (~5 min)
	$(BENCH_ENV) $(PY) bench/bench_reflect.py --write docs/BENCHMARKS.md

bench-batch: build  ## many views only: render_batch vs loop vs 2 processes, pickling -> docs/BENCHMARKS.md (~2 min)
	$(BENCH_ENV) $(PY) bench/bench_batch.py --write docs/BENCHMARKS.md

bench-auto: build  ## shading="auto" only: its choice, error and time against the fastest fixed mode meeting the tolerance -> docs/AUTO_SHADING.md (~30 min)
	$(BENCH_ENV) $(PY) bench/bench_auto.py --write docs/AUTO_SHADING.md

bench-cold: build  ## cold start only: import time, first picture, save_image per PNG compression -> docs/COLD_START.md (~1 min)
	$(BENCH_ENV) $(PY) bench/bench_cold_start.py --write docs/COLD_START.md

docs-images: build  ## render the guides' images -> docs/lighting/*.png, docs/first_minutes/*.png, docs/antialiasing/*.png, docs/edges/*.png, docs/reflect/*.png, docs/textures/*.png
	$(PY) docs/lighting/make_images.py
	$(PY) docs/first_minutes/make_images.py
	$(PY) docs/antialiasing/make_images.py
	$(PY) docs/edges/make_images.py
	$(PY) docs/reflect/make_images.py
	$(PY) docs/textures/make_gallery.py

# manylinux2014 (glibc 2.17: Ubuntu 18.04+, RHEL 7+) through zig as the linker, from the
# ziglang package on PyPI: no Docker. Without --zig the wheel would need this machine's glibc.
WHEEL_TAG := manylinux2014_x86_64.manylinux_2_17_x86_64

wheel: $(DEPS)  ## build a release manylinux2014 abi3 wheel into dist/
	$(PY) -m pip install -q "ziglang<0.14"
	rm -f dist/shadelab_rs-*.whl
	$(ENVS) $(PY) -m maturin build --release --zig --compatibility manylinux2014 -o dist

clean:  ## remove build products and the venv
	cargo clean
	rm -rf $(VENV) dist demo.png

wheel-check: wheel  ## check the wheel's tag and LICENSE, install it into a fresh venv, render
	@whl=$$(ls dist/shadelab_rs-*.whl); echo "$$whl"; \
	case "$$whl" in *-cp39-abi3-$(WHEEL_TAG).whl) ;; \
	  *) echo "wheel-check: expected an abi3 $(WHEEL_TAG) wheel, got $$whl" >&2; exit 1;; esac; \
	$(PY) -c "import sys, zipfile; n = zipfile.ZipFile(sys.argv[1]).namelist(); assert any(p.endswith('LICENSE') for p in n), 'no LICENSE in the wheel'" "$$whl"; \
	tmp=$$(mktemp -d); trap 'rm -rf "$$tmp"' EXIT; \
	$(PYTHON) -m venv "$$tmp/venv" && \
	"$$tmp/venv/bin/pip" install -q "$$whl" && \
	cd "$$tmp" && "$$tmp/venv/bin/python" -c "import shadelab_rs as sl; s, c = sl.demo_scene(); im = sl.render(s, c, width=160, height=120); assert im.shape == (120, 160, 3) and im.max() > 0; print('wheel OK', sl.__version__, im.mean())" && \
	"$$tmp/venv/bin/shadelab" demo -o "$$tmp/demo.png" --size 160x120
