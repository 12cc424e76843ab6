#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# One-command set-up for a fresh Debian 12 machine (README "Quick start").
#   ./tumble.sh run [SCENE.toml] [tumble run options]   install, build, run a scene (default: molecules)
#   ./tumble.sh test                                     install, build, run every test
#   ./tumble.sh build                                    install and build only
#   ./tumble.sh sanitize                                 the tests again in an ASan + UBSan build (build-sanitize)
#   ./tumble.sh tsan                                     the threaded tests under ThreadSanitizer (build-tsan)
#   ./tumble.sh fuzz [SECONDS] [TARGET...]               each libFuzzer target SECONDS (default 60) on its corpus (build-fuzz)
# Environment: BUILD_DIR (default build), JOBS (default: all cores), TUMBLE_ENABLE_CUDA (AUTO|ON|OFF).
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

configure_and_build() {
  cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DTUMBLE_ENABLE_CUDA="${TUMBLE_ENABLE_CUDA:-AUTO}" -DTUMBLE_WERROR=ON >/dev/null
  cmake --build "$build" -j "$jobs"
}

# The tests `tsan` runs (a ctest regex; TSAN_TESTS overrides it).
tsan_tests='SameResultForAnyThreadCount|StepPairsMatchBruteForceOnTheBenchScene|PipelineContactSumsEqualThoseOfItsPairs|DeterminismTest|CheckpointTest|HaloPipelineTest'

cmd=${1:-run}
[ $# -gt 0 ] && shift
case "$cmd" in
  build)
    install_packages; configure_and_build ;;
  run)
    install_packages; configure_and_build
    scene=$here/scenes/molecules.toml
    if [ $# -gt 0 ] && [[ "$1" != -* ]]; then scene=$1; shift; fi
    exec "$build/examples/tumble" run "$scene" "$@" ;;
  test)
    packages+=("${test_packages[@]}")
    install_packages; configure_and_build
    cd "$build"
    exec ctest --output-on-failure -j "$jobs" ;;
  sanitize)
    # Address and undefined-behaviour sanitizers on every test (CI runs this after `test`).
    packages+=("${test_packages[@]}")
    install_packages
    build=${SANITIZE_BUILD_DIR:-$here/build-sanitize}
    cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTUMBLE_ENABLE_CUDA=OFF \
          -DTUMBLE_SANITIZE=ON -DTUMBLE_BUILD_BENCH=OFF >/dev/null
    cmake --build "$build" -j "$jobs"
    cd "$build"
    # Leaks are checked everywhere except in the viewer's tests, where Mesa's EGL drivers keep a
    # few allocations to the end of the process (112 bytes, inside the driver), and in tumble run
    # under mpirun, where Open MPI does the same (MPI_Init's allocations outlive MPI_Finalize).
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1} ctest --output-on-failure -j "$jobs" -LE viewer -E '^mpi_runs$'
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} ctest --output-on-failure -j "$jobs" -R '^mpi_runs$'
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=0} exec ctest --output-on-failure -j "$jobs" -L viewer ;;
  tsan)
    # ThreadSanitizer on the tests that run the parallel code. Debian's libtbb is not
    # instrumented, so TSan would see none of oneTBB's synchronisation and report races inside
    # it that are not there; it is built here with TSan from Debian's own source of the
    # installed version (apt-get source onetbb: needs a deb-src line for bookworm), or from
    # TBB_SOURCE=DIR.
    packages+=(dpkg-dev xz-utils)
    install_packages
    build=${TSAN_BUILD_DIR:-$here/build-tsan}
    mkdir -p "$build"
    src=${TBB_SOURCE:-}
    if [ -z "$src" ]; then
      src=$(find "$build/onetbb-src" -maxdepth 1 -mindepth 1 -type d -name 'onetbb-*' 2>/dev/null | head -n 1 || true)
      if [ -z "$src" ]; then
        mkdir -p "$build/onetbb-src"
        ensure_deb_src
        if ! (cd "$build/onetbb-src" && apt-get source -qq onetbb >/dev/null 2>&1); then
          echo "tumble.sh tsan: cannot get Debian's oneTBB source (apt-get source onetbb); check the deb-src" \
               "lines for bookworm in /etc/apt/sources.list.d and run apt-get update, or set TBB_SOURCE=DIR" >&2
          exit 2
        fi
        src=$(find "$build/onetbb-src" -maxdepth 1 -mindepth 1 -type d -name 'onetbb-*' | head -n 1)
      fi
    fi
    if [ ! -f "$build/onetbb/lib/cmake/TBB/TBBConfig.cmake" ]; then
      cmake -S "$src" -B "$build/onetbb-build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTBB_TEST=OFF \
            -DTBB_STRICT=OFF -DTBB_SANITIZE=thread -DCMAKE_INSTALL_PREFIX="$build/onetbb" >/dev/null
      cmake --build "$build/onetbb-build" -j "$jobs" --target install >/dev/null
    fi
    cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTUMBLE_ENABLE_CUDA=OFF \
          -DTUMBLE_SANITIZE=thread -DTUMBLE_BUILD_BENCH=OFF -DTUMBLE_VIEWER=OFF \
          -DTBB_DIR="$build/onetbb/lib/cmake/TBB" >/dev/null
    cmake --build "$build" -j "$jobs"
    cd "$build"
    # Any report fails its test. The selection runs every parallel stage (detection, contact list,
    # forces, integration, guard sums, checkpoints) with 1 to 4 threads in a few minutes; the
    # whole suite under TSan takes hours on two cores.
    export TSAN_OPTIONS=${TSAN_OPTIONS:-halt_on_error=1 exitcode=66 second_deadlock_stack=1}
    exec ctest --output-on-failure -j "$jobs" -R "${TSAN_TESTS:-$tsan_tests}" ;;
  fuzz)
    # The readers under libFuzzer with ASan + UBSan (docs/fuzzing.md). New inputs go to
    # build-fuzz/corpus/TARGET, findings (the input, for the regression test) to
    # build-fuzz/findings; the seed corpus in validation/fuzz/corpus is only read.
    packages+=(clang-14 libclang-rt-14-dev)
    install_packages
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
    CC=clang-14 CXX=clang++-14 cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
          -DTUMBLE_ENABLE_CUDA=OFF -DTUMBLE_FUZZ=ON -DTUMBLE_SANITIZE=ON -DTUMBLE_BUILD_TESTS=OFF \
          -DTUMBLE_BUILD_BENCH=OFF -DTUMBLE_BUILD_EXAMPLES=OFF >/dev/null
    cmake --build "$build" -j "$jobs" --target "${targets[@]/#/fuzz_}"
    mkdir -p "$build/findings"
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
    status=0
    for t in "${targets[@]}"; do
      mkdir -p "$build/corpus/$t"
      echo "tumble.sh fuzz: $t for $seconds s" >&2
      if ! "$build/validation/fuzz/fuzz_$t" -max_total_time="$seconds" -timeout=30 -rss_limit_mb=4096 \
             -print_final_stats=1 -artifact_prefix="$build/findings/$t-" \
             "$build/corpus/$t" "$here/validation/fuzz/corpus/$t" >"$build/fuzz-$t.log" 2>&1; then
        tail -n 60 "$build/fuzz-$t.log" >&2
        echo "tumble.sh fuzz: $t found a problem; the input is in $build/findings (log: $build/fuzz-$t.log)" >&2
        status=1
      fi
      grep -E '^stat::number_of_executed_units|^stat::peak_rss_mb' "$build/fuzz-$t.log" | sed "s/^/  $t /" >&2 || true
    done
    exit $status ;;
  -h|--help|help)
    sed -n '3,10p' "$0" | sed 's/^# \{0,1\}//' ;;
  *)
    echo "tumble.sh: unknown command '$cmd' (expected run, test, build, sanitize, tsan or fuzz)" >&2; exit 2 ;;
esac
