#!/bin/sh
# tandem-render RENDER OUTDIR: a render running longer than --progress-after prints progress lines
# (percent, elapsed, ETA) on stderr and ends with a 100% line; --quiet prints nothing at all, the engine's
# warnings included (a scene whose two quads fight for one plane warns without it); a render
# shorter than the default threshold (2 s) prints no progress. The threshold is 0 here so that a frame
# of a fraction of a second stands in for a long one.
set -u
render="$1"
out="$2"
status=0
"$render" --preset reference --spp 2 --size 64x36 --progress-after 0 -o "$out/cli-progress.png" \
  >"$out/cli-progress.out" 2>"$out/cli-progress.err" || exit 1
if ! grep -Eq '^tandem-render: [0-9]+%, [0-9.]+ s elapsed, ETA ' "$out/cli-progress.err"; then
  echo "no progress line (percent, elapsed, ETA) on stderr:"
  cat "$out/cli-progress.err"
  status=1
fi
if ! tail -n 1 "$out/cli-progress.err" | grep -Eq '^tandem-render: 100%, done in [0-9.]+ s$'; then
  echo "the progress does not end with a 100% line:"
  cat "$out/cli-progress.err"
  status=1
fi
if grep -q '%' "$out/cli-progress.out"; then
  echo "progress on stdout"
  status=1
fi
rm -f "$out/cli-quiet.png"
"$render" --preset reference --spp 2 --size 64x36 --progress-after 0 --quiet -o "$out/cli-quiet.png" \
  >"$out/cli-quiet.out" 2>"$out/cli-quiet.err" || exit 1
if [ -s "$out/cli-quiet.out" ] || [ -s "$out/cli-quiet.err" ] || [ ! -s "$out/cli-quiet.png" ]; then
  echo "--quiet printed something or wrote no image:"
  cat "$out/cli-quiet.out" "$out/cli-quiet.err"
  status=1
fi
# Two quads in one plane: the scene loader warns of the flicker (tandem/Scene.h coplanarOverlaps).
cat >"$out/cli-warns.json" <<'EOF'
{
  "meshes": { "quad": { "primitive": "plane", "size": 2 } },
  "materials": { "grey": { "kd": 0.5 } },
  "lights": [ { "type": "directional", "direction": [0, -1, 0] } ],
  "instances": [ { "mesh": "quad", "material": "grey" }, { "mesh": "quad", "material": "grey" } ],
  "camera": { "position": [0, 3, 3], "target": [0, 0, 0] }
}
EOF
"$render" "$out/cli-warns.json" --size 32x18 -o "$out/cli-warns.png" >"$out/cli-warns.out" 2>"$out/cli-warns.err" || exit 1
if ! grep -q '^tandem warning: ' "$out/cli-warns.err"; then
  echo "the coplanar quads' scene printed no warning (the --quiet check below would prove nothing):"
  cat "$out/cli-warns.err"
  status=1
fi
"$render" "$out/cli-warns.json" --size 32x18 --quiet -o "$out/cli-warns.png" >"$out/cli-warns.out" \
  2>"$out/cli-warns.err" || exit 1
if [ -s "$out/cli-warns.out" ] || [ -s "$out/cli-warns.err" ]; then
  echo "--quiet printed a warning:"
  cat "$out/cli-warns.out" "$out/cli-warns.err"
  status=1
fi
"$render" --size 64x36 -o "$out/cli-short.png" >"$out/cli-short.out" 2>"$out/cli-short.err" || exit 1
if [ -s "$out/cli-short.err" ]; then
  echo "a render under the 2 s default threshold printed progress:"
  cat "$out/cli-short.err"
  status=1
fi
exit $status
