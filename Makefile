# Thin wrapper over CMake. `make demo` and `make test` install what is
# missing (Debian packages, via .ci/deps), configure build/, build and run.
BUILD ?= build
CMAKE_FLAGS ?=
JOBS ?= $(shell nproc 2>/dev/null || echo 2)

.PHONY: all deps configure build demo test bench clean

all: build

deps:
	@bash .ci/deps

configure: deps
	cmake -S . -B $(BUILD) -DGEOM_WERROR=ON -DGEOM_BUILD_TESTS=ON -DGEOM_VALIDATE=ON $(CMAKE_FLAGS)

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# The demo installs and builds only what it needs: the library and the tools
# (no tests, no validation shim), with cJSON and libspng.
demo:
	@bash .ci/deps demo
	cmake -S . -B $(BUILD) -DGEOM_WERROR=ON -DGEOM_BUILD_TESTS=OFF -DGEOM_VALIDATE=OFF $(CMAKE_FLAGS)
	cmake --build $(BUILD) -j $(JOBS)
	@bash tools/demo.sh $(BUILD)

test: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS)

bench:
	@bash .ci/deps bench
	cmake -S . -B $(BUILD) -DGEOM_WERROR=ON $(CMAKE_FLAGS)
	cmake --build $(BUILD) -j $(JOBS)
	cmake --build $(BUILD) --target bench

clean:
	rm -rf $(BUILD)
