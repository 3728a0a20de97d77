#!/bin/sh
# tandem-render RENDER: --help shows the default of every option (CLI11's "=VALUE" or a "(default ...)" in
# the description) and lists the presets with what each sets, marking the default one.
set -u
help=$("$1" --help) || exit 1
status=0
# Option lines start with two spaces and a dash; a description may wrap onto the next line, so each
# option is checked together with the line after it.
missing=$(printf '%s\n' "$help" | awk '
  /^  -/ { if (opt != "" && !ok) print opt; opt = $1; ok = ($0 ~ /default/ || $1 ~ /=/ || $0 ~ /[^ ]=[^ ]/); next }
  { if (opt != "" && $0 ~ /default/) ok = 1 }
  END { if (opt != "" && !ok) print opt }' | grep -v -- '^-h,--help$')
if [ -n "$missing" ]; then
  echo "options whose default --help does not show:"
  echo "$missing"
  status=1
fi
for preset in raster hybrid-fast hybrid-full reference; do
  if ! printf '%s\n' "$help" | grep -q "^  $preset  *shadows "; then
    echo "--help does not list the preset $preset"
    status=1
  fi
done
if ! printf '%s\n' "$help" | grep -q "^  hybrid-full .*<- the default"; then
  echo "--help does not mark hybrid-full as the default"
  status=1
fi
exit $status
