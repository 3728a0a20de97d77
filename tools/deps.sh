#!/usr/bin/env bash
# Sourced by run.sh and test.sh: installs the Debian 12 packages Tandem needs when any is missing.
# As root it runs apt-get; otherwise it stops with one message naming what is missing.
TANDEM_PACKAGES=(
  build-essential cmake pkg-config
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libosmesa6-dev libglfw3-dev python3-glad
  libembree-dev libtbb-dev libglm-dev libtinygltf-dev libstb-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libbenchmark-dev libimgui-dev
  gnuplot-nox xvfb xauth clang libclang-rt-14-dev
)

tandem_install_deps() {
  local missing=()
  local p
  for p in "${TANDEM_PACKAGES[@]}"; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      missing+=("$p")
    fi
  done
  [ ${#missing[@]} -eq 0 ] && return 0
  if [ "$(id -u)" -ne 0 ]; then
    echo "tandem: missing Debian packages (run as root, or: sudo apt-get install ${missing[*]})" >&2
    exit 1
  fi
  echo "tandem: installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq >/dev/null || { echo "tandem: apt-get update failed" >&2; exit 1; }
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null ||
    { echo "tandem: apt-get install ${missing[*]} failed" >&2; exit 1; }
}

# Configure + build in Release into build/ (binaries in build/bin/). Extra arguments go to cmake.
tandem_build() {
  local root
  root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
  local jobs
  jobs="$(nproc 2>/dev/null || echo 2)"
  cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release "$@" >"$root/build-configure.log" 2>&1 ||
    { cat "$root/build-configure.log" >&2; echo "tandem: cmake configure failed" >&2; exit 1; }
  cmake --build "$root/build" -j "$jobs" ||
    { echo "tandem: build failed" >&2; exit 1; }
}
