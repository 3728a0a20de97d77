#!/usr/bin/env bash
# One command to play Marble Mirrors: installs missing Debian packages, builds (Release), starts the game
# in a window. Extra arguments go to tandem-game (e.g. tools/play.sh --preset raster --size 960x540).
# Without a display, run it under Xvfb: xvfb-run -a tools/play.sh --frames 300 --capture shot.png
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tools/deps.sh"
tandem_install_deps
tandem_build
exec "$root/build/bin/tandem-game" "$@"
