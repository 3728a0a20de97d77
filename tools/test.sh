#!/usr/bin/env bash
# Set-up, build and the whole test suite through ctest. Idempotent.
#   tools/test.sh                 the default suite (every test without the long or mutation label)
#   tools/test.sh --all           everything, long and mutation tests included (-L long or -L mutation: one of them)
#   tools/test.sh --asan          the suite under AddressSanitizer + UBSan, built with clang (build-asan), with
#                                 the libFuzzer smoke run of the glTF loader
#   tools/test.sh --tsan          the ray pass (rt + numerics tests) and the pipelined frame's tests (Pipeline.*)
#                                 under ThreadSanitizer (build-tsan)
#   tools/test.sh --fuzz          the timed fuzz runs of the glTF and scene-file harnesses (build-asan, label fuzz)
# Other arguments go to ctest (e.g. -R Scene, -L rt).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tools/deps.sh"
tandem_install_deps

mode=default
args=()
for a in "$@"; do
  case "$a" in
    --all) mode=all ;;
    --asan) mode=asan ;;
    --tsan) mode=tsan ;;
    --fuzz) mode=fuzz ;;
    *) args+=("$a") ;;
  esac
done

jobs="$(nproc 2>/dev/null || echo 2)"
# Tests run one per core (ctest -j): each is its own process with its own context and output files (the game's
# shared scripted runs take a lock), and much of a GL test is single-threaded (shader compiles, set-up), so two
# at once nearly halve the suite's time on 2 cores (526 -> 283 s on 2026-11-27).
# The packages above include libosmesa6: here the OSMesa context tests must run, not skip (elsewhere, e.g. on
# the GPU machine's bundle, they skip when libOSMesa is missing).
export TANDEM_REQUIRE_OSMESA=1
case "$mode" in
  asan|fuzz)
    # clang so the same tree also builds the libFuzzer targets (gcc has no libFuzzer).
    cmake -S "$root" -B "$root/build-asan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTANDEM_SANITIZE=address,undefined \
      -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 -DTANDEM_BUILD_FUZZ=ON \
      -DTANDEM_BUILD_BENCH=OFF -DTANDEM_BUILD_SAMPLES=OFF >/dev/null
    cmake --build "$root/build-asan" -j "$jobs"
    export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:halt_on_error=1"
    export LSAN_OPTIONS="suppressions=$root/tools/lsan.supp:print_suppressions=0"
    export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
    # Mesa unloads its DRI driver when the last EGL display goes away; the driver's globals then stop
    # pointing at its allocations and LSan calls them leaks, with frames it can no longer name. Keeping the
    # driver mapped (preloaded) makes those allocations reachable again, as they really are.
    dri="$(ls /usr/lib/*/dri/swrast_dri.so 2>/dev/null | head -n 1 || true)"
    if [ "$mode" = fuzz ]; then
      cd "$root/build-asan" && ctest -j "$jobs" --output-on-failure -L '^fuzz$' "${args[@]}"
    else
      # Left out here (tests/slow-under-asan.txt says why; the default suite runs them): each must still be a test.
      cd "$root/build-asan"
      skip=()
      while read -r name _; do
        case "$name" in '' | '#'*) continue ;; esac
        if ! ctest -N -R "^${name//./\\.}\$" | grep -q "Total Tests: 1$"; then
          echo "tests/slow-under-asan.txt names '$name', which is not a test" >&2
          exit 1
        fi
        skip+=("$name")
      done <"$root/tests/slow-under-asan.txt"
      exclude="^($(IFS='|'; echo "${skip[*]}"))\$"
      LD_PRELOAD="${dri}" ctest -j "$jobs" --output-on-failure -LE '^(long|fuzz|mutation)$' -E "$exclude" "${args[@]}"
    fi
    ;;
  tsan)
    cmake -S "$root" -B "$root/build-tsan" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTANDEM_SANITIZE=thread \
      -DTANDEM_BUILD_BENCH=OFF -DTANDEM_BUILD_SAMPLES=OFF >/dev/null
    cmake --build "$root/build-tsan" -j "$jobs" --target tandem-rt-tests tandem-numerics-tests tandem-pipeline-tests
    export TSAN_OPTIONS="halt_on_error=1:suppressions=$root/tools/tsan.supp"
    # Left out: ReferenceConvergence's 4, 8 and 16 spp of the reference (100 s under TSan, twice the next
    # longest): its threads are RayTracer::renderReference's, which the PathTracer, PixelTrace, RayCapture,
    # RayPass and RayPassProgress tests also run here; the Release suite runs it.
    cd "$root/build-tsan" && ctest -j "$jobs" --output-on-failure -L 'rt|numerics' \
      -E '^ReferenceConvergence\.ErrorShrinksFromFourToEightToSixteenSpp$' "${args[@]}"
    # The pipelined frame: its ray pass on a thread of its own beside the GL's calls (docs/pipeline.md). Mesa's
    # driver stays loaded (its suppression needs it), and TSan's deadlock detector is off: it overflows on
    # the locks LLVM's JIT holds at once while llvmpipe compiles a shader. The variants' test (the same paths
    # in six presets, 50 s under TSan) is left to the other builds.
    dri="$(ls /usr/lib/*/dri/swrast_dri.so 2>/dev/null | head -n 1 || true)"
    TSAN_OPTIONS="$TSAN_OPTIONS:detect_deadlocks=0" LD_PRELOAD="${dri}" \
      ctest -j "$jobs" --output-on-failure -R '^Pipeline\.' -E 'ThroughputFramesEqualLatencyFrames' "${args[@]}"
    ;;
  *)
    tandem_build
    cd "$root/build"
    if [ "$mode" = all ]; then
      ctest -j "$jobs" --output-on-failure "${args[@]}"
    else
      ctest -j "$jobs" --output-on-failure -LE '^(long|mutation)$' "${args[@]}"
    fi
    ;;
esac
