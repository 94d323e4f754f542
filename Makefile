# floorscan: `make test` and `make demo` work on a fresh machine; each installs what it needs
# into ./.venv (Python packages) and builds the Rust extension there.

VENV    ?= .venv
PYTHON  ?= python3
PY      := $(VENV)/bin/python
STAMP   := $(VENV)/.deps-stamp
CARGO   ?= cargo

.PHONY: test demo dev deps lint fmt bench bench-py clean rust-toolchain fuzz stubs wheels test-aarch64

FUZZ_CASES   ?= 20000
FUZZ_SECONDS ?= 600

rust-toolchain:
	@command -v $(CARGO) >/dev/null 2>&1 || { \
	  echo "cargo not found: installing Rust from Debian's packages"; \
	  (apt-get update -qq && apt-get install -y -qq cargo rustc) || \
	  { echo "error: install Rust (https://rustup.rs) and re-run"; exit 1; }; }

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q "maturin>=1.5,<2" "numpy>=1.21" "pillow>=9" "opencv-python-headless>=4.5" "pyyaml>=5.1" "tomlkit>=0.11" "tqdm>=4.60" "matplotlib>=3.5" \
	    "pytest>=7" "hypothesis>=6" "rosbags>=0.9" "ray>=2.9" "eclipse-zenoh>=1.0,<2" \
	    "foxglove-sdk>=0.30,<1" "websockets>=12" "protobuf>=4" "gtsam>=4.2" ruff
	touch $@

deps: $(STAMP)

# Builds the extension in release mode and installs the package in the venv (editable).
dev: rust-toolchain deps
	VIRTUAL_ENV=$(abspath $(VENV)) PATH=$(abspath $(VENV))/bin:$$PATH \
	    $(VENV)/bin/maturin develop --release -q

# The type stubs of floorscan._native, generated from the bindings (pyo3-introspection reads the
# metadata PyO3 compiles into the extension); `make test` fails when they are stale.
stubs: dev
	$(CARGO) run -q -p floorscan-stubgen -- \
	    "$$($(PY) -c 'import floorscan._native as n; print(n.__file__)')" python/floorscan/_native

test: dev
	$(CARGO) test --workspace -q
	$(PY) -m pytest -q

# Fuzzing (issues 12, 14), bounded in time: proptest targets of the Rust parsers (the PNG decoder
# too) and FFI entry points with FUZZ_CASES random cases each, then hypothesis on the Python readers (the "fuzz" profile).
# Each stage stops after FUZZ_SECONDS. `make test` runs the short deterministic corpus of both.
fuzz: dev
	FLOORSCAN_FUZZ=1 PROPTEST_CASES=$(FUZZ_CASES) timeout $(FUZZ_SECONDS) \
	    $(CARGO) test --release -q -p floorscan-core -p floorscan-sim -p floorscan-codec --test fuzz
	FLOORSCAN_HYPOTHESIS_PROFILE=fuzz timeout $(FUZZ_SECONDS) \
	    $(PY) -m pytest -q -p no:cacheprovider tests/test_fuzz_readers.py

# abi3 manylinux2014 wheels (CPython >= 3.9) for x86_64 and aarch64 into dist/, cross-compiled
# with zig (PyPI's ziglang) as the linker: no aarch64 toolchain, no container.
WHEEL_TARGETS ?= x86_64-unknown-linux-gnu aarch64-unknown-linux-gnu
wheels: rust-toolchain deps
	$(PY) -m pip install -q "ziglang>=0.11"
	@for t in $(WHEEL_TARGETS); do \
	  rustup target list --installed 2>/dev/null | grep -qx $$t || rustup target add $$t || \
	    { echo "error: the $$t standard library is missing: install rustup (https://rustup.rs)"; exit 1; }; \
	  PATH=$(abspath $(VENV))/bin:$$PATH $(VENV)/bin/maturin build --release -q --zig \
	    --target $$t --compatibility manylinux2014 -o dist || exit 1; \
	done

# The Rust crates' tests compiled for aarch64 and run under qemu-user (Debian's qemu-user and
# gcc-aarch64-linux-gnu as the linker): the NEON kernels against the portable ones, bit for bit.
AARCH64_ENV := CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc \
	CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_RUNNER="qemu-aarch64 -L /usr/aarch64-linux-gnu"
test-aarch64: rust-toolchain
	@command -v qemu-aarch64 >/dev/null 2>&1 && command -v aarch64-linux-gnu-gcc >/dev/null 2>&1 || \
	  (apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq \
	     qemu-user gcc-aarch64-linux-gnu libc6-arm64-cross)
	rustup target list --installed 2>/dev/null | grep -qx aarch64-unknown-linux-gnu || \
	  rustup target add aarch64-unknown-linux-gnu || \
	  { echo "error: the aarch64 standard library is missing: install rustup (https://rustup.rs)"; exit 1; }
	$(AARCH64_ENV) $(CARGO) clippy -q --target aarch64-unknown-linux-gnu --all-targets \
	  -p floorscan-core -p floorscan-sim -p floorscan-py -- -D warnings
	$(AARCH64_ENV) $(CARGO) test -q --target aarch64-unknown-linux-gnu -p floorscan-core -p floorscan-sim

demo: dev
	$(VENV)/bin/floorscan demo -o demo-out --force

lint: deps
	$(CARGO) fmt --all -- --check
	$(CARGO) clippy --workspace --all-targets -q -- -D warnings
	$(VENV)/bin/ruff check python tests bench
	$(VENV)/bin/ruff format --check python tests bench

fmt: deps
	$(CARGO) fmt --all
	$(VENV)/bin/ruff format python tests bench
	$(VENV)/bin/ruff check --fix python tests bench

bench: dev
	$(CARGO) bench -p floorscan-core
	$(CARGO) bench -p floorscan-sim
	$(PY) -m pytest -q -m benchmark -s

clean:
	rm -rf $(VENV) target demo-out
