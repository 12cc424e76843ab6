#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# `tumble run` under mpirun (issue 15, docs/mpi.md): on 1, 2, 3 and 4 ranks the state, the
# recording, the time series and the checkpoint are the one process's byte for byte; a
# checkpoint of either continues on the other; a failure ends every rank with one message and
# one status. Runs on 2 cores with --oversubscribe, each rank on one thread.
# usage: mpi_run_test.sh TUMBLE_BINARY SOURCE_DIR HAS_MPI   (exit 77: skipped, no MPI)
set -u
bin=$1; src=$2; has_mpi=$3
if [ "$has_mpi" != "ON" ] && [ "$has_mpi" != "1" ]; then echo "skipped: tumble was built without MPI"; exit 77; fi
if ! command -v mpirun >/dev/null; then echo "skipped: no mpirun (apt-get install openmpi-bin)"; exit 77; fi
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
# Open MPI refuses root without these (CI runs as root); no single-copy transport in containers
# that forbid ptrace; -q: no banner of mpirun's own when a rank exits with a status.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_btl_vader_single_copy_mechanism=none
mpi() { local np=$1; shift; mpirun -q --oversubscribe -np "$np" "$bin" "$@"; }
fails=0; passes=0
ok()   { passes=$((passes+1)); echo "ok: $1"; }
bad()  { fails=$((fails+1)); echo "FAIL: $1"; }
same() {  # name file-a file-b
  if cmp -s "$2" "$3"; then ok "$1"; else bad "$1: $2 and $3 differ ($(cmp "$2" "$3" 2>&1 | head -1))"; fi
}
# The one-process run (the CPU pipeline), then the same run on each rank count, compared byte
# for byte; rank_args: what the ranks' runs add (--pipeline cuda-host: the CUDA pipeline's code
# on every rank).
# usage: ranks_equal NAME "RANKS" run args...  (each run writes --state-out and --thermo, with
# the energy tally's columns)
rank_args=()
ranks_equal() {
  local name=$1 ranks=$2; shift 2
  if ! "$bin" run "$@" --threads 1 -q --state-out ref.csv --thermo ref.thermo.csv --thermo-every 50 --energy-balance 2>err.txt; then
    bad "$name: the one-process run failed: $(cat err.txt)"; return
  fi
  for np in $ranks; do
    if ! mpi "$np" run "$@" "${rank_args[@]}" --threads 1 -q --state-out np.csv --thermo np.thermo.csv --thermo-every 50 \
      --energy-balance 2>err.txt; then
      bad "$name on $np ranks failed: $(cat err.txt)"; continue
    fi
    same "$name, $np ranks: state" ref.csv np.csv
    same "$name, $np ranks: time series" ref.thermo.csv np.thermo.csv
  done
}

# --- The examples (both rotation schemes) and a reduced bench-128k: 100 steps from its state at
# step 700 (a checkpoint of one process), when its clumps touch. A thin skin makes the ranks
# redistribute their bodies often (the skin changes no bit); the automatic one leaves the ghosts
# long between redistributions.
for rot in report splitting; do
  ranks_equal "molecules ($rot)" "1 2 3 4" "$src/scenes/molecules.toml" --steps 1500 --set output.record='""' \
              --set integrator.rotation="\"$rot\""
  ranks_equal "spheres ($rot)" "1 2 3 4" "$src/scenes/spheres.toml" --steps 300 --set output.record='""' \
              --set integrator.rotation="\"$rot\"" --skin 0.002
done
"$bin" run "$src/scenes/bench-128k.toml" --steps 700 --threads 2 -q --checkpoint bench.ck 2>err.txt ||
  bad "bench-128k to step 700: $(cat err.txt)"
ranks_equal "bench-128k (steps 700-800)" "1 2 3 4" "$src/scenes/bench-128k.toml" --resume bench.ck --steps 800
# Contact histories (hooke-history) and Hertz–Mindlin travel with the bodies; a turning drum.
ranks_equal "heap (hooke-history)" "2 3" "$src/scenes/heap.toml" --steps 400 --skin 0.002 --set output.record='""'
ranks_equal "heap-hertz" "3" "$src/scenes/heap-hertz.toml" --steps 300 --skin 0.002 --set output.record='""'
ranks_equal "powder-cohesive (sjkr cohesion, polydisperse)" "2 3" "$src/scenes/powder-cohesive.toml" --steps 1500
# The same powder under JKR (γ 5 J/m²: the sjkr pile's pull-off force): necks held beyond
# touching, marked in their springs, travel with the bodies and across the halos.
sed -e 's/cohesion = "sjkr"/cohesion = "jkr"/' -e 's/^cohesion_energy_density = 7.0e5/surface_energy = 5.0/' \
  "$src/scenes/powder-cohesive.toml" >powder-jkr.toml
ranks_equal "powder-cohesive under jkr" "3" powder-jkr.toml --steps 1500
ranks_equal "drum (moving walls)" "3" "$src/scenes/drum.toml" --steps 300 --set output.record='""'
# The mesh drum once it turns (from 0.3 s, step 7500): mesh springs travel with the bodies, and
# the ranks' guards and time series see the mesh contacts.
"$bin" run "$src/scenes/drum-mesh.toml" --steps 7400 --threads 2 -q --checkpoint drum-mesh.ck --set output.record='""' 2>err.txt ||
  bad "drum-mesh to step 7400: $(cat err.txt)"
ranks_equal "drum-mesh (a turning mesh, steps 7400-8000)" "2 3" "$src/scenes/drum-mesh.toml" --resume drum-mesh.ck \
  --steps 8000 --set output.record='""'
# The CUDA pipeline on every rank (one GPU per rank on a machine with GPUs; here its host
# backend, the same code) against one CPU process: clumps under the report's law, and the
# turning mesh drum under hooke-history (contact histories and mesh springs carried across the
# redistributions).
rank_args=(--pipeline cuda-host)
ranks_equal "molecules, the CUDA pipeline (cuda-host) on every rank" "1 2 3" "$src/scenes/molecules.toml" --steps 1500 \
            --set output.record='""'
ranks_equal "drum-mesh (steps 7400-8000), the CUDA pipeline (cuda-host) on every rank" "1 2 3" \
            "$src/scenes/drum-mesh.toml" --resume drum-mesh.ck --steps 8000 --set output.record='""'
rank_args=()

# --- Purpose-built scenes.
ball='[[shape]]
name = "ball"
[[shape.sphere]]
offset = [0.0, 0.0, 0.0]
radius = 0.05
mass = 0.3
elasticity = 0.6'
# [scene] NAME, dt, steps on a ground at z = 0, with the ball.
scene_head() {
  printf '[scene]\nname = "%s"\ndt = %s\nsteps = %s\n[ground]\nheight = 0.0\nfriction = 0.5\n%s\n' "$1" "$2" "$3" "$ball"
}
# Two clouds of balls and dumbbells flying into each other at 5 m/s each across the middle of
# the domain, where the first cut falls: they cross the rank boundaries at speed.
cat > crossing.toml <<TOML
[scene]
name = "crossing"
dt = 1.5e-4
steps = 700
gravity = [0.0, 0.0, 0.0]
[contact]
stiffness = 1.0e5
damping = 10.0
[ground]
enabled = false
$ball
[[shape]]
name = "dumbbell"
[[shape.sphere]]
offset = [-0.04, 0.0, 0.0]
radius = 0.04
mass = 0.2
elasticity = 0.6
[[shape.sphere]]
offset = [0.04, 0.0, 0.0]
radius = 0.05
mass = 0.3
elasticity = 0.6
[[group]]
shapes = ["ball", "dumbbell"]
count = [4, 5, 5]
spacing = 0.25
origin = [-1.0, 0.0, 0.0]
jitter = 0.02
velocity = [5.0, 0.0, 0.0]
velocity_jitter = 0.5
random_orientation = true
spin = 5.0
[[group]]
shapes = ["ball", "dumbbell"]
count = [4, 5, 5]
spacing = 0.25
origin = [0.25, 0.05, 0.05]
jitter = 0.02
velocity = [-5.0, 0.0, 0.0]
velocity_jitter = 0.5
random_orientation = true
spin = 5.0
TOML
ranks_equal "bodies crossing the boundaries at speed" "1 2 3 4" crossing.toml --skin 0.005
ranks_equal "the same cut in slabs" "3" crossing.toml --skin 0.005 --decomposition slabs
# The same 4 km from the origin: the run integrates in a local frame, the whole run's on every rank.
sed -e 's/origin = \[-1.0,/origin = [4095.0,/' -e 's/origin = \[0.25,/origin = [4096.25,/' crossing.toml > far.toml
ranks_equal "crossing far from the origin" "2 3" far.toml --skin 0.005

# A rod of 41 spheres 2.1 m long spinning on the ground, balls raining on it: its particles lie
# on every rank's side of the cuts, its owner sums them all.
{
  scene_head rod 2e-4 600
  printf '[[shape]]\nname = "rod"\n'
  for k in $(seq -20 20); do
    printf '[[shape.sphere]]\noffset = [%s, 0.0, 0.0]\nradius = 0.05\nmass = 0.1\nelasticity = 0.5\n' "$(awk -v k="$k" 'BEGIN { printf "%.2f", k * 0.05 }')"
  done
  printf '[[body]]\nshape = "rod"\nposition = [0.0, 0.0, 0.05]\nangular_velocity = [0.0, 0.0, 1.5]\n'
  printf '[[group]]\nshape = "ball"\ncount = [20, 3, 2]\nspacing = 0.11\norigin = [-1.05, -0.11, 0.25]\njitter = 0.005\n'
} > rod.toml
ranks_equal "a clump spanning three ranks" "3 4" rod.toml --skin 0.005
mpi 3 run rod.toml --threads 1 --steps 10 >out.txt 2>err.txt
owners=$(awk '/^ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9]+/ {print $2}' out.txt | tr '\n' ' ')
[ -n "$owners" ] && ok "rod: bodies per rank $owners" || bad "rod: no rank table in $(cat out.txt)"

# Three bodies on four ranks: one rank owns nothing, steps, gathers and writes with the others.
{
  scene_head three 2e-4 500
  cat <<TOML
[[body]]
shape = "ball"
position = [-0.3, 0.0, 0.3]
velocity = [2.0, 0.0, 0.0]
[[body]]
shape = "ball"
position = [0.3, 0.01, 0.3]
velocity = [-2.0, 0.0, 0.0]
[[body]]
shape = "ball"
position = [0.0, 0.4, 0.05]
TOML
} > three.toml
ranks_equal "an empty rank" "4" three.toml --skin 0.002
mpi 4 run three.toml --threads 1 >out.txt 2>err.txt
empty=$(awk '/^ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9]+ +[0-9]+/ && $2 == 0' out.txt | wc -l)
[ "$empty" = 1 ] && ok "three bodies on four ranks: one rank without bodies" || bad "no empty rank in $(cat out.txt)"

# Balls on a touching lattice (spacing 2 r), 5 x 7 x 2 (70 bodies): the cut along y falls inside
# the middle row, between balls at the same y.
{
  scene_head lattice 2e-4 400
  cat <<TOML
[[group]]
shape = "ball"
count = [5, 7, 2]
spacing = 0.1
origin = [0.0, 0.0, 0.05]
TOML
} > lattice.toml
ranks_equal "a rank boundary exactly on a particle" "2 3" lattice.toml --skin 0.001

# A mesh plate sweeping at 3 m/s through balls at rest: only the mesh's motion makes the local
# lists rebuild, in the step and in the ghosts' rewrite (HaloPipeline::writeMotion; without the
# meshes' motion there, 2 and 3 ranks end in another state than the one process).
printf 'v 0 -0.5 0\nv 0 0.5 0\nv 0 0.5 0.3\nv 0 -0.5 0.3\nf 1 2 3 4\n' > plate.obj
{
  scene_head plate 2e-4 400
  cat <<TOML
[[wall]]
type = "mesh"
file = "plate.obj"
position = [-0.2, 0.0, 0.0]
velocity = [3.0, 0.0, 0.0]
[[group]]
shape = "ball"
count = [4, 7, 1]
spacing = 0.1
origin = [0.0, -0.3, 0.05]
TOML
} > plate.toml
ranks_equal "a moving mesh plate through balls at rest" "2 3" plate.toml --skin 0.002

# Bodies poured in during the run (the world grows; every rank reloads).
{
  scene_head pour 2e-4 600
  cat <<TOML
[[pour]]
shape = "ball"
count = 80
rate = 2000
interval = 0.01
region = "box"
min = [-0.3, -0.3, 0.1]
max = [0.3, 0.3, 0.5]
velocity = [0, 0, -1]
TOML
} > pour.toml
ranks_equal "a pour" "2 3" pour.toml --skin 0.005

# --- Outputs: a debug recording (with the contact forces), the time series, checkpoints; continuing on the other side.
heap=("$src/scenes/heap.toml" --threads 1 -q --skin 0.002)
"$bin" run "${heap[@]}" --steps 300 --record ref.bin --debug-record --record-contacts --checkpoint ref.ck --checkpoint-every 150 \
       --state-out ref.csv 2>err.txt || bad "heap recorded: $(cat err.txt)"
mpi 3 run "${heap[@]}" --steps 300 --record np.bin --debug-record --record-contacts --checkpoint np.ck --checkpoint-every 150 \
       --state-out np.csv 2>err.txt || bad "heap recorded on 3 ranks: $(cat err.txt)"
same "debug recording on 3 ranks" ref.bin np.bin
same "checkpoint on 3 ranks" ref.ck np.ck
"$bin" run "${heap[@]}" --steps 150 --checkpoint one.ck --record cont.bin --debug-record --record-contacts 2>err.txt
mpi 4 run "${heap[@]}" --steps 300 --resume one.ck --state-out r1.csv --record cont.bin --debug-record --record-contacts 2>err.txt \
  || bad "resume on 4 ranks: $(cat err.txt)"
same "one process's checkpoint continued on 4 ranks" ref.csv r1.csv
same "its recording continued on 4 ranks" ref.bin cont.bin
"$bin" run "${heap[@]}" --steps 300 --record c1.bin --record-contacts 2>err.txt || bad "contact forces: $(cat err.txt)"
mpi 2 run "${heap[@]}" --steps 300 --record c2.bin --record-contacts 2>err.txt || bad "contact forces on 2 ranks: $(cat err.txt)"
same "a recording of contact forces on 2 ranks" c1.bin c2.bin
mpi 2 run "${heap[@]}" --steps 150 --checkpoint two.ck 2>err.txt
same "checkpoint of 2 ranks" one.ck two.ck
"$bin" run "${heap[@]}" --steps 300 --resume two.ck --state-out r2.csv 2>err.txt
same "2 ranks' checkpoint continued by one process" ref.csv r2.csv

# --- Failures: every rank ends with the same status and rank 0 alone says why, once.
one_message() {  # name status want-regex
  local n; n=$(grep -c '^tumble: ' err.txt)
  if [ "$1" = "$got" ] && [ "$n" = 1 ] && grep -Eq "$3" err.txt; then ok "$2 (status $got, one message)"
  else bad "$2: status $got (want $1), $n messages: $(cat err.txt)"; fi
}
printf '[scene]\nname = "x"\ndt = 1e-4\nbogus = 3\n' > unknown.toml
mpi 3 run unknown.toml --state-out s.csv >out.txt 2>err.txt; got=$?
one_message 2 "bad input on 3 ranks" "unknown.toml:4"
[ -e s.csv ] && bad "bad input wrote s.csv" || ok "bad input wrote nothing"
mpi 3 run three.toml --steps 10 --state-out no/such/dir/s.csv >out.txt 2>err.txt; got=$?
one_message 2 "an output rank 0 cannot write" "no/such/dir/s.csv"
mpi 2 run "$src/scenes/chute.toml" --steps 10 >out.txt 2>err.txt; got=$?
one_message 2 "periodic boundaries refused" "periodic boundaries"
mpi 2 pairs nothing.csv >out.txt 2>err.txt; got=$?
one_message 2 "another command than run refused" "only .tumble run"
# A guard trip (dt far too large): the one process's message and status, once.
diverge=(three.toml --threads 1 -q --set scene.dt=0.05 --steps 400)
"$bin" run "${diverge[@]}" >out.txt 2>ref.err; want=$?
mpi 3 run "${diverge[@]}" >out.txt 2>err.txt; got=$?
one_message "$want" "a guard trip on 3 ranks" "$(head -1 ref.err | sed 's/[][().*^$]/./g')"

echo "$passes passed, $fails failed"
[ "$fails" = 0 ]
