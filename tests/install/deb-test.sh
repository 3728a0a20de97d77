#!/bin/sh
# deb-test.sh CMAKE CPACK SOURCE_DIR BUILD_DIR OUT VERSION CXX: `cpack -G DEB` builds one libtandem-dev .deb
# of this version, holding every public header, every engine library and the CMake package under /usr,
# depending on the -dev packages TandemConfig.cmake finds; unpacked anywhere, find_package(Tandem) resolves
# from it (the exported targets check that every file they name exists), without building anything.
set -eu
cmake="$1" cpack="$2" src="$3" build="$4" out="$5" version="$6" cxx="$7"
rm -rf "$out"
mkdir -p "$out"

"$cpack" -G DEB --config "$build/CPackConfig.cmake" -B "$out" >"$out/cpack.log" 2>&1 || { cat "$out/cpack.log"; exit 1; }
set -- "$out"/*.deb
if [ $# -ne 1 ] || [ ! -f "$1" ]; then
  echo "cpack made no single .deb in $out: $*"
  exit 1
fi
deb="$1"
status=0
dpkg-deb -c "$deb" | awk '{ print $NF }' >"$out/contents"
want=""
for h in "$src"/engine/include/tandem/*.h; do want="$want ./usr/include/tandem/$(basename "$h")"; done
for l in core scene rt glad gl plan engine; do want="$want libtandem_$l.a"; done
want="$want cmake/Tandem/TandemConfig.cmake cmake/Tandem/TandemConfigVersion.cmake cmake/Tandem/TandemTargets.cmake"
for f in $want; do
  if ! grep -q -- "$f\$" "$out/contents"; then
    echo "$deb lacks $f"
    status=1
  fi
done
# Only /usr/include/tandem, the libraries and the package: no internal header, no tool, no test.
extra=$(grep -v -e '/$' -e '^\./usr/include/tandem/[A-Za-z]*\.h$' -e '/libtandem_[a-z]*\.a$' \
          -e '/cmake/Tandem/Tandem[A-Za-z-]*\.cmake$' "$out/contents" || true)
if [ -n "$extra" ]; then
  echo "$deb holds files beyond the package:"
  echo "$extra"
  status=1
fi

got=$(dpkg-deb -f "$deb" Package Version)
if [ "$got" != "$(printf 'Package: libtandem-dev\nVersion: %s' "$version")" ]; then
  echo "$deb: package/version '$got', want libtandem-dev $version"
  status=1
fi
depends=$(dpkg-deb -f "$deb" Depends)
for p in libglm-dev libembree-dev libtbb-dev libglfw3-dev libtinygltf-dev libegl-dev; do
  if ! printf '%s\n' "$depends" | grep -qE "(^|, )$p( |,|\$)"; then
    echo "$deb: Depends lacks $p ($depends)"
    status=1
  fi
done

dpkg-deb -x "$deb" "$out/root"
"$cmake" -S "$src/tests/install/consumer" -B "$out/consumer-build" -DCMAKE_PREFIX_PATH="$out/root/usr" \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$out/configure.log" 2>&1 ||
  { cat "$out/configure.log"; echo "find_package(Tandem) failed against the unpacked $deb"; exit 1; }
if ! grep -q "^Tandem_DIR:PATH=$out/root/usr/" "$out/consumer-build/CMakeCache.txt"; then
  echo "Tandem was not found in the unpacked .deb: $(grep '^Tandem_DIR' "$out/consumer-build/CMakeCache.txt")"
  status=1
fi
exit $status
