#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# One-command set-up for a fresh Debian 12 machine (README "Quick start").
#   ./tumble.sh run [SCENE.toml] [tumble run options]   install, build, run a scene (default: molecules)
#   ./tumble.sh test                                     install, build, run every test
#   ./tumble.sh build                                    install and build only
#   ./tumble.sh sanitize                                 the tests again in an ASan + UBSan build (build-sanitize)
#   ./tumble.sh tsan                                     the threaded tests under ThreadSanitizer (build-tsan)
#   ./tumble.sh fuzz [SECONDS] [TARGET...]               each libFuzzer target SECONDS (default 60) on its corpus (build-fuzz)
# Environment: BUILD_DIR (default build), JOBS (default: all cores), TUMBLE_ENABLE_CUDA (AUTO|ON|OFF),
# TUMBLE_CUDA_ARCHITECTURES (nvcc's targets, e.g. "90"; default 80 and 90, what CI builds too),
# TUMBLE_TIMINGS (a file: each step's seconds are appended to it, "command step<TAB>seconds";
# .ci/run prints them as its stage table).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${BUILD_DIR:-$here/build}
jobs=${JOBS:-$(nproc)}
packages=(g++ cmake ninja-build pkg-config libtbb-dev libeigen3-dev libtomlplusplus-dev libcli11-dev
          libgtest-dev libgmock-dev libbenchmark-dev
          libglfw3-dev libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libimgui-dev libpng-dev
          ffmpeg xvfb xauth xdotool gnuplot-nox fonts-dejavu-core
          python3-dev pybind11-dev python3-numpy
          openmpi-bin libopenmpi-dev)
# What only the tests need: pytest for the Python module, VTK's reader for the export test.
test_packages=(python3-pytest python3-vtk9)

# timed STEP CMD...: runs CMD; with TUMBLE_TIMINGS set, appends "<command> STEP<TAB>seconds" to it
# (also when CMD fails). Returns CMD's status. CMD runs in a subshell with `set -e` on: a shell
# function stops at its first failing command, as it would unwrapped (`CMD || rc=$?` would turn
# -e off inside it; so does calling timed itself in a condition). CMD cannot set this shell's
# variables.
timed() {
  local step=$1 t0=$SECONDS rc=0
  shift
  set +e
  (set -e; "$@")
  rc=$?
  set -e
  if [ -n "${TUMBLE_TIMINGS:-}" ]; then printf '%s %s\t%d\n' "$cmd" "$step" $((SECONDS - t0)) >>"$TUMBLE_TIMINGS"; fi
  return $rc
}

install_packages() {
  local missing=()
  for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  echo "tumble.sh: installing ${missing[*]}" >&2
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
}

# Debian's source index (for apt-get source), from the Debian archives already configured, when
# no deb-src line is there: /etc/apt/sources.list.d/tumble-src.{sources,list}.
ensure_deb_src() {
  grep -rqsE '^[[:space:]]*(Types:.*deb-src|deb-src[[:space:]])' /etc/apt/sources.list /etc/apt/sources.list.d/ && return 0
  local sudo=""
  [ "$(id -u)" -ne 0 ] && sudo="sudo"
  echo "tumble.sh: adding the deb-src lines of the configured Debian archives (/etc/apt/sources.list.d/tumble-src.*)" >&2
  local f
  for f in /etc/apt/sources.list.d/*.sources; do
    if [ -f "$f" ] && grep -qE '^URIs:.*/debian' "$f"; then
      sed 's/^Types:[[:space:]]*deb[[:space:]]*$/Types: deb-src/' "$f"
      echo
    fi
  done | $sudo tee /etc/apt/sources.list.d/tumble-src.sources >/dev/null
  [ ! -f /etc/apt/sources.list ] || sed -n 's/^deb[[:space:]]\(.*\/debian.*\)/deb-src \1/p' /etc/apt/sources.list |
    $sudo tee /etc/apt/sources.list.d/tumble-src.list >/dev/null
  $sudo apt-get update -qq
}

# ccache (Debian's) when it is installed: a second build of the same sources (another checkout, a
# rerun on the same machine) takes minutes less. Nothing is installed for it.
launcher=()
if command -v ccache >/dev/null 2>&1; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi

# The flags of the sanitizer builds (sanitize, tsan, fuzz): -O1 and line tables only (-g1), as
# OSS-Fuzz builds: reports keep their file:line stacks, and the build takes about a third of the
# time of -O2 -g (the fused step pass, cpu/src/cpu_pipeline.cpp: 181 s against 596 s under ASan
# + UBSan on the 2-core development machine).
sanitize_flags=(-DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG")

# configure_and_build [TARGET...]: the Release build in $build (every target, or those named).
configure_and_build() {
  local archs=()
  if [ -n "${TUMBLE_CUDA_ARCHITECTURES:-}" ]; then archs=(-DCMAKE_CUDA_ARCHITECTURES="$TUMBLE_CUDA_ARCHITECTURES"); fi
  timed configure cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release "${launcher[@]}" "${archs[@]}" \
        -DTUMBLE_ENABLE_CUDA="${TUMBLE_ENABLE_CUDA:-AUTO}" -DTUMBLE_WERROR=ON >/dev/null
  if [ $# -gt 0 ]; then
    timed build cmake --build "$build" -j "$jobs" --target "$@"
  else
    timed build cmake --build "$build" -j "$jobs"
  fi
}

# ctest_longest_first DIR: ctest starts the tests it has timed before longest first. A build that
# has never run its tests borrows the Release build's timings (the same test names), so that the
# long tests do not start last and leave one core idle at the end.
ctest_longest_first() {
  local costs=Testing/Temporary/CTestCostData.txt
  if [ ! -f "$1/$costs" ] && [ -f "$here/build/$costs" ] && [ "$1" != "$here/build" ]; then
    mkdir -p "$1/Testing/Temporary" && cp "$here/build/$costs" "$1/$costs"
  fi
}

# The tests `tsan` runs (a ctest regex; TSAN_TESTS overrides it): every parallel stage of both
# pipelines (detection, contact list, forces, integration, guard sums, checkpoints) with 1 to 4
# threads, the CUDA pipeline's on the host backend (its forEach: one writer per element).
tsan_tests='SameResultForAnyThreadCount|PeriodicCudaPipeline|StepPairsMatchBruteForceOnTheBenchScene|PipelineContactSumsEqualThoseOfItsPairs|DeterminismTest|CheckpointTest|HaloPipelineTest|CudaHostBroadphase|GpuSmokeTest'
# The test programs that hold them: `tsan` builds only these.
tsan_targets=(tumble_validation_tests tumble_gpu_tests tumble_mpi_tests)

cmd=${1:-run}
[ $# -gt 0 ] && shift
case "$cmd" in
  build)
    timed install install_packages; configure_and_build ;;
  run)
    # Only the tumble command: the first run does not wait for the tests to build.
    timed install install_packages; configure_and_build tumble
    scene=$here/scenes/molecules.toml
    if [ $# -gt 0 ] && [[ "$1" != -* ]]; then scene=$1; shift; fi
    exec "$build/examples/tumble" run "$scene" "$@" ;;
  test)
    packages+=("${test_packages[@]}")
    timed install install_packages; configure_and_build
    cd "$build"
    timed tests ctest --output-on-failure -j "$jobs" ;;
  sanitize)
    # Address and undefined-behaviour sanitizers on every test (CI runs this after `test`).
    packages+=("${test_packages[@]}")
    timed install install_packages
    build=${SANITIZE_BUILD_DIR:-$here/build-sanitize}
    timed configure cmake -S "$here" -B "$build" -G Ninja "${sanitize_flags[@]}" "${launcher[@]}" \
          -DTUMBLE_ENABLE_CUDA=OFF -DTUMBLE_SANITIZE=ON -DTUMBLE_BUILD_BENCH=OFF >/dev/null
    timed build cmake --build "$build" -j "$jobs"
    ctest_longest_first "$build"
    cd "$build"
    # Leaks are checked everywhere except in the viewer's tests, where Mesa's EGL drivers keep a
    # few allocations to the end of the process (112 bytes, inside the driver), and in tumble run
    # under mpirun, where Open MPI does the same (MPI_Init's allocations outlive MPI_Finalize):
    # those tests carry ASAN_OPTIONS=detect_leaks=0 themselves (TUMBLE_TEST_NO_LEAK_CHECK).
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1} timed tests ctest --output-on-failure -j "$jobs" ;;
  tsan)
    # ThreadSanitizer on the tests that run the parallel code. Debian's libtbb is not
    # instrumented, so TSan would see none of oneTBB's synchronisation and report races inside
    # it that are not there; it is built here with TSan from Debian's own source of the
    # installed version (apt-get source onetbb: needs a deb-src line for bookworm), or from
    # TBB_SOURCE=DIR, once per machine: it is kept in TBB_TSAN_CACHE (default
    # ~/.cache/tumble/onetbb-tsan-VERSION) and built again only when missing.
    packages+=(dpkg-dev xz-utils)
    timed install install_packages
    build=${TSAN_BUILD_DIR:-$here/build-tsan}
    mkdir -p "$build"
    tbb_version=$(dpkg-query -W -f='${Version}' libtbb-dev 2>/dev/null || echo unknown)
    tbb=${TBB_TSAN_CACHE:-${XDG_CACHE_HOME:-$HOME/.cache}/tumble/onetbb-tsan-${tbb_version//[^A-Za-z0-9.+~-]/_}}
    if [ ! -f "$tbb/lib/cmake/TBB/TBBConfig.cmake" ]; then
      src=${TBB_SOURCE:-}
      if [ -z "$src" ]; then
        src=$(find "$build/onetbb-src" -maxdepth 1 -mindepth 1 -type d -name 'onetbb-*' 2>/dev/null | head -n 1 || true)
        if [ -z "$src" ]; then
          mkdir -p "$build/onetbb-src"
          timed deb-src ensure_deb_src
          if ! (cd "$build/onetbb-src" && timed onetbb-source apt-get source -qq onetbb >/dev/null 2>&1); then
            echo "tumble.sh tsan: cannot get Debian's oneTBB source (apt-get source onetbb); check the deb-src" \
                 "lines for bookworm in /etc/apt/sources.list.d and run apt-get update, or set TBB_SOURCE=DIR" >&2
            exit 2
          fi
          src=$(find "$build/onetbb-src" -maxdepth 1 -mindepth 1 -type d -name 'onetbb-*' | head -n 1)
        fi
      fi
      echo "tumble.sh tsan: building oneTBB $tbb_version with ThreadSanitizer into $tbb (once per machine)" >&2
      timed onetbb-configure cmake -S "$src" -B "$build/onetbb-build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
            -DTBB_TEST=OFF -DTBB_STRICT=OFF -DTBB_SANITIZE=thread -DCMAKE_INSTALL_PREFIX="$tbb" >/dev/null
      timed onetbb-build cmake --build "$build/onetbb-build" -j "$jobs" --target install >/dev/null
    fi
    timed configure cmake -S "$here" -B "$build" -G Ninja "${sanitize_flags[@]}" "${launcher[@]}" \
          -DTUMBLE_ENABLE_CUDA=OFF -DTUMBLE_SANITIZE=thread -DTUMBLE_BUILD_BENCH=OFF -DTUMBLE_VIEWER=OFF \
          -DTBB_DIR="$tbb/lib/cmake/TBB" >/dev/null
    timed build cmake --build "$build" -j "$jobs" --target "${tsan_targets[@]}"
    ctest_longest_first "$build"
    cd "$build"
    # Any report fails its test. The selection runs every parallel stage with 1 to 4 threads in a
    # few minutes; the whole suite under TSan takes hours on two cores.
    export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1 exitcode=66 second_deadlock_stack=1}
    timed tests ctest --output-on-failure -j "$jobs" -R "${TSAN_TESTS:-$tsan_tests}" ;;
  fuzz)
    # The readers under libFuzzer with ASan + UBSan (docs/fuzzing.md). New inputs go to
    # build-fuzz/corpus/TARGET, findings (the input, for the regression test) to
    # build-fuzz/findings; the seed corpus in validation/fuzz/corpus is only read.
    packages+=(clang-14 libclang-rt-14-dev)
    timed install install_packages
    seconds=60
    if [ $# -gt 0 ] && [[ "$1" =~ ^[0-9]+$ ]]; then seconds=$1; shift; fi
    targets=("$@")
    # Every target has a seed corpus: the corpus folders name them.
    all=()
    for d in "$here"/validation/fuzz/corpus/*/; do all+=("$(basename "$d")"); done
    [ ${#targets[@]} -eq 0 ] && targets=("${all[@]}")
    for t in "${targets[@]}"; do
      [ -d "$here/validation/fuzz/corpus/$t" ] ||
        { echo "tumble.sh fuzz: no target '$t' (expected one of: ${all[*]})" >&2; exit 2; }
    done
    build=${FUZZ_BUILD_DIR:-$here/build-fuzz}
    CC=clang-14 CXX=clang++-14 timed configure cmake -S "$here" -B "$build" -G Ninja "${sanitize_flags[@]}" \
          "${launcher[@]}" -DTUMBLE_ENABLE_CUDA=OFF -DTUMBLE_FUZZ=ON -DTUMBLE_SANITIZE=ON -DTUMBLE_BUILD_TESTS=OFF \
          -DTUMBLE_BUILD_BENCH=OFF -DTUMBLE_BUILD_EXAMPLES=OFF >/dev/null
    timed build cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"
    mkdir -p "$build/findings"
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
    # One target: its log, and a note on stderr when it found something.
    fuzz_one() {
      local t=$1 len=()
      mkdir -p "$build/corpus/$t"
      # libFuzzer's inputs stay near its corpus' largest (a few KB) unless told: a scene may be
      # long (a dotted key of 40 000 parts is 80 KB: issue 34, item 1).
      [ "$t" = scene ] && len=(-max_len=131072)
      if ! "$build/validation/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=4096 "${len[@]}" \
             -print_final_stats=1 -artifact_prefix="$build/findings/$t-" \
             "$build/corpus/$t" "$here/validation/fuzz/corpus/$t" >"$build/fuzz-$t.log" 2>&1; then
        tail -n 60 "$build/fuzz-$t.log" >&2
        echo "tumble.sh fuzz: $t found a problem; the input is in $build/findings (log: $build/fuzz-$t.log)" >&2
        return 1
      fi
    }
    # The targets side by side, $jobs at a time: each fuzzer is one process on one core, so every
    # target still gets its SECONDS of a whole core, in a fraction of the wall time.
    fuzz_targets() {
      local t status=0 pids=() names=() k
      for t in "${targets[@]}"; do
        echo "tumble.sh fuzz: $t for $seconds s" >&2
        fuzz_one "$t" &
        pids+=($!) names+=("$t")
        if [ ${#pids[@]} -ge "$jobs" ]; then
          wait "${pids[0]}" || status=1
          pids=("${pids[@]:1}")
        fi
      done
      for k in "${pids[@]}"; do wait "$k" || status=1; done
      for t in "${names[@]}"; do
        grep -E '^stat::number_of_executed_units|^stat::peak_rss_mb' "$build/fuzz-$t.log" | sed "s/^/  $t /" >&2 || true
      done
      return $status
    }
    timed run fuzz_targets ;;
  -h|--help|help)
    sed -n '3,13p' "$0" | sed 's/^# \{0,1\}//' ;;
  *)
    echo "tumble.sh: unknown command '$cmd' (expected run, test, build, sanitize, tsan or fuzz)" >&2; exit 2 ;;
esac
