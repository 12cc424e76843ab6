#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# tumble against a peer on the same starting state, on this machine, in one sitting.
#
#   bench/side_by_side.sh [N ...]          N in 16000 128000 960000 (default: 16000 128000)
#   MODEL=hertz-mindlin bench/side_by_side.sh [N ...]    N in 16000 128000
#
# MODEL: tumble's contact law, and the peer.
#   hooke-history (the default): clumps of 8 against LAMMPS gran/hooke/history + rigid/small,
#     LAMMPS's own model with the deck's constants (k_n 2e4, k_t 5714.2857, gamma_n 86.17,
#     gamma_t 43.085, mu 0.5): like for like.
#   report: the report's law (no tangential history) against the same LAMMPS run: a different
#     model, labelled so in the output (the pairing of earlier sittings).
#   hertz-mindlin: single spheres of one material (bench/peers/spheres.py: E 1e7 Pa, nu 0.3,
#     e 0.5, mu 0.5, dt 5e-5 s, the ground of the same material) against LIGGGHTS
#     (bench/peers/in.spheres_hertz: pair gran model hertz tangential history, fix wall/gran,
#     nve/sphere; skin 1 mm = 0.2 radii, as LAMMPS's 0.1 of a 0.5 radius).
#
# For each N: writes the peers' clump state for both codes (bench/peers/clumps.py), then
# alternates, REPS times: tumble (tumble bench --scene, THREADS threads) and LAMMPS
# (bench/peers/in.clumps, THREADS MPI ranks: Debian's lammps has no OpenMP), each timed over
# steps 500-2500 excluding set-up. Two pairings: with a skin (tumble's default skin, LAMMPS skin
# 0.1 with "check yes") and detecting every step (tumble --skin 0, LAMMPS skin 0 rebuilt every
# step). Prints ns per particle-step, the medians and the LAMMPS/tumble ratio as Markdown.
#
# Environment: MODEL (hooke-history), TUMBLE (default build/examples/tumble), REPS (3), THREADS (2), WORK (/var/tmp/tumble-sbs),
# SKIN_ONLY=1 (skip the every-step pairing). Installs lammps (or liggghts) and openmpi-bin with apt when missing.
# Run it on an idle machine (uptime): the rows of a contended run mean nothing.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
tumble=${TUMBLE:-$here/../build/examples/tumble}
REPS=${REPS:-3}; THREADS=${THREADS:-2}; WORK=${WORK:-/var/tmp/tumble-sbs}; MODEL=${MODEL:-hooke-history}
# Per model: tumble's scene file and the peer's (program, Debian package, deck, data file, skin
# with a list kept, in the deck's units), the generator of both files.
peer=LAMMPS peer_bin=lmp peer_pkg=lammps deck=$here/peers/in.clumps peer_skin=0.1 gen=$here/peers/clumps.py
scene_of() { echo "$WORK/clumps_$1$scene_suffix.toml"; }
data_of() { echo "clumps_$1.data"; }
case "$MODEL" in
  hooke-history) scene_suffix=_hooke-history; model_label="same model: tumble hooke-history, LAMMPS gran/hooke/history" ;;
  report) scene_suffix=""; model_label="DIFFERENT models: tumble's report law (no tangential history), LAMMPS gran/hooke/history" ;;
  hertz-mindlin)
    peer=LIGGGHTS peer_bin=liggghts peer_pkg=liggghts deck=$here/peers/in.spheres_hertz peer_skin=0.001 gen=$here/peers/spheres.py
    scene_of() { echo "$WORK/spheres_$1_hertz-mindlin.toml"; }
    data_of() { echo "spheres_$1.data"; }
    model_label="same model: tumble hertz-mindlin, LIGGGHTS hertz with tangential history (single spheres)" ;;
  *) echo "side_by_side.sh: MODEL must be hooke-history, report or hertz-mindlin (got '$MODEL')" >&2; exit 2 ;;
esac
sizes=${*:-16000 128000}
[ -x "$tumble" ] || { echo "side_by_side.sh: no tumble binary at $tumble (build first, or set TUMBLE)" >&2; exit 2; }
if ! command -v "$peer_bin" >/dev/null || ! command -v mpirun >/dev/null; then
  echo "side_by_side.sh: installing $peer_pkg and openmpi-bin" >&2
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "$peer_pkg" openmpi-bin >/dev/null
fi
mkdir -p "$WORK"
mpi=(mpirun --allow-run-as-root --oversubscribe -np "$THREADS")

tumble_ns() {  # N SKIN_ARGS... → ns per particle-step over steps 500-2500
  local n=$1; shift
  "$tumble" bench --scene "$(scene_of "$n")" --threads "$THREADS" --warmup 500 --steps 2000 "$@" 2>/dev/null |
    awk -F'|' '$2 ~ /(clumps|spheres)_/ {gsub(/ /, "", $9); gsub(/ /, "", $13); print $9, $13}'
}
peer_ns() {  # N SKIN CHECK → ns per particle-step and list builds over steps 500-2500
  local n=$1 skin=$2 check=$3 log="$WORK/${peer_bin}_$1_$2_$3.log"
  (cd "$WORK" && "${mpi[@]}" "$peer_bin" -in "$deck" -var data "$(data_of "$n")" -var nwarm 500 -var nrun 2000 \
      -var skin "$skin" -var check "$check" -log none -screen "$log" >/dev/null 2>&1) || { echo "nan nan"; return; }
  awk -v n="$n" '/TIMED_RUN/ {f = 1} f && /^Loop time of/ {t = $4} f && /^Neighbor list builds/ {b = $5}
                 END {printf "%.1f %.1f\n", t / 2000 / n * 1e9, b / 2}' "$log"
}
median() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR] = $1} END {print (NR % 2) ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2}'; }

echo "Machine: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'), $(nproc) cores; $(date -u '+%Y-%m-%d %H:%M UTC'); load: $(cut -d' ' -f1-3 /proc/loadavg)"
echo "tumble: $("$tumble" --version 2>/dev/null | head -1 || echo "$tumble"); $peer: Debian $peer_pkg $(dpkg-query -W -f '${Version}' "$peer_pkg" 2>/dev/null)"
echo "Model: $model_label"
echo
printf "| particles | pairing | rep | tumble ns | tumble rebuilds/1000 | %s ns | %s rebuilds/1000 | %s / tumble |\n|---|---|---|---|---|---|---|---|\n" "$peer" "$peer" "$peer"
summary=()
for n in $sizes; do
  [ -f "$(scene_of "$n")" ] || python3 "$gen" "$n" "$WORK" >&2
  pairings=("skin")
  [ "${SKIN_ONLY:-0}" = 1 ] || pairings+=("every step")
  for pairing in "${pairings[@]}"; do
    if [ "$pairing" = skin ]; then targs=(); lskin=$peer_skin; lcheck=yes; else targs=(--skin 0); lskin=0.0; lcheck=no; fi
    ts=""; ls=""
    for r in $(seq "$REPS"); do
      read -r t tb < <(tumble_ns "$n" "${targs[@]}")
      read -r l lb < <(peer_ns "$n" "$lskin" "$lcheck")
      printf "| %s | %s | %d | %s | %s | %s | %s | %.2f |\n" "$n" "$pairing" "$r" "$t" "$tb" "$l" "$lb" \
        "$(awk -v a="$l" -v b="$t" 'BEGIN {print a / b}')"
      ts="$ts $t"; ls="$ls $l"
    done
    mt=$(echo "$ts" | median); ml=$(echo "$ls" | median)
    summary+=("| $n | $pairing | $mt | $ml | $(awk -v a="$ml" -v b="$mt" 'BEGIN {printf "%.2f", a / b}') |")
  done
done
echo
echo "Medians over $REPS alternating runs (ns per particle-step, steps 500-2500, $THREADS threads / ranks; $model_label):"
echo
printf "| particles | pairing | tumble | %s | %s / tumble |\n|---|---|---|---|---|\n" "$peer" "$peer"
printf "%s\n" "${summary[@]}"
