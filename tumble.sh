#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# One-command set-up for a fresh Debian 12 machine (README "Quick start").
#   ./tumble.sh run [SCENE.toml] [tumble run options]   install, build, run a scene (default: molecules)
#   ./tumble.sh test                                     install, build, run every test
#   ./tumble.sh build                                    install and build only
#   ./tumble.sh sanitize                                 the tests again in an ASan + UBSan build (build-sanitize)
#   ./tumble.sh tsan                                     the threaded tests under ThreadSanitizer (build-tsan)
# Environment: BUILD_DIR (default build), JOBS (default: all cores), TUMBLE_ENABLE_CUDA (AUTO|ON|OFF).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${BUILD_DIR:-$here/build}
jobs=${JOBS:-$(nproc)}
packages=(g++ cmake ninja-build pkg-config libtbb-dev libeigen3-dev libtomlplusplus-dev libcli11-dev
          libgtest-dev libgmock-dev libbenchmark-dev
          libglfw3-dev libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libimgui-dev libpng-dev
          ffmpeg xvfb xauth xdotool gnuplot-nox fonts-dejavu-core)

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

configure_and_build() {
  cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
        -DTUMBLE_ENABLE_CUDA="${TUMBLE_ENABLE_CUDA:-AUTO}" -DTUMBLE_WERROR=ON >/dev/null
  cmake --build "$build" -j "$jobs"
}

# The tests `tsan` runs (a ctest regex; TSAN_TESTS overrides it).
tsan_tests='SameResultForAnyThreadCount|StepPairsMatchBruteForceOnTheBenchScene|PipelineContactSumsEqualThoseOfItsPairs|DeterminismTest|CheckpointTest'

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
    install_packages; configure_and_build
    cd "$build"
    exec ctest --output-on-failure -j "$jobs" ;;
  sanitize)
    # Address and undefined-behaviour sanitizers on every test (CI runs this after `test`).
    install_packages
    build=${SANITIZE_BUILD_DIR:-$here/build-sanitize}
    cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTUMBLE_ENABLE_CUDA=OFF \
          -DTUMBLE_SANITIZE=ON -DTUMBLE_BUILD_BENCH=OFF >/dev/null
    cmake --build "$build" -j "$jobs"
    cd "$build"
    # Leaks are checked everywhere except in the viewer's tests: Mesa's EGL drivers keep a few
    # allocations to the end of the process (112 bytes, inside the driver).
    export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1}
    ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1} ctest --output-on-failure -j "$jobs" -LE viewer
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
        if ! (cd "$build/onetbb-src" && apt-get source -qq onetbb >/dev/null 2>&1); then
          echo "tumble.sh tsan: cannot get Debian's oneTBB source (apt-get source onetbb); add a deb-src line" \
               "for bookworm to /etc/apt/sources.list.d and run apt-get update, or set TBB_SOURCE=DIR" >&2
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
  -h|--help|help)
    sed -n '3,9p' "$0" | sed 's/^# \{0,1\}//' ;;
  *)
    echo "tumble.sh: unknown command '$cmd' (expected run, test, build, sanitize or tsan)" >&2; exit 2 ;;
esac
