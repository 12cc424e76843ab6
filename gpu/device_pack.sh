#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# gpu/device_pack.sh [BUILD_DIR]: packs a CUDA build of this machine for gpu/device_check.sh on
# a GPU machine that has none of Debian's libraries. Runs here, in a second or two.
#
# Copies into .device/ (ignored by git; the device tool's `carry: [".device"]` sends it):
#   bin/       tumble, tumble_gpu_tests, tumble_validation_tests from BUILD_DIR (default: build,
#              or $BUILD_DIR)
#   lib/       every shared library they load according to ldd, except glibc's own (ld-linux,
#              libc, libm, libdl, libpthread, librt, libresolv, libutil, libmvec), which the device
#              has in a newer version, and the driver's (libcuda, libnvidia-*), which it must supply
#   lib/gcc/   libstdc++ and libgcc_s: used there only if the device's own are too old (a newer
#              one serves these binaries too, and compute-sanitizer may need the newer one)
#   source_dir the source tree compiled into the binaries (TUMBLE_SOURCE_DIR); device_check.sh
#              links it to the repository there, where the scenes and golden files are read from
#   manifest.txt  build dir, commit, date, the files and their sizes
# device_check.sh runs the binaries with LD_LIBRARY_PATH=.device/lib.
# The whole tree that travels (repository + .device) must stay under 64 MiB: this prints both
# sizes and warns above 48 MiB for .device.
set -uo pipefail

die() { echo "device_pack: $*" >&2; exit 1; }

root=$(git rev-parse --show-toplevel 2>/dev/null) || die "run it inside the repository"
cd "$root" || die "cannot enter $root"
build=${1:-${BUILD_DIR:-build}}
[[ -f "$build/CMakeCache.txt" ]] || die "$build is not a CMake build folder (no CMakeCache.txt)"

bins=("$build/examples/tumble" "$build/gpu/tumble_gpu_tests" "$build/validation/tumble_validation_tests")
for b in "${bins[@]}"; do
  [[ -x "$b" ]] || die "$b is missing: build it first (cmake --build $build), with CUDA"
done
ldd "${bins[0]}" | grep -q 'libcudart' ||
  echo "device_pack: warning: ${bins[0]} does not load libcudart: is this a CUDA build?" >&2

dest=.device
rm -rf "$dest"
mkdir -p "$dest/bin" "$dest/lib" || die "cannot create $dest"
for b in "${bins[@]}"; do cp -L "$b" "$dest/bin/" || die "cannot copy $b"; done

# glibc and the loader come from the device; so do the driver's libraries.
skip_re='^(linux-vdso|linux-gate|ld-linux|libc\.so|libm\.so|libdl\.so|libpthread\.so|librt\.so|libresolv\.so|libutil\.so|libmvec\.so|libcuda\.so|libnvidia-)'
missing=0
declare -A seen=()
while read -r name arrow path _; do
  [[ "$arrow" == "=>" ]] || continue           # the loader and vdso lines have no "=>"
  [[ "$name" =~ $skip_re ]] && continue
  if [[ "$path" == "not" ]]; then echo "device_pack: $name: not found here" >&2; missing=1; continue; fi
  [[ -n "${seen[$name]:-}" ]] && continue
  seen[$name]=1
  to=$dest/lib
  [[ "$name" == libstdc++.so.* || "$name" == libgcc_s.so.* ]] && to=$dest/lib/gcc
  mkdir -p "$to" || die "cannot create $to"
  cp -L "$path" "$to/$name" || die "cannot copy $path"
done < <(for b in "${bins[@]}"; do ldd "$b"; done)
((missing == 0)) || die "some libraries are not found here either; fix the build first"

src=$(sed -n 's/^tumble_SOURCE_DIR:STATIC=//p' "$build/CMakeCache.txt")
[[ -n "$src" ]] || src=$(sed -n 's/^CMAKE_HOME_DIRECTORY:INTERNAL=//p' "$build/CMakeCache.txt")
echo "$src" > "$dest/source_dir"

kib() { du -sk "$1" | cut -f1; }
{
  echo "packed: $(date -u '+%Y-%m-%d %H:%M UTC') on $(uname -n)"
  echo "build dir: $(cd "$build" && pwd) ($(sed -n 's/^CMAKE_BUILD_TYPE:STRING=//p' "$build/CMakeCache.txt"))"
  echo "source dir compiled in: $src"
  echo "commit: $(git rev-parse --short HEAD 2>/dev/null)$(git diff --quiet HEAD 2>/dev/null || echo ' + uncommitted changes')"
  echo "files (KiB):"
  (cd "$dest" && find bin lib -type f -printf '%k\t%p\n' | sort -k2)
} > "$dest/manifest.txt"

total=$(kib "$dest")
tree=$(git ls-files -co --exclude-standard -z | du -cb --files0-from=- 2>/dev/null | tail -1 | cut -f1)
tree_kib=$(( ${tree:-0} / 1024 ))
printf 'device_pack: %d binaries and %d libraries in %s/ (bin %d KiB, lib %d KiB)\n' \
  "${#bins[@]}" "$(find "$dest/lib" -type f | wc -l)" "$dest" "$(kib "$dest/bin")" "$(kib "$dest/lib")"
awk -v d="$total" -v t="$tree_kib" 'BEGIN { printf "device_pack: .device %.1f MiB; with the repository (%.1f MiB) %.1f MiB of the 64 MiB that travel\n", d / 1024, t / 1024, (d + t) / 1024 }'
if ((total > 48 * 1024)); then
  echo "device_pack: warning: .device is over 48 MiB; strip the binaries (strip .device/bin/*) or carry less" >&2
fi
if ((total + tree_kib > 64 * 1024)); then
  echo "device_pack: error: over the 64 MiB that the device tool sends" >&2
  exit 1
fi
echo "device_pack: lib/: $(cd "$dest/lib" && find . -type f -printf '%P\n' | sort | tr '\n' ' ')"
echo "device_pack: next: the device tool's run with carry [\".device\"] and command: bash gpu/device_check.sh"
