#!/bin/sh
# consumer-test.sh CMAKE SOURCE_DIR BUILD_DIR OUT CXX: the installed package as a game consumes it.
#  1. cmake --install BUILD_DIR --prefix OUT/prefix; the headers installed are exactly engine/include/tandem.
#  2. tests/install/consumer (find_package(Tandem), Tandem::tandem) configured against that prefix alone, with
#     BUILD_DIR's C++ compiler; Tandem must come from the prefix, and nothing of the source or build tree (the
#     engine's internal headers, the generated GL loader, the build's archives) may reach its compile or link
#     lines: a consumer sees the installed files only.
#  3. It is built and run: one headless 64x36 frame of the embedded default scene, written as PNG.
set -eu
cmake="$1" src="$2" build="$3" out="$4" cxx="$5"
rm -rf "$out"
mkdir -p "$out"
prefix="$out/prefix"

"$cmake" --install "$build" --prefix "$prefix" >"$out/install.log"
(cd "$src/engine/include/tandem" && ls) >"$out/headers.want"
(cd "$prefix/include/tandem" && ls) >"$out/headers.got"
if ! cmp -s "$out/headers.want" "$out/headers.got"; then
  echo "installed headers differ from engine/include/tandem:"
  diff "$out/headers.want" "$out/headers.got"
  exit 1
fi
for f in TandemConfig.cmake TandemConfigVersion.cmake TandemTargets.cmake; do
  if [ -z "$(find "$prefix" -path "*/cmake/Tandem/$f")" ]; then
    echo "$f not installed"
    exit 1
  fi
done

consumer="$out/consumer-build"
"$cmake" -S "$src/tests/install/consumer" -B "$consumer" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$out/configure.log" 2>&1 || { cat "$out/configure.log"; exit 1; }
if ! grep -q "^Tandem_DIR:PATH=$prefix/" "$consumer/CMakeCache.txt"; then
  echo "Tandem was not found in the install prefix: $(grep '^Tandem_DIR' "$consumer/CMakeCache.txt")"
  exit 1
fi
"$cmake" --build "$consumer" >"$out/build.log" 2>&1 || { cat "$out/build.log"; exit 1; }
leaks=$(grep -h -o -e "$src/engine[^ \"]*" -e "[^ \"]*engine/src[^ \"]*" -e "$build/engine[^ \"]*" \
          "$consumer/compile_commands.json" "$consumer/CMakeFiles/tandem-consumer.dir/link.txt" | sort -u)
if [ -n "$leaks" ]; then
  echo "the consumer's compile or link line reaches into the source or build tree:"
  echo "$leaks"
  exit 1
fi

rm -f "$out/frame.png"
"$consumer/tandem-consumer" "$out/frame.png"
# PNG signature: 89 50 4E 47 (written by the installed library's stb_image_write).
test "$(head -c 4 "$out/frame.png" | od -An -tx1 | tr -d ' ')" = 89504e47
