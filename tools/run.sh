#!/usr/bin/env bash
# Set-up and the main job: installs missing Debian packages, builds in Release, renders the embedded
# default scene (the Whitted scene) headless to out/default.png and prints the per-stage timings.
# Extra arguments go to tandem-render (e.g. tools/run.sh --preset raster --size 640x360).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tools/deps.sh"
tandem_install_deps
tandem_build
mkdir -p "$root/out"
"$root/build/bin/tandem-render" -o "$root/out/default.png" --frames 5 --stats "$root/out/default-stats.json" "$@"
echo "wrote $root/out/default.png"
