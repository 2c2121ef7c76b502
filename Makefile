# Every target sets itself up on a fresh machine: a local .venv with the Python tools, and
# the extension built in release mode. `make help` lists the targets.

PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
DEPS := $(VENV)/.deps-stamp
# NumPy's OpenBLAS threads busy-wait after each call; in benchmarks they took a core from
# the renderers being timed (about a tenth of the samples in a profile).
BENCH_ENV := OPENBLAS_NUM_THREADS=1
ENVS := VIRTUAL_ENV=$(abspath $(VENV)) PATH="$(abspath $(VENV))/bin:$$PATH"

.PHONY: help demo test lint build bench bench-batch bench-peers docs-images wheel wheel-check clean fuzz

help:  ## list targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | sed 's/:.*## /\t/'

$(DEPS): pyproject.toml requirements-dev.txt
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -r requirements-dev.txt
	touch $@

build: $(DEPS)  ## build the extension (release) into .venv
	$(ENVS) $(PY) -m maturin develop --release -q

demo: build  ## render the built-in demo scene to demo.png
	$(PY) -m shadelab_rs demo -o demo.png

lint: $(DEPS)  ## rustfmt, clippy (warnings are errors), ruff
	cargo fmt --all -- --check
	PYO3_PYTHON=$(abspath $(PY)) cargo clippy --workspace --all-targets -- -D warnings
	$(VENV)/bin/ruff check python tests bench docs/lighting examples
	$(VENV)/bin/ruff format --check python tests bench docs/lighting examples

test: lint build  ## lint, stub check, cargo test, pytest
	$(PY) -m mypy.stubtest shadelab_rs._core
	$(PY) -m mypy python/shadelab_rs
	cargo test
	$(PY) -m pytest -q

FUZZ_SECONDS ?= 60
FUZZ_TARGETS := obj_loader pipeline

# cargo-fuzz needs nightly; the crate in fuzz/ is its own workspace. New corpus entries go to
# fuzz/corpus/<target> (not committed), crashes to fuzz/artifacts/<target>; the committed
# seeds in fuzz/seeds/<target> are read too. No sanitizer: the renderer has no unsafe code.
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

bench: build $(BENCH_DEPS)  ## benchmarks, speed against error, llvmpipe, feature costs, many views -> docs/BENCHMARKS.md, docs/FEATURE_COSTS.md (~27 min)

bench-batch: build  ## many views only: render_batch vs loop vs 2 processes, pickling -> docs/BENCHMARKS.md (~2 min)
	$(BENCH_ENV) $(PY) bench/bench_batch.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/bench_render.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/speed_error.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/speed_error_vtk.py --write docs/BENCHMARKS.md
	$(BENCH_ENV) $(PY) bench/bench_features.py --write docs/FEATURE_COSTS.md $(if $(AGAINST),--against-commit $(AGAINST))
	$(BENCH_ENV) $(PY) bench/bench_batch.py --write docs/BENCHMARKS.md

docs-images: build  ## render the lighting guide's images -> docs/lighting/*.png
	$(PY) docs/lighting/make_images.py

wheel: $(DEPS)  ## build a release wheel into dist/
	$(ENVS) $(PY) -m maturin build --release -o dist

clean:  ## remove build products and the venv
	cargo clean
	rm -rf $(VENV) dist demo.png

wheel-check: wheel  ## install the built wheel into a fresh venv and render with it
	rm -rf /tmp/shadelab-wheel-venv
	$(PYTHON) -m venv /tmp/shadelab-wheel-venv
	/tmp/shadelab-wheel-venv/bin/pip install -q dist/shadelab_rs-*.whl
	cd /tmp && /tmp/shadelab-wheel-venv/bin/python -c "import shadelab_rs as sl; s, c = sl.demo_scene(); im = sl.render(s, c, width=160, height=120); assert im.shape == (120, 160, 3) and im.max() > 0; print('wheel OK', sl.__version__, im.mean())"
	cd /tmp && /tmp/shadelab-wheel-venv/bin/shadelab demo -o /tmp/shadelab-wheel-demo.png --size 160x120
