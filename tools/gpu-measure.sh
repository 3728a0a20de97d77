#!/usr/bin/env bash
# One measurement batch on the GPU machine (docs/bench.md, "On the GPU class"). It runs there, inside the
# bundle ../shared/tools/gpu-bundle.sh packs, and writes one archive under $OUT:
#
#   ../shared/tools/gpu-bundle.sh            # here, after a Release build (tools/run.sh)
#   device run, carry [".gpu"], command:  bash .gpu/run.sh bash "$(pwd)/tools/gpu-measure.sh"
#
# The GPU's clock is logged beside every step (nvidia-smi, read only): an H100 left idle while the CPU traces
# drops to 345 MHz from 1980, and GL stage times follow it, so a GPU figure means little without its clock.
# Each step has its own time limit, so a hang costs one step, not the batch; the whole batch takes ~4 min.
# `gpu-measure.sh proofs` runs only the hybrid shadows' steps and the GL tests (~3 min): --shadows ray against
# hybrid with the proofs in the GL (auto on a GPU) and on the CPU, the frames kept to compare byte for byte.
# `gpu-measure.sh pipeline` runs the pipelined frame's tests, Whitted at 1920x1080 and 1280x720 with --pipeline off and
# on (interleaved, twice), the game with each, and the GL tests (~5 min).
# `gpu-measure.sh check` (~4.5 min) runs the pipeline tests, the game at --target-fps 30 pipelined and not, and the
# GL tests, each into its own file under $OUT (no archive: a run cut short keeps what it finished).
# `gpu-measure.sh denoise` (~5 min) measures the spatiotemporal filter (docs/denoise.md; its GPU target: 2 ms at
# 1920x1080): BM_Denoise at 640x360 and 1920x1080, the game at 1920x1080 with one filtered light sample against
# four raw ones (twice, interleaved), and the Denoise GL tests.
# `gpu-measure.sh switches` measures Embree's huge pages at 16 threads, twice, interleaved (~2 min): BM_RayPass
# and BM_RetraceFloor (heavy) with the defaults and TANDEM_EMBREE_CONFIG=hugepages=1, and Whitted 1920x1080
# with every ray and with the GL's proofs.
set -u
mode=${1:-all}
out=${OUT:?run on the GPU machine, where \$OUT is set}/r
mkdir -p "$out"
B=build/bin
S=tests/game/collect3.script
step() {  # step NAME LIMIT_S COMMAND...: stdout+stderr to NAME.txt, then its status and wall time
  local name=$1 limit=$2; shift 2
  echo "$name start $(date +%H:%M:%S.%N)" >> "$out/marks.txt"
  local s; s=$(date +%s%N)
  timeout "$limit" "$@" > "$out/$name.txt" 2>&1
  echo "rc=$? wall_ms=$(( ($(date +%s%N) - s) / 1000000 ))" >> "$out/$name.txt"
  echo "$name end $(date +%H:%M:%S.%N)" >> "$out/marks.txt"
}
game() { local name=$1; shift; step "game-$name" 60 $B/tandem-game --headless --frames 60 --size 1920x1080 --script $S \
           --frame-log "$out/game-$name.csv" "$@"; }
nvidia-smi -L > "$out/gpu.txt" 2>&1; nproc >> "$out/gpu.txt"
nvidia-smi --query-gpu=timestamp,pstate,clocks.sm,clocks.mem,utilization.gpu,power.draw --format=csv -lms 200 \
  > "$out/clocks.csv" 2>&1 &
smi=$!
proofs() {  # proofs NAME ARGS...: Whitted 1920x1080 hybrid-full, 15 frames, its last frame and stats kept
  local name=$1; shift
  step "proofs-$name" 90 $B/tandem-render --size 1920x1080 --preset hybrid-full --frames 15 \
    --stats "$out/proofs-$name.json" -o "$out/proofs-$name.png" "$@"
}
if [ "$mode" = denoise ]; then
  step bench-denoise 300 $B/tandem-bench --benchmark_filter='BM_Denoise'
  for round in 1 2; do
    game "denoised-$round" --preset hybrid-fast --denoise on --light-samples 1
    game "raw4-$round" --preset hybrid-fast
  done
  step denoise-tests 300 $B/tandem-gl-tests --gtest_filter='Denoise*'
  kill "$smi" 2>/dev/null
  cd "$OUT" && tar czf results.tgz r && rm -rf r
  exit 0
fi
if [ "$mode" = switches ]; then
  for round in 1 2; do
    for cfg in default hugepages=1; do
      case $cfg in
        default) env=() ;; hugepages=1) env=(TANDEM_EMBREE_CONFIG=hugepages=1) ;;
      esac
      step "bench-$cfg-$round" 90 env ${env[@]+"${env[@]}"} $B/tandem-bench --benchmark_filter='BM_RayPass/heavy:1|BM_RetraceFloor/heavy:1' \
        --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
    done
    proofs "ray-$round" --shadows ray
    proofs "gl-$round" --shadows hybrid --shadow-proofs gl
  done
  kill "$smi" 2>/dev/null
  cd "$OUT" && tar czf results.tgz r && rm -rf r
  exit 0
fi
if [ "$mode" = check ]; then  # after a fix: the pipelined frame's tests, the game's budget both ways, the GL tests (~4.5 min)
  o=${OUT:?}  # plain files straight into $OUT, so that a run cut short still brings back what it finished
  timeout 60 $B/tandem-pipeline-tests > "$o/pipeline-tests.txt" 2>&1; echo "rc=$?" >> "$o/pipeline-tests.txt"
  for p in on off; do
    timeout 40 $B/tandem-game --headless --frames 60 --size 1920x1080 --script $S --preset hybrid-full --target-fps 30 \
      --pipeline $p --frame-log "$o/game-fps30-$p.csv" > "$o/game-fps30-$p.txt" 2>&1
  done
  timeout 215 $B/tandem-gl-tests > "$o/gl-tests.txt" 2>&1; echo "rc=$?" >> "$o/gl-tests.txt"
  kill "$smi" 2>/dev/null; rm -rf "$out"
  exit 0
fi
if [ "$mode" = pipeline ]; then  # throughput against latency mode, interleaved, and the GL suites (~5 min)
  step pipeline-tests 150 $B/tandem-pipeline-tests
  for round in 1 2; do
    for p in off on; do
      step "render-full-1080-$p-$round" 60 $B/tandem-render --size 1920x1080 --preset hybrid-full --frames 30 \
        --pipeline $p --stats "$out/render-full-1080-$p-$round.json" -o "$out/render-full-1080-$p-$round.png"
      step "render-fast-1080-$p-$round" 40 $B/tandem-render --size 1920x1080 --preset hybrid-fast --frames 60 \
        --pipeline $p --stats "$out/render-fast-1080-$p-$round.json"
      step "render-full-720-$p-$round" 40 $B/tandem-render --size 1280x720 --preset hybrid-full --frames 30 \
        --pipeline $p --stats "$out/render-full-720-$p-$round.json"
    done
  done
  for p in off on; do
    game "fast-$p" --preset hybrid-fast --pipeline $p
    game "fps30-$p" --preset hybrid-full --target-fps 30 --pipeline $p
  done
  step gl-tests 240 $B/tandem-gl-tests
  kill "$smi" 2>/dev/null
  cd "$OUT" && tar czf results.tgz r && rm -rf r
  exit 0
fi
if [ "$mode" = proofs ]; then
  proofs ray --shadows ray
  proofs gl --shadows hybrid --shadow-proofs gl
  proofs cpu --shadows hybrid --shadow-proofs cpu
  proofs ray-again --shadows ray
  game hybrid-fast --preset hybrid-fast
  game hybrid-fast-proofs --preset hybrid-fast --shadows hybrid
  step gl-tests 300 $B/tandem-gl-tests
  kill "$smi" 2>/dev/null
  cd "$OUT" && tar czf results.tgz r && rm -rf r
  exit 0
fi
step render-raster-720 40 $B/tandem-render --size 1280x720 --preset raster --frames 200 --stats "$out/render-raster-720.json"
step render-fast-1080 40 $B/tandem-render --size 1920x1080 --preset hybrid-fast --frames 30 --stats "$out/render-fast-1080.json"
step render-full-1080 60 $B/tandem-render --size 1920x1080 --preset hybrid-full --frames 15 --stats "$out/render-full-1080.json"
step bench-summary 150 $B/tandem-bench --summary --sizes 1280x720,1920x1080 --out "$out/bench"
game raster --preset raster
game hybrid-fast --preset hybrid-fast
game fps30 --preset hybrid-full --target-fps 30
step gl-tests 240 $B/tandem-gl-tests
# The golden tests' frames as this GPU drew them (gltest::savePng), to look at beside the goldens.
mkdir -p "$out/frames" && find build -name 'golden-*.png' -newer "$out/gpu.txt" -exec cp {} "$out/frames/" \; 2>/dev/null
kill "$smi" 2>/dev/null
cd "$OUT" && tar czf results.tgz r && rm -rf r
