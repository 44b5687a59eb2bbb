#!/bin/sh
# Redraws the pictures of the README and docs/reference.md from the commands they give, so that
# each picture is what its command produces today:
#   docs/mixed.png          the README's picture (its quick-start command)
#   docs/circles.png, docs/ellipses.png, docs/squircles.png, docs/mixed-contacts.png
#   docs/mixed.gif          the presets, as docs/reference.md says they are drawn
#   docs/pour-1000.png      the 1,000-grain pour at rest
#   docs/silo.png           the silo of docs/silo.md, 6 s into its discharge (needs python3)
# Usage: scripts/redraw-docs.sh   (from anywhere; builds the release binary first; about half a
# minute on two cores once built). CARGO_TARGET_DIR is honoured.
set -eu
cd "$(dirname "$0")/.."
cargo build --release --locked -p supergrain-cli
sg="${CARGO_TARGET_DIR:-target}/release/supergrain"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The README's quick start, written into docs/.
"$sg" run --preset mixed --until-rest --png docs/mixed.png --width 500 --dump "$tmp/mixed.json" --quiet

# docs/reference.md, `supergrain render`: each preset to rest, drawn 500 wide.
for name in circles ellipses squircles; do
    "$sg" run --preset "$name" --until-rest --dump "$tmp/$name.json" --quiet
    "$sg" render "$tmp/$name.json" -o "docs/$name.png" --width 500 --colour palette
done
"$sg" render "$tmp/mixed.json" -o docs/mixed-contacts.png --width 500 --boxes --contacts
"$sg" run --preset mixed --until-rest --gif docs/mixed.gif --every 25 --width 300 --quiet

# The 1,000-grain pour at rest, coloured by group.
"$sg" run examples/scenes/pour-1000.toml --until-rest --steps 20000 --dump "$tmp/pour.json" --quiet
"$sg" render "$tmp/pour.json" -o docs/pour-1000.png --colour group --width 900

# The silo of docs/silo.md (scripts/beverloo.py's, an orifice 8 grains wide), 6 s in.
python3 scripts/beverloo.py --scene-only 8 --out "$tmp" > /dev/null
"$sg" run "$tmp/silo8.toml" --steps 1200 --dump "$tmp/silo.json" --quiet
"$sg" render "$tmp/silo.json" -o docs/silo.png --width 240 --colour palette

# The mixer of docs/reference.md (a driven paddle).
"$sg" run examples/scenes/mixer.toml --png docs/mixer.png --colour group --width 500 --quiet

# The hopper of docs/reference.md#boundaries.
"$sg" run examples/scenes/hopper.toml --png docs/hopper.png --quiet

# The tumbler of docs/peers.md, 12 s in.
"$sg" run examples/scenes/tumbler.toml --png docs/tumbler.png --width 600 --quiet

# The silo of stars and the chute of docs/silo.md, with their plots.
"$sg" run examples/scenes/star-silo.toml --steps 1200 --png docs/star-silo.png --width 400 --measures "$tmp/stars" --quiet
cp "$tmp/stars/discharge.png" docs/star-silo-discharge.png
"$sg" run examples/scenes/chute.toml --png docs/chute.png --width 700 --measures "$tmp/chute" --quiet
cp "$tmp/chute/profile.png" docs/chute-profile.png

# The drum of docs/drum.md, 12 s in.
"$sg" run examples/scenes/drum.toml --png docs/drum.png --quiet

echo "redrawn: docs/star-silo.png docs/star-silo-discharge.png docs/chute.png docs/chute-profile.png docs/tumbler.png docs/drum.png docs/hopper.png docs/silo.png docs/mixed.png docs/circles.png docs/ellipses.png docs/squircles.png docs/mixed-contacts.png docs/mixed.gif docs/pour-1000.png"
