#!/usr/bin/env bash
# Mutation testing: tools/mutate.py applies each listed one-line bug in a scratch tree, rebuilds the test binary
# meant to catch it, runs it, and reports survivors (docs/testing.md). Arguments go to tools/mutate.py
# (--only ID,..., --list, --build DIR). Also the ctest label `mutation` (tools/test.sh --all -L mutation).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
source "$root/tools/deps.sh"
tandem_install_deps
exec python3 "$root/tools/mutate.py" "$@"
