#!/bin/sh
# docs-current.sh RENDER SOURCE_DIR: the README keeps up with the code it describes.
#  - every long option tandem-render --help lists is in README's tandem-render command summary;
#  - every folder under tests/ and tools/, and every tools/*.sh, is in README's Layout section;
#  - README's sentence on the presets gives each the depth --help's preset table (the code) gives it;
#  - README's frame times of the game are those of docs/game.md's table;
#  - no doc, header, source or test cites a numbered issue (the word and a number): readers of the repository
#    cannot see the tracker, so the text says what is meant instead.
set -u
render="$1"
src="$2"
readme="$src/README.md"
status=0

usage=$(awk '/^build\/bin\/tandem-render \[SCENE\]/ { on = 1 } on && /^```/ { exit } on' "$readme")
if [ -z "$usage" ]; then
  echo "README.md has no tandem-render command summary"
  exit 1
fi
# An option with a short name (-o,--output) may appear under either.
for names in $("$render" --help | grep -oE '^  (-[a-z],)?--[a-z][a-z-]*' | grep -v -- '--help$'); do
  found=0
  for opt in $(echo "$names" | tr ',' ' '); do
    if printf '%s\n' "$usage" | grep -q -- "\[$opt[] =]"; then found=1; fi
  done
  if [ "$found" -eq 0 ]; then
    echo "README's tandem-render summary lacks $names"
    status=1
  fi
done

layout=$(awk '/^## Layout/ { on = 1; next } on && /^## / { exit } on' "$readme")
for dir in "$src"/tests/*/ "$src"/tools/*/ "$src"/tools/*.sh; do
  [ -e "$dir" ] || continue
  name=$(basename "$dir")
  parent=$(basename "$(dirname "$dir")")
  case "$parent/$name" in
    tests/data | tests/golden | tests/support) continue ;;  # inputs and helpers, not suites
  esac
  if ! printf '%s\n' "$layout" | grep -qE "(^|[ /])($parent/)?$name([ /,]|$)"; then
    echo "README's Layout section lacks $parent/$name"
    status=1
  fi
done

help=$("$render" --help)
presets=$(awk '/Presets: `raster`/ { on = 1 } on { printf "%s ", $0 } on && /^$/ { exit }' "$readme")
for preset in hybrid-fast hybrid-full reference; do
  depth=$(printf '%s\n' "$help" | grep "^  $preset " | grep -oE 'depth [0-9]+')
  said=$(printf '%s\n' "$presets" | sed -n "s/.*\`$preset\` (\([^\`]*\).*/\1/p" | grep -oE 'depth [0-9]+')
  if [ -z "$depth" ] || [ "$said" != "$depth" ]; then
    echo "README says $preset runs '${said:-no depth}', --help says '${depth:-nothing}'"
    status=1
  fi
done

# docs/game.md rows "| preset | N ms (fps) | M ms (fps) |" (the frame-times table, not the stage tables) give "raster / hybrid-fast / hybrid-full" per size.
for column in 3 4; do
  times=$(awk -F'|' -v c="$column" '$2 ~ /^ (raster|hybrid-fast|hybrid-full) $/ && $c ~ / ms \(/ { split($c, f, " "); printf "%s%s", sep, f[1]; sep = " / " }' "$src/docs/game.md")
  if [ -z "$times" ] || ! grep -q -- "$times ms" "$readme"; then
    echo "README does not quote docs/game.md's game frame times '$times ms'"
    status=1
  fi
done

cited=$(cd "$src" && grep -rniE '\bissues? #?[0-9]+' README.md docs engine tools samples tests shaders 2>/dev/null)
if [ -n "$cited" ]; then
  echo "numbered issues cited (say what is meant instead):"
  echo "$cited"
  status=1
fi
exit $status
