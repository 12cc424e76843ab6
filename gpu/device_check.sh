#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# gpu/device_check.sh [LOG_DIR]: the prepared device run (docs/cuda.md). On a machine with an
# NVIDIA GPU (H100/H200), from the binaries that gpu/device_pack.sh put in .device/, it runs, each
# step under its own timeout and the whole within DEVICE_CHECK_BUDGET seconds (default 450):
#   1. sanity (seconds): nvidia-smi, `tumble --version` says CUDA is ready, ldd finds every library
#   2. tumble_gpu_tests and the CUDA instances of tumble_validation_tests with TUMBLE_REQUIRE_CUDA=1
#   3. the same with TUMBLE_CUDA_SYNC=1 as well
#   4. compute-sanitizer memcheck, racecheck, initcheck and synccheck on 20 steps of bench-16k
#      (the four at once; SANITIZER_JOBS=1 runs them one after the other), then memcheck on 20
#      steps each of drum (hooke-history, turning walls), drum-mesh (a turning triangle mesh),
#      heap-hertz (hertz-mindlin) and chute (periodic boundaries: the ghost images' detection)
#   5. tumble bench --pipeline cuda at 16k, 128k, 960k, 4M and 10M particles, one call per size
#      (BENCH_PLAN: size:warmup:steps:timeout ...): the GPU numbers early, while they are cheap;
#      then bench --pipeline cpu,cuda on heap (a history law: hooke-history, rolling resistance)
#   6. tumble validate --pipelines cpu,cuda
#   7. tumble validate --pipelines cuda --quick --out LOG_DIR/study (the study; STUDY_DEPTH=full for
#      the full one, which takes far longer than the budget)
#   8. tumble bench --pipeline cpu at the same sizes (BENCH_PLAN_CPU), for the ratio; last, so
#      that the budget cuts these first
# DEVICE_CHECK_STEPS picks some of "tests sync sanitizers validate study bench" (default: all).
# A failed or timed-out step does not stop the rest. Logs go to LOG_DIR (default .device/logs,
# cleared first); with $OUT set (the device tool), $OUT/device_logs.tar.gz and $OUT/summary.txt
# too. The last thing printed is the summary table: step, PASS/FAIL/TIMEOUT/SKIP, seconds, result.
# Expected: about 5 minutes on an H200 with 16 cores (an estimate); at most the budget plus 10 s.
# Exit status: 0 every step passed or was skipped, 1 a step failed or timed out, 2 no usable GPU,
# 3 binaries, libraries or scene files missing.
# DEVICE_CHECK_DRY=1 runs the same flow here without a GPU: CPU pipeline, tiny sizes, a few tests.
set -uo pipefail

cd "$(dirname "$0")/.." || exit 3
DEV=${DEVICE_DIR:-.device}
BIN=$DEV/bin
case $DEV in /*) LIBDIR=$DEV/lib ;; *) LIBDIR=$PWD/$DEV/lib ;; esac
LDP=$LIBDIR${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}  # the binaries' LD_LIBRARY_PATH (not exported)
DRY=${DEVICE_CHECK_DRY:-0}
BUDGET=${DEVICE_CHECK_BUDGET:-450}
SANITIZER_JOBS=${SANITIZER_JOBS:-4}
STUDY_DEPTH=${STUDY_DEPTH:-quick}
STEPS=" ${DEVICE_CHECK_STEPS:-tests sync sanitizers validate study bench} "
STEPS=${STEPS//,/ }
want() { [[ "$STEPS" == *" $1 "* ]]; }
if [[ $# -ge 1 ]]; then
  LOG=$1
elif [[ -n "${DEVICE_LOG_DIR:-}" ]]; then
  LOG=$DEVICE_LOG_DIR
else
  LOG=$DEV/logs
  rm -rf "$LOG"
fi
mkdir -p "$LOG/.steps" || { echo "device_check: cannot create $LOG" >&2; exit 3; }
rm -f "$LOG"/.steps/*
T0=$(date +%s)
DEADLINE=$((T0 + BUDGET))

if [[ "$DRY" == 1 ]]; then
  PAIR=cpu GPU=cpu
  GPU_FILTER='*/cuda_host'
  VALIDATION_FILTER='Backends/PairsTest.*/cpu:Backends/DeterminismTest.*/cpu'
  REQUIRE=()
  VALIDATE_ARGS=(--steps 50 --random 3)
  STUDY_ARGS=(--quick --cases "ground_restitution,free_fall")
  BENCH_PLAN=${BENCH_PLAN:-"16000:20:50:60 128000:20:30:60"}
else
  PAIR=cpu,cuda GPU=cuda
  # The device's instances only (label gpu): their host-backend twins (*/cuda_host) run in CI.
  GPU_FILTER='*/cuda'
  VALIDATION_FILTER='*/cuda:CudaPrimitives*'
  REQUIRE=(TUMBLE_REQUIRE_CUDA=1)
  VALIDATE_ARGS=()
  if [[ "$STUDY_DEPTH" == full ]]; then STUDY_ARGS=(); else STUDY_ARGS=(--quick); fi
  # CUDA: steps 500-2500 (the CPU's window in docs/performance.md) up to 960k, shorter beyond.
  BENCH_PLAN=${BENCH_PLAN:-"16000:500:2000:60 128000:500:2000:60 960000:500:2000:90 4000000:500:1000:120 10000000:500:500:150"}
  # The CPU for the ratio: shorter windows at the large sizes (a 10M step takes ~0.1 s on 16 cores).
  BENCH_PLAN_CPU=${BENCH_PLAN_CPU:-"16000:500:2000:60 128000:500:1000:60 960000:200:300:90 4000000:50:60:120 10000000:20:30:150"}
fi

elapsed() { echo $(($(date +%s) - T0)); }
say() { printf '[%4ss] %s\n' "$(elapsed)" "$*"; }

# record N NAME STATUS SECONDS RESULT [LOGFILE]: one row of the summary.
record() { printf '%s\t%s\t%s\t%s\t%s\n' "$2" "$3" "$4" "$5" "${6:-}" > "$LOG/.steps/$1"; }

summary_table() {
  printf '| %-24s | %-7s | %5s | %s |\n' step status s result
  printf '|%s|%s|%s|%s|\n' -------------------------- --------- ------- --------
  local f name status secs result
  for f in "$LOG"/.steps/*; do
    [[ -f "$f" ]] || continue
    IFS=$'\t' read -r name status secs result _ < "$f"
    printf '| %-24s | %-7s | %5s | %s |\n' "$name" "$status" "$secs" "$result"
  done
}

# The result column, from a step's log.
gtest_result() {
  local log=$1 n p f s
  n=$(grep -aoE '^\[==========\] [0-9]+ tests? from' "$log" | tail -1 | grep -oE '[0-9]+' | head -1)
  p=$(grep -aoE '^\[  PASSED  \] [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+$')
  f=$(grep -aE '^\[  FAILED  \] [A-Za-z]' "$log" | sed -E 's/ \([0-9]+ ms\)$//' | sort -u | grep -c .)  # per test: --gtest_brief prints no total
  s=$(grep -aoE '^\[  SKIPPED \] [0-9]+' "$log" | tail -1 | grep -oE '[0-9]+$')
  if [[ -z "$n" ]]; then echo "no gtest summary: $(grep -av '^#' "$log" | tail -1 | cut -c1-80)"; return; fi
  echo "$n tests: ${p:-0} passed, ${f:-0} failed, ${s:-0} skipped"
}
sanitizer_result() {
  local log=$1 s
  s=$(grep -aoE '(ERROR|RACECHECK) SUMMARY: .*' "$log" | tail -1 | sed -E 's/^[A-Z]+ SUMMARY: //')
  echo "${s:-no sanitizer summary}; $(bench_result "$log")"
}
validate_result() {
  local log=$1 rows diff traj
  rows=$(grep -acE '^\| [^|]+ \| [0-9]+ \| (identical|DIFFERS)' "$log")
  diff=$(grep -acE '^\| .*DIFFERS' "$log")
  if grep -aq 'bitwise identical after every step' "$log"; then traj="states bitwise identical"
  elif grep -aq 'OUT OF TOLERANCE' "$log"; then traj="states OUT OF TOLERANCE"
  elif grep -aq 'states first differ' "$log"; then
    traj="states within tolerance, $(grep -aoE 'first differ at step [0-9]+' "$log" | head -1)"
  else traj="no trajectory result"; fi
  echo "pair sets: $((rows - diff)) of $rows identical; $traj"
}
study_result() {
  local log=$1 c h threw
  c=$(grep -aoE '^- [0-9]+ of [0-9]+ checks within tolerance' "$log" | tail -1 | sed -E 's/^- ([0-9]+) of ([0-9]+).*/\1\/\2 checks pass/')
  h=$(grep -aoE '^## Validation study \([^)]*\)' "$log" | tail -1 | sed -E 's/^## Validation study \((.*)\)/\1/')
  # A case that throws fails; one whose model the pipeline lacks (tumble::NotSupported) is not run
  # and named.
  threw=$(grep -aE '^\| [a-z]+ \| [a-z0-9_]+ \| case ran to completion \|.*\| FAIL \|$' "$log" |
    awk -F'|' '{ gsub(/ /, "", $3); printf "%s%s", (n++ ? "," : ""), $3 }')
  ns=$(grep -acE '^\| [a-z]+ \| [a-z0-9_]+ \| \(not run\) \|' "$log")
  echo "${c:-no study result}${h:+ ($h)}${threw:+; threw: $threw}$( ((ns > 0)) && echo "; $ns not supported")"
}
# "cuda 1.234 ms, cpu 5.678 ms/step (4.60x)" from bench's progress lines.
bench_result() {
  grep -aoE '^bench: .*, (cpu|cuda), threads .* [0-9.]+ ms/step' "$1" |
    sed -E 's/^bench: [^,]*\([0-9]+ particles\), (cpu|cuda), .* ([0-9.]+) ms\/step$/\1 \2/' |
    awk '{ ms[$1] = $2; order[++n] = $1 }
         END { if (!n) { printf "no step time"; exit }
               for (i = 1; i <= n; ++i) printf "%s%s %s ms", (i > 1 ? ", " : ""), order[i], ms[order[i]]
               printf "/step"
               if (("cpu" in ms) && ("cuda" in ms) && ms["cuda"] > 0) printf " (cuda %.2fx)", ms["cpu"] / ms["cuda"] }'
}

# run_step N KIND NAME CAP LOGFILE COMMAND...: runs COMMAND under timeout min(CAP, time left),
# its output in LOG/LOGFILE, and records its row.
run_step() {
  local id=$1 kind=$2 name=$3 cap=$4 logf=$5
  shift 5
  local log=$LOG/$logf left t start rc secs status result
  left=$((DEADLINE - $(date +%s) - 10))
  t=$((cap < left ? cap : left))
  if ((left < 5)); then
    record "$id" "$name" SKIP 0 "no time left in the ${BUDGET} s budget"
    say "$name: SKIP (no time left)"
    return
  fi
  say "$name: start (timeout ${t} s, log $logf)"
  { echo "# $name"; echo "# command: $*"; echo "# timeout: ${t} s"; } > "$log"
  start=$(date +%s)
  timeout -k 10 "$t" "$@" >> "$log" 2>&1
  rc=$?
  secs=$(($(date +%s) - start))
  [[ -n "$(tail -c1 "$log")" ]] && echo >> "$log"
  echo "# exit status $rc after $secs s" >> "$log"
  if ((rc == 0)); then status=PASS
  elif (((rc == 124 || rc == 137) && secs >= t)); then status=TIMEOUT
  else status=FAIL; fi
  case $kind in
    gtest) result=$(gtest_result "$log") ;;
    sanitizer)
      result=$(sanitizer_result "$log")
      if grep -aqiE 'device not supported|not supported on this (device|platform)' "$log"; then
        status=SKIP result="compute-sanitizer does not support this device or runtime (gVisor?)"
      fi ;;
    validate) result=$(validate_result "$log") ;;
    study) result=$(study_result "$log") ;;
    bench) result=$(bench_result "$log") ;;
    *) result="" ;;
  esac
  [[ $status == PASS || $status == SKIP ]] || result="exit $rc; $result"
  record "$id" "$name" "$status" "$secs" "$result" "$logf"
  say "$name: $status ($secs s): $result"
  summary_table > "$LOG/summary.txt"
}

# ---- 1. sanity ----------------------------------------------------------------------------------
say "device_check on $(uname -n): kernel $(uname -r), $(nproc) cores, budget ${BUDGET} s, logs in $LOG$([[ $DRY == 1 ]] && echo ', DRY RUN (CPU only)')"
[[ -f "$DEV/manifest.txt" ]] && sed -n '1,4p' "$DEV/manifest.txt" | sed 's/^/  /'
bad=0
for b in tumble tumble_gpu_tests tumble_validation_tests; do
  [[ -x "$BIN/$b" ]] || { echo "sanity: $BIN/$b is missing: run gpu/device_pack.sh on the build machine and carry $DEV" >&2; bad=1; }
done
((bad)) && exit 3
# The libraries: .device/lib first; .device/lib/gcc (libstdc++, libgcc_s) only when the device's
# own are missing or too old.
missing_libs() {
  local b
  if command -v ldd > /dev/null; then
    for b in "$BIN"/*; do
      LD_LIBRARY_PATH=$1 ldd "$b" 2>&1 | grep -a 'not found' | sed "s|^[[:space:]]*|  ${b##*/}: |"
    done
  fi
  LD_LIBRARY_PATH=$1 "$BIN/tumble" --version > /dev/null 2>&1 || echo "  tumble --version fails with LD_LIBRARY_PATH=$1"
}
miss=$(missing_libs "$LDP")
if [[ -n "$miss" && -d "$LIBDIR/gcc" ]]; then
  LDP=$LIBDIR:$LIBDIR/gcc${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  miss=$(missing_libs "$LDP")
fi
if [[ -n "$miss" ]]; then
  echo "sanity: libraries not found with LD_LIBRARY_PATH=$LDP:" >&2
  echo "$miss" >&2
  echo "sanity: carry them in $DEV/lib (gpu/device_pack.sh copies what ldd lists on the build machine)" >&2
  if echo "$miss" | grep -q 'GLIBC_'; then
    echo "sanity: the device's C library is older than the build machine's ($(ldd --version 2>&1 | head -1)):" \
      "build the carried binaries without MPI and the viewer (-DTUMBLE_ENABLE_MPI=OFF -DTUMBLE_VIEWER=OFF)," \
      "or on a system no newer than the device" >&2
  fi
  exit 3
fi
command -v ldd > /dev/null &&
  say "libstdc++: $(LD_LIBRARY_PATH=$LDP ldd "$BIN/tumble" | grep -a 'libstdc++' | awk '{print $3}')"
gpu="no GPU"  # nvidia-smi is for the log only: `tumble --version` (below) decides
if command -v nvidia-smi > /dev/null && smi=$(nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader 2>&1); then
  gpu=$(echo "$smi" | head -1 | sed 's/, /, driver /')
  say "GPU: $smi"
else
  say "nvidia-smi: $(command -v nvidia-smi > /dev/null && echo "${smi:-no output}" || echo 'not installed')"
fi
ver=$(LD_LIBRARY_PATH=$LDP "$BIN/tumble" --version 2>&1)
vrc=$?
while IFS= read -r line; do echo "  $line"; done <<< "$ver"
if ((vrc != 0)); then echo "sanity: $BIN/tumble --version failed (exit $vrc)" >&2; exit 3; fi
if [[ "$DRY" != 1 ]] && ! echo "$ver" | grep -q '^cuda: ready'; then
  echo "sanity: tumble cannot run its CUDA pipeline here: $(echo "$ver" | grep '^cuda:')" >&2
  echo "sanity: (DEVICE_CHECK_DRY=1 runs the flow without a GPU, CPU pipeline only)" >&2
  exit 2
fi
dev=$(echo "$ver" | sed -n 's/^cuda: ready: CUDA device 0 of [0-9]*: //p' | cut -c1-50)
[[ "$gpu" == "no GPU" && -n "$dev" ]] && gpu=$dev
# The binaries read scenes and golden files from the source tree they were built from
# (TUMBLE_SOURCE_DIR), else from their install folder: point one of them at this checkout.
src=$(cat "$DEV/source_dir" 2>/dev/null)
if [[ -n "$src" && ! -f "$src/scenes/molecules.toml" ]]; then
  if [[ ! -e "$src" && ! -L "$src" ]] && mkdir -p "$(dirname "$src")" 2>/dev/null && ln -s "$PWD" "$src" 2>/dev/null; then
    say "linked $src -> $PWD (the source folder compiled into the binaries)"
  elif mkdir -p /usr/local/share 2>/dev/null && ln -sfn "$PWD" /usr/local/share/tumble 2>/dev/null; then
    say "linked /usr/local/share/tumble -> $PWD ($src is taken)"
  fi
fi
if [[ -n "$src" && ! -f "$src/scenes/molecules.toml" && ! -f /usr/local/share/tumble/scenes/molecules.toml ]]; then
  echo "sanity: the binaries read scenes from $src, which does not hold this checkout, and no link could be made" >&2
  exit 3
fi
SAN=${COMPUTE_SANITIZER:-$(command -v compute-sanitizer)}
if [[ -z "$SAN" ]]; then
  for c in /usr/local/cuda/bin/compute-sanitizer /usr/local/cuda/compute-sanitizer/compute-sanitizer \
           /usr/local/cuda-*/bin/compute-sanitizer /opt/nvidia/*/compute-sanitizer /opt/nvidia/*/*/compute-sanitizer; do
    [[ -x "$c" ]] && { SAN=$c; break; }
  done
fi
# It runs with the binaries' LD_LIBRARY_PATH if it can; else it passes it on to tumble through env.
SAN_CMD=() SAN_ENV=()
if [[ -n "$SAN" ]]; then
  if env LD_LIBRARY_PATH="$LDP" "$SAN" --version > /dev/null 2>&1; then
    SAN_CMD=(env LD_LIBRARY_PATH="$LDP" "$SAN")
  elif "$SAN" --version > /dev/null 2>&1; then
    SAN_CMD=("$SAN" --target-processes all) SAN_ENV=(env LD_LIBRARY_PATH="$LDP")
    say "compute-sanitizer does not start with $DEV/lib in LD_LIBRARY_PATH: tumble gets it through env"
  else
    say "compute-sanitizer at $SAN does not start"
    SAN=""
  fi
fi
if [[ -n "$SAN" ]]; then say "compute-sanitizer: $SAN ($("$SAN" --version 2>/dev/null | grep -aiE 'version' | tail -1))"
else say "compute-sanitizer: none that runs (the four sanitizer steps will be skipped)"; fi
[[ "$(uname -r)" == 4.4.0* ]] && say "note: kernel 4.4.0 looks like gVisor, where compute-sanitizer was seen to refuse the device"
record 00 sanity PASS "$(elapsed)" "$gpu; $(echo "$ver" | grep '^cuda:' | cut -c1-60)"

# ---- 2-3. tests ---------------------------------------------------------------------------------
GT=(--gtest_brief=1 --gtest_color=no)
if want tests; then
  run_step 01 gtest gpu-tests 60 gpu_tests.log \
    env LD_LIBRARY_PATH="$LDP" "${REQUIRE[@]}" "$BIN/tumble_gpu_tests" "${GT[@]}" --gtest_filter="$GPU_FILTER"
  run_step 02 gtest "validation-$GPU" 150 validation_cuda.log \
    env LD_LIBRARY_PATH="$LDP" "${REQUIRE[@]}" "$BIN/tumble_validation_tests" "${GT[@]}" --gtest_filter="$VALIDATION_FILTER"
fi
if want sync; then
  run_step 03 gtest gpu-tests-sync 60 gpu_tests_sync.log \
    env LD_LIBRARY_PATH="$LDP" "${REQUIRE[@]}" TUMBLE_CUDA_SYNC=1 "$BIN/tumble_gpu_tests" "${GT[@]}" --gtest_filter="$GPU_FILTER"
  run_step 04 gtest "validation-$GPU-sync" 180 validation_cuda_sync.log \
    env LD_LIBRARY_PATH="$LDP" "${REQUIRE[@]}" TUMBLE_CUDA_SYNC=1 "$BIN/tumble_validation_tests" "${GT[@]}" --gtest_filter="$VALIDATION_FILTER"
fi

# ---- 4. compute-sanitizer on 20 steps of bench-16k ----------------------------------------------
n=5
want sanitizers || n=9
for tool in memcheck racecheck initcheck synccheck; do
  ((n > 8)) && break
  id=0$n
  n=$((n + 1))
  if [[ -z "$SAN" ]]; then
    record "$id" "sanitizer-$tool" SKIP 0 "no compute-sanitizer that runs"
    continue
  fi
  cmd=("${SAN_CMD[@]}" --tool "$tool" --error-exitcode 86
       "${SAN_ENV[@]}" "$BIN/tumble" bench --sizes 16000 --pipeline "$GPU" --warmup 0 --steps 20)
  if ((SANITIZER_JOBS > 1)); then
    run_step "$id" sanitizer "sanitizer-$tool" 150 "sanitizer_$tool.log" "${cmd[@]}" &
  else
    run_step "$id" sanitizer "sanitizer-$tool" 100 "sanitizer_$tool.log" "${cmd[@]}"
  fi
done
wait
# The models beyond the bench scene's, under memcheck: 20 steps of each scene (the wall and mesh
# candidate lists built and walked, the history and Hertz paths, the periodic images and rows
# built at every rebuild; the scenes' walls start turning
# and their bodies reach them only later, so wall contacts and moving meshes are not under it).
if want sanitizers; then
  if [[ -z "$SAN" ]]; then
    record 09 sanitizer-scenes SKIP 0 "no compute-sanitizer that runs"
  else
    run_step 09 sanitizer sanitizer-scenes 120 sanitizer_memcheck_scenes.log \
      "${SAN_CMD[@]}" --tool memcheck --error-exitcode 86 "${SAN_ENV[@]}" "$BIN/tumble" bench \
      --scene scenes/drum.toml scenes/drum-mesh.toml scenes/heap-hertz.toml scenes/chute.toml --pipeline "$GPU" \
      --warmup 0 --steps 20
  fi
fi

# ---- 5-8. the CUDA bench (its numbers first: cheap), validate, the study, the CPU bench -------------
# bench_pass FIRST_ID PIPELINE PLAN: one `tumble bench` per size (size:warmup:steps:timeout).
bench_pass() {
  local id=$1 pipe=$2 plan size warmup steps cap
  for plan in $3; do
    IFS=: read -r size warmup steps cap <<< "$plan"
    run_step "$id" bench "bench-$size $pipe" "${cap:-120}" "bench_${pipe}_$size.log" \
      env LD_LIBRARY_PATH="$LDP" "$BIN/tumble" bench --sizes "$size" --pipeline "$pipe" \
      --warmup "$warmup" --steps "$steps"
    id=$((id + 1))
  done
}
want bench && bench_pass 10 "$GPU" "$BENCH_PLAN"
want bench && run_step 16 bench "bench heap $PAIR" 90 bench_heap.log \
  env LD_LIBRARY_PATH="$LDP" "$BIN/tumble" bench --scene scenes/heap.toml --pipeline "$PAIR" --warmup 200 --steps 1000
want validate && run_step 20 validate "validate $PAIR" 90 validate.log \
  env LD_LIBRARY_PATH="$LDP" "$BIN/tumble" validate --pipelines "$PAIR" "${VALIDATE_ARGS[@]}"
want study && run_step 21 study "study $GPU $STUDY_DEPTH" 150 study.log \
  env LD_LIBRARY_PATH="$LDP" "$BIN/tumble" validate --pipelines "$GPU" "${STUDY_ARGS[@]}" --out "$LOG/study"
[[ "$GPU" != cpu ]] && want bench && bench_pass 30 cpu "$BENCH_PLAN_CPU"

# ---- the end: logs, the failures' tails, the bench table, the summary ---------------------------
failed=0 timedout=0 skipped=0 passed=0 bad_logs=()
for f in "$LOG"/.steps/*; do
  IFS=$'\t' read -r _ status _ _ logf < "$f"
  case $status in
    PASS) passed=$((passed + 1)) ;;
    SKIP) skipped=$((skipped + 1)) ;;
    TIMEOUT) timedout=$((timedout + 1)) ;;
    *) failed=$((failed + 1)) ;;
  esac
  [[ $status != PASS && -n "$logf" && -f "$LOG/$logf" ]] && bad_logs+=("$logf")
done
counts="$passed passed, $failed failed, $timedout timed out, $skipped skipped"
{ summary_table; echo "$counts"; } > "$LOG/summary.txt"
if [[ -n "${OUT:-}" && -d "$OUT" ]]; then
  cp "$LOG/summary.txt" "$OUT/summary.txt"
  if tar -czf "$OUT/device_logs.tar.gz" -C "$(dirname "$LOG")" "$(basename "$LOG")"; then
    if (($(du -k "$OUT/device_logs.tar.gz" | cut -f1) > 15 * 1024)); then  # 16 MiB a file comes back
      say "logs over 15 MiB: the tarball leaves out the study's CSV and PNG files"
      tar -czf "$OUT/device_logs.tar.gz" --exclude='*.csv' --exclude='*.png' -C "$(dirname "$LOG")" "$(basename "$LOG")"
    fi
    say "logs: \$OUT/device_logs.tar.gz ($(du -k "$OUT/device_logs.tar.gz" | cut -f1) KiB)"
  fi
fi
for logf in "${bad_logs[@]}"; do
  log=$LOG/$logf
  echo
  echo "---- $logf: $(tail -1 "$log" | sed 's/^# //')"
  grep -av '^# ' "$log" | grep -aE '^\[  FAILED  \] [A-Za-z]|SUMMARY:|^validate: |rror' | head -6 | cut -c1-200
  grep -av '^# ' "$log" | tail -5 | cut -c1-200
  [[ $logf == study.log && -f "$LOG/study/report.md" ]] && grep -aoE 'threw: .{0,150}' "$LOG/study/report.md" | sort -u | head -4
done
bench_logs=()
for f in "$LOG"/bench_*.log; do [[ -f "$f" ]] && bench_logs+=("$f"); done
if ((${#bench_logs[@]})); then
  echo
  echo "bench (tumble bench's table; ms/step: mean over the timed window):"
  first=$(grep -alE '^\| scene \|' "${bench_logs[@]}" | head -1)
  [[ -n "$first" ]] && grep -aE '^\| scene \||^\|---' "$first" | cut -c1-400
  grep -ahE '^\| bench-' "${bench_logs[@]}" | cut -c1-400
fi
echo
echo "device_check summary ($(date -u '+%Y-%m-%d %H:%M UTC'), $(elapsed) s in all; logs: $LOG$([[ -n "${OUT:-}" && -d "$OUT" ]] && echo ", \$OUT/device_logs.tar.gz"))"
summary_table
echo "$counts"
((failed + timedout == 0))
