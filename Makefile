# adamss: the README's two commands.
#   make heart   install dependencies if missing, build, run the heart case end to end
#   make test    install dependencies if missing, build, run the whole test suite
BUILD_DIR ?= build
JOBS ?= 2
CMAKE_FLAGS ?=
HEART_OUT ?= results/heart
# OpenMP threads sleep instead of spinning while they wait: on a machine busy with other work
# (CI running two tests at once on two cores) spinning made a 2-thread run 60x slower.
OMP_WAIT_POLICY ?= passive
export OMP_WAIT_POLICY
# ccache (used when installed, CMakeLists.txt): paths relative to the clone, so clones share objects.
CCACHE_BASEDIR ?= $(CURDIR)
export CCACHE_BASEDIR

FUZZ_SECONDS ?= 60

.PHONY: all deps configure build test heart bench fuzz sanitize sanitize-ci clean format lint

all: build

deps:
	@scripts/install-deps

configure: deps
	@cmake -S . -B $(BUILD_DIR) -DCMAKE_BUILD_TYPE=Release $(CMAKE_FLAGS) > $(BUILD_DIR).configure.log 2>&1 \
	  || (cat $(BUILD_DIR).configure.log; exit 1)
	@echo "configured $(BUILD_DIR) (log: $(BUILD_DIR).configure.log)"

build: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS)

test: build
	@cd $(BUILD_DIR) && ctest --output-on-failure -j $(JOBS)

# make heart: the real heart by default, biv-me patient1 of ../shared/anatomy (cases/heart/run_image.sh:
# unloading and two beats of both ventricles; results in results/heart). HEART_IMAGE=PATH: any label
# image in that convention (1 wall, 2 LV, 3 RV if any; results in results/heart-image/<the image's
# folder name> unless HEART_OUT is given). HEART_IMAGE=phantom, or no anatomy folder beside the
# clone: the phantom case (cases/heart/run.sh: the Land LV ellipsoid, healthy and scarred, and the
# biventricular phantom).
BIVME_IMAGE := ../shared/anatomy/bivme_patient1/labels_frame000_1mm.nii.gz
heart: build
	@image="$(HEART_IMAGE)"; out="$(HEART_OUT)"; \
	if [ -z "$$image" ]; then \
	  if [ -f "$(BIVME_IMAGE)" ]; then image="$(BIVME_IMAGE)"; \
	  else echo "make heart: $(BIVME_IMAGE) not found (the shared anatomy folder beside the clone): running the phantom case"; image=phantom; fi; \
	elif [ "$$image" != phantom ] && [ "$(origin HEART_OUT)" = file ]; then \
	  out=results/heart-image/$$(basename "$$(dirname "$$image")"); \
	fi; \
	if [ "$$image" = phantom ]; then \
	  cases/heart/run.sh $(BUILD_DIR)/app/adamss "$$out"; \
	else \
	  cases/heart/run_image.sh $(BUILD_DIR)/app/adamss "$$image" "$$out"; \
	fi

# Benchmarks (issue 9; bench/README.md), never part of `make test`: Release build of the bench
# targets and the app, STREAM bandwidth, kernel + explicit-step Google Benchmarks, the HybMSS cube,
# the speed/error Pareto runs when bench/pareto/run.sh exists, then bench/report.md with the plots.
# BENCH_QUICK=1: small sizes and short timings, no Pareto part (a smoke run; use another
# BENCH_RESULTS so the committed results are not overwritten).
BENCH_RESULTS ?= bench/results
BENCH_QUICK ?= 0
export BENCH_QUICK
bench: configure
	@cmake --build $(BUILD_DIR) -j $(JOBS) --target bench_forces stream adamss
	@mkdir -p $(BENCH_RESULTS)
	@$(BUILD_DIR)/bench/stream $(BENCH_RESULTS)/stream.json $(if $(filter 1,$(BENCH_QUICK)),40 3,80 10)
	@$(BUILD_DIR)/bench/bench_forces --benchmark_counters_tabular=true \
	  --benchmark_out=$(BENCH_RESULTS)/kernels.json --benchmark_out_format=json
	@bench/hybmss_cube.sh $(BUILD_DIR)/app/adamss $(BENCH_RESULTS)/hybmss_cube.json
	@bench/solver.sh $(BUILD_DIR)/app/adamss $(BENCH_RESULTS)/solver.json
	@bench/solver_scaling.sh $(BUILD_DIR)/app/adamss $(BENCH_RESULTS)/solver_scaling.json
	@if [ "$(BENCH_QUICK)" != 1 ]; then bench/mpi.sh $(BUILD_DIR)/app/adamss $(BENCH_RESULTS)/mpi.json; fi
	@if [ -f bench/pareto/run.sh ] && [ "$(BENCH_QUICK)" != 1 ]; then \
	  bash bench/pareto/run.sh $(BUILD_DIR)/app/adamss $(BENCH_RESULTS); fi
	@bench/make_report.sh $(BENCH_RESULTS) $(BUILD_DIR) $(if $(filter bench/results,$(BENCH_RESULTS)),bench/report.md,$(BENCH_RESULTS)/report.md)

# libFuzzer on the NIfTI reader, the mesh.h5 reader and the scene parser (clang, ASan + UBSan, in
# build-fuzz/), FUZZ_SECONDS per target; findings fail and leave a reproducer (fuzz/README.md).
fuzz: deps
	@CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DADAMSS_FUZZ=ON \
	  -DADAMSS_FUZZ_SECONDS=$(FUZZ_SECONDS) > build-fuzz.configure.log 2>&1 || (cat build-fuzz.configure.log; exit 1)
	@cmake --build build-fuzz -j $(JOBS) --target fuzz_nifti fuzz_mesh_h5 fuzz_scene
	@cd build-fuzz && ctest -L fuzz --output-on-failure

# The unit tests under AddressSanitizer + UndefinedBehaviorSanitizer (gcc, build-asan/).
sanitize: deps
	@cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DADAMSS_SANITIZE=ON > build-asan.configure.log 2>&1 \
	  || (cat build-asan.configure.log; exit 1)
	@cmake --build build-asan -j $(JOBS)
	@cd build-asan && ASAN_OPTIONS=detect_leaks=0 ctest -L unit --output-on-failure -j $(JOBS)

# CI's second step (.ci/run, after make test): every test executable under AddressSanitizer +
# UndefinedBehaviorSanitizer (gcc -O1 -g1, build-asan/; the CGAL mesher's one file is built without
# instrumentation: preprocess/CMakeLists.txt), two at a time, with leak detection on
#. tests/app runs the sanitized adamss
# executable. The fuzz drivers' quick runs stay in make test. Times: fuzz/README.md.
SANITIZE_CI_TESTS ?= test_solver test_app test_preprocess test_verify test_materials test_common
sanitize-ci: deps
	@cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DADAMSS_SANITIZE=ON > build-asan.configure.log 2>&1 \
	  || (cat build-asan.configure.log; exit 1)
	@cmake --build build-asan -j $(JOBS) --target $(SANITIZE_CI_TESTS)
	@SANITIZE_JOBS=$(JOBS) scripts/sanitize-tests build-asan $(SANITIZE_CI_TESTS)

# clang-tidy-14 with the committed .clang-tidy over the library (scripts/lint; any warning fails;
# no build needed, only compile_commands.json). LINT_ARGS="--changed origin/main": only the changes.
LINT_ARGS ?=
lint: configure
	@BUILD_DIR=$(BUILD_DIR) LINT_JOBS=$(JOBS) scripts/lint $(LINT_ARGS)

format:
	@git ls-files '*.cpp' '*.hpp' | xargs clang-format -i

clean:
	@rm -rf $(BUILD_DIR) $(BUILD_DIR).configure.log
